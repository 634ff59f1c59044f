// The job history as the recorder keeps it (docs/job_recorder.md): DIR/NAME/job.json, events.jsonl,
// outline.json, path.json. Read only; every file read is bounded in size and a broken one is skipped.
#pragma once

#include <filesystem>
#include <nlohmann/json.hpp>
#include <optional>
#include <string>

namespace hg::station {

struct HistoryFilter {
  std::string state;  // job.json "state" (or "interrupted"), exact; empty: any
  std::string part;   // part_id contains this; empty: any
  std::string from;   // requested on or after this date (YYYY-MM-DD); empty: any
  std::string to;     // requested on or before this date
  std::size_t limit = 500;
};

class History {
 public:
  explicit History(std::filesystem::path dir) : dir_(std::move(dir)) {}
  bool enabled() const { return !dir_.empty(); }
  // Newest first.
  nlohmann::json list(const HistoryFilter& filter) const;
  // job.json, events (the last 2000 lines of events.jsonl) and the files there; nullopt when not recorded.
  std::optional<nlohmann::json> record(const std::string& job_id) const;
  // A downloadable file of the job's record: path.json, outline.json, job.json, events.jsonl, or a URScript
  // (*.script) or picture (*.png) the record holds. nullopt when the name is not one of those or absent.
  std::optional<std::filesystem::path> file(const std::string& job_id, const std::string& name) const;

  static bool downloadable_name(const std::string& name);

 private:
  std::optional<std::filesystem::path> dir_of(const std::string& job_id) const;
  std::filesystem::path dir_;
};

}  // namespace hg::station
