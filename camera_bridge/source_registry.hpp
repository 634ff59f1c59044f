// The camera sources of hg-camera-bridge, as a list. Each source registers itself: its name (the value of
// --source), a line of help, its parameters in a section of their own (`device` of `genicam` is
// --genicam.device on the command line, `genicam: {device: ...}` in a config file) and a factory. The bridge
// reads this list for its --help, its parameter declarations and check, and the error for an unknown source.
//
// Adding a source: one folder camera_bridge/NAME/ whose CMakeLists.txt calls hg_camera_source(NAME LIBRARY
// lib) (or hg_camera_source(NAME MISSING "why") when its dependency is absent) and whose library defines
// `SourceEntry NAME_source()`; NAME in HG_CAMERA_SOURCES (camera_bridge/CMakeLists.txt, the registration
// line); its tests in tests/camera/NAME/. The built-in sources (synthetic, files) are in sources.cpp.
#pragma once

#include <functional>
#include <memory>
#include <string>
#include <vector>

#include "camera_types/depth_source.hpp"
#include "runtime/params.hpp"

namespace hg::camera_bridge {

// What a factory reads: its own section of the parameters (by short key) and the bridge's capture mode.
class SourceContext {
 public:
  SourceContext(const runtime::Params& params, std::string section, bool job_trigger, double rate)
      : job_trigger(job_trigger), rate(rate), params_(params), section_(std::move(section)) {}
  std::string key(const std::string& k) const { return section_ + "." + k; }  // "genicam.device"
  std::string text(const std::string& k) const { return params_.text(key(k)); }
  double number(const std::string& k) const { return params_.number(key(k)); }
  std::int64_t integer(const std::string& k) const { return params_.integer(key(k)); }
  bool flag(const std::string& k) const { return params_.flag(key(k)); }
  bool given(const std::string& k) const { return params_.given(key(k)); }
  // A ConfigError naming the key and where its value came from.
  runtime::ConfigError error(const std::string& k, const std::string& what) const {
    return params_.error(key(k), what);
  }

  const bool job_trigger;  // --trigger job: one capture per job (a software trigger, a frame rendered on request)
  const double rate;       // frames per second at most for a free-running source (0: as fast as asked)

 private:
  const runtime::Params& params_;
  std::string section_;
};

struct SourceEntry {
  std::string name;                    // --source NAME; the section of its parameters
  std::string help;                    // what it reads, for --help (one or a few sentences)
  std::vector<runtime::Param> params;  // declared with short names ("device"); the bridge prefixes the section
  // Builds the source; throws runtime::ConfigError on a bad value (SourceContext::error names the key).
  std::function<std::unique_ptr<camera::DepthSource>(const SourceContext&)> make;
  std::string missing;  // not in this build: why (configure time); then `make` is empty
};

// Every source, built-in ones first, then HG_CAMERA_SOURCES in their order; the missing ones included.
const std::vector<SourceEntry>& registered_sources();
std::vector<std::string> source_names();
// The parameters of every source, named SECTION.KEY, with the section named in their help.
std::vector<runtime::Param> source_params();
// The --help lines on the sources: one paragraph per source, "NOT in this build" and why for a missing one.
std::string sources_help(const std::vector<SourceEntry>& sources = registered_sources());
// The source --source names, from its section of `params`. Throws runtime::ConfigError: an unknown source
// (naming the choices), a source not in this build (saying why) or a bad parameter of the source.
std::unique_ptr<camera::DepthSource> make_source(const runtime::Params& params, bool job_trigger, double rate,
                                                 const std::vector<SourceEntry>& sources = registered_sources());

// The built-in sources (sources.cpp).
SourceEntry synthetic_source();
SourceEntry files_source();

}  // namespace hg::camera_bridge
