#include "camera_bridge/source_registry.hpp"

namespace hg::camera_bridge {

// camera_sources.inc is written by camera_bridge/CMakeLists.txt from HG_CAMERA_SOURCES: one line per source,
// HG_CAMERA_SOURCE(name) when its folder built its library, HG_CAMERA_SOURCE_MISSING(name, "why") when not.
#define HG_CAMERA_SOURCE(name) SourceEntry name##_source();
#define HG_CAMERA_SOURCE_MISSING(name, why)
#include "camera_sources.inc"
#undef HG_CAMERA_SOURCE
#undef HG_CAMERA_SOURCE_MISSING

namespace {

SourceEntry missing_source(std::string name, std::string why) {
  SourceEntry e;
  e.name = std::move(name);
  e.missing = std::move(why);
  return e;
}

std::vector<SourceEntry> all_sources() {
  std::vector<SourceEntry> v{synthetic_source(), files_source()};
#define HG_CAMERA_SOURCE(name) v.push_back(name##_source());
#define HG_CAMERA_SOURCE_MISSING(name, why) v.push_back(missing_source(#name, why));
#include "camera_sources.inc"
#undef HG_CAMERA_SOURCE
#undef HG_CAMERA_SOURCE_MISSING
  return v;
}

std::string joined(const std::vector<std::string>& names, const std::string& sep, const std::string& last) {
  std::string s;
  for (std::size_t i = 0; i < names.size(); ++i) s += (i == 0 ? "" : i + 1 == names.size() ? last : sep) + names[i];
  return s;
}

// `text` wrapped at 110 columns after a 2-column indent, every line after the first indented by `indent`.
std::string wrapped(const std::string& text, const std::string& indent) {
  std::string out, line;
  std::size_t start = 0;
  while (start < text.size()) {
    std::size_t end = text.find(' ', start);
    if (end == std::string::npos) end = text.size();
    const std::string word = text.substr(start, end - start);
    if (!line.empty() && line.size() + 3 + word.size() > 110) out += line + "\n", line = indent;
    line += (line.empty() || line == indent ? "" : " ") + word;
    start = end + 1;
  }
  return out + line + "\n";
}

}  // namespace

const std::vector<SourceEntry>& registered_sources() {
  static const std::vector<SourceEntry> sources = all_sources();
  return sources;
}

std::vector<std::string> source_names() {
  std::vector<std::string> names;
  for (const SourceEntry& e : registered_sources()) names.push_back(e.name);
  return names;
}

std::vector<runtime::Param> source_params() {
  std::vector<runtime::Param> out;
  for (const SourceEntry& e : registered_sources())
    for (runtime::Param p : e.params) {
      p.name = e.name + "." + p.name;
      p.help = e.name + ": " + p.help;
      out.push_back(std::move(p));
    }
  return out;
}

std::string sources_help(const std::vector<SourceEntry>& sources) {
  std::string s = "Sources (--source; the parameters of each in its own section, --NAME.KEY or NAME: {KEY: ...}):\n";
  for (const SourceEntry& e : sources)
    s += "  " + wrapped(e.name + ": " + (e.missing.empty() ? e.help : "NOT in this build: " + e.missing), "    ");
  return s;
}

std::unique_ptr<camera::DepthSource> make_source(const runtime::Params& params, bool job_trigger, double rate,
                                                 const std::vector<SourceEntry>& sources) {
  const std::string name = params.text("source");
  std::vector<std::string> names;
  for (const SourceEntry& e : sources) {
    names.push_back(e.name);
    if (e.name != name) continue;
    if (!e.missing.empty()) throw params.error("source", "'" + name + "' is not available in this build: " + e.missing);
    return e.make(SourceContext(params, e.name, job_trigger, rate));
  }
  throw params.error("source", "must be " + joined(names, ", ", " or ") + ", not '" + name + "'");
}

}  // namespace hg::camera_bridge
