#include "station/history.hpp"

#include <algorithm>
#include <deque>
#include <fstream>
#include <sstream>

namespace hg::station {

namespace fs = std::filesystem;
using Json = nlohmann::json;

namespace {

constexpr std::uintmax_t kMaxJobJson = 1 << 20;
constexpr std::size_t kMaxDirs = 20000, kEventLines = 2000;

std::optional<Json> read_json(const fs::path& file) {
  std::error_code ec;
  if (!fs::is_regular_file(file, ec) || fs::file_size(file, ec) > kMaxJobJson) return std::nullopt;
  std::ifstream in(file, std::ios::binary);
  Json j = Json::parse(in, nullptr, /*allow_exceptions*/ false);
  if (j.is_discarded() || !j.is_object()) return std::nullopt;
  return j;
}

bool plain_id(const std::string& id) {
  if (id.empty() || id.size() > 120 || id[0] == '.') return false;
  return std::all_of(id.begin(), id.end(), [](char c) {
    return std::isalnum(static_cast<unsigned char>(c)) || c == '_' || c == '-' || c == '.';
  });
}

std::string text_of(const Json& j, const char* key) {
  auto it = j.find(key);
  return it != j.end() && it->is_string() ? it->get<std::string>() : std::string();
}

bool matches(const Json& rec, const HistoryFilter& f) {
  const std::string state =
      rec.contains("interrupted") && !rec.value("final", false) ? "interrupted" : text_of(rec, "state");
  if (!f.state.empty() && f.state != state && f.state != text_of(rec, "state")) return false;
  if (!f.part.empty() && text_of(rec, "part_id").find(f.part) == std::string::npos) return false;
  const std::string day = text_of(rec, "requested").substr(0, 10);
  if (!f.from.empty() && day < f.from) return false;
  if (!f.to.empty() && day > f.to) return false;
  return true;
}

Json read_events(const fs::path& file) {
  std::ifstream in(file, std::ios::binary);
  std::deque<std::string> lines;
  std::string line;
  while (std::getline(in, line)) {
    if (line.size() > (1 << 16)) continue;
    lines.push_back(std::move(line));
    if (lines.size() > kEventLines) lines.pop_front();
  }
  Json out = Json::array();
  for (const std::string& l : lines) {
    Json j = Json::parse(l, nullptr, false);
    if (!j.is_discarded()) out.push_back(std::move(j));
  }
  return out;
}

}  // namespace

bool History::downloadable_name(const std::string& name) {
  static const char* fixed[] = {"path.json", "outline.json", "job.json", "events.jsonl"};
  for (const char* f : fixed)
    if (name == f) return true;
  if (name.empty() || name.size() > 100 || name[0] == '.') return false;
  for (char c : name)
    if (!(std::isalnum(static_cast<unsigned char>(c)) || c == '_' || c == '-' || c == '.')) return false;
  auto ends = [&](const std::string& s) { return name.size() > s.size() && name.ends_with(s); };
  return ends(".script") || ends(".png");
}

std::optional<fs::path> History::dir_of(const std::string& job_id) const {
  if (!enabled() || job_id.empty()) return std::nullopt;
  if (plain_id(job_id)) {  // the recorder's folder name of an id of safe characters is the id itself
    auto rec = read_json(dir_ / job_id / "job.json");
    if (rec && text_of(*rec, "job_id") == job_id) return dir_ / job_id;
  }
  std::error_code ec;
  std::size_t seen = 0;
  for (fs::directory_iterator it(dir_, ec), end; !ec && it != end && seen < kMaxDirs; it.increment(ec), ++seen) {
    auto rec = read_json(it->path() / "job.json");
    if (rec && text_of(*rec, "job_id") == job_id) return it->path();
  }
  return std::nullopt;
}

Json History::list(const HistoryFilter& filter) const {
  std::vector<Json> rows;
  std::error_code ec;
  std::size_t seen = 0;
  if (enabled())
    for (fs::directory_iterator it(dir_, ec), end; !ec && it != end && seen < kMaxDirs; it.increment(ec), ++seen) {
      auto rec = read_json(it->path() / "job.json");
      if (!rec || !matches(*rec, filter)) continue;
      Json row = {{"job_id", text_of(*rec, "job_id")},       {"part_id", text_of(*rec, "part_id")},
                  {"state", text_of(*rec, "state")},         {"final", rec->value("final", false)},
                  {"requested", text_of(*rec, "requested")}, {"ended", text_of(*rec, "ended")},
                  {"reason", text_of(*rec, "reason")},       {"message", text_of(*rec, "message")}};
      if (rec->contains("interrupted")) row["interrupted"] = (*rec)["interrupted"];
      rows.push_back(std::move(row));
    }
  std::sort(rows.begin(), rows.end(), [](const Json& a, const Json& b) { return a["requested"] > b["requested"]; });
  if (rows.size() > filter.limit) rows.resize(filter.limit);
  return rows;
}

std::optional<Json> History::record(const std::string& job_id) const {
  auto dir = dir_of(job_id);
  if (!dir) return std::nullopt;
  auto rec = read_json(*dir / "job.json");
  if (!rec) return std::nullopt;
  Json files = Json::array();
  std::error_code ec;
  for (fs::directory_iterator it(*dir, ec), end; !ec && it != end; it.increment(ec)) {
    const std::string name = it->path().filename().string();
    if (downloadable_name(name) && it->is_regular_file(ec))
      files.push_back({{"name", name}, {"size", it->file_size(ec)}});
  }
  std::sort(files.begin(), files.end(), [](const Json& a, const Json& b) { return a["name"] < b["name"]; });
  return Json{{"job", *rec}, {"events", read_events(*dir / "events.jsonl")}, {"files", files}};
}

std::optional<fs::path> History::file(const std::string& job_id, const std::string& name) const {
  if (!downloadable_name(name)) return std::nullopt;
  auto dir = dir_of(job_id);
  if (!dir) return std::nullopt;
  std::error_code ec;
  const fs::path f = *dir / name;
  if (fs::is_symlink(f, ec) || !fs::is_regular_file(f, ec)) return std::nullopt;
  return f;
}

}  // namespace hg::station
