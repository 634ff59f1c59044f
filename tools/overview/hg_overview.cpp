// hg-overview: turns a recorded pipeline run into out/: outline.json, path.json, overview.png and
// summary.json, and prints the stage timings and the job's final state.
#include <cstdio>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <map>
#include <sstream>
#include <string>

#include "outline_core/io/outline_writers.hpp"
#include "path_planner/io.hpp"
#include "tools/overview/overview.hpp"

namespace {

const char* kUsage = R"(usage: hg-overview LOG.lcmlog --out DIR [--job-id J] [--planner-config FILE]
Reads a recorded run (tools/record) and writes, for one job (default: the last START request):
  DIR/outline.json   the outline the job was planned on, in hg-outline's JSON schema
  DIR/path.json      {"job_id", "frame", "waypoints": [{"position", "orientation" [w,x,y,z], "speed", "kind"}]}
  DIR/overview.png   top view on the plate: cloud, outline (holes red), grind path, edge out of the tool's
                     reach (magenta: the planner's coverage check redone with --planner-config), legend
  DIR/summary.json   stage timings (ms) and every job status
--planner-config: the path planner's config, for the camera-to-base calibration that brings the path back
onto the plate in the picture and for the coverage check [default: config/path_planner.yaml].
Exit status: 0 the job is DONE, 1 it is not (or not in the log), 2 bad usage or unreadable log.
)";

std::vector<double> parse_list(const std::string& text) {
  std::vector<double> out;
  std::stringstream ss(text);
  std::string item;
  while (std::getline(ss, item, ',')) out.push_back(std::stod(item));
  return out;
}

}  // namespace

int main(int argc, char** argv) {
  std::string log_path, out_dir, job_id, planner_config = "config/path_planner.yaml";
  for (int i = 1; i < argc; ++i) {
    std::string a = argv[i];
    auto value = [&]() -> std::string {
      if (i + 1 >= argc) {
        std::fprintf(stderr, "hg-overview: %s needs a value\n", a.c_str());
        std::exit(2);
      }
      return argv[++i];
    };
    if (a == "-h" || a == "--help") {
      std::fputs(kUsage, stdout);
      return 0;
    } else if (a == "--out") out_dir = value();
    else if (a == "--job-id") job_id = value();
    else if (a == "--planner-config") planner_config = value();
    else if (!a.empty() && a[0] == '-') {
      std::fprintf(stderr, "hg-overview: unknown option %s\n%s", a.c_str(), kUsage);
      return 2;
    } else log_path = a;
  }
  if (log_path.empty() || out_dir.empty()) {
    std::fputs(kUsage, stderr);
    return 2;
  }
  try {
    // Camera -> base from the planner's own configuration code, so the picture uses what planning used.
    hg::runtime::Config cfg = hg::runtime::Config::load(planner_config);
    std::map<std::string, std::string> defaults;
    for (const auto& p : hg::path_planner::planner_params()) defaults[p.name] = p.default_value;
    hg::path_planner::ParamLookup lookup{
        [&](const std::string& k) { return cfg.get_string(k).value_or(defaults[k]); },
        [&](const std::string& k) {
          if (auto v = cfg.get_doubles(k)) return *v;
          return parse_list(defaults[k]);
        }};
    const hg::path_planner::PlannerConfig planner = hg::path_planner::config_from(lookup);
    auto camera_to_base = planner.camera_to_base;

    auto log = hg::overview::read_run_log(log_path);
    auto job = hg::overview::trace_job(log, job_id);
    if (job.job_id.empty()) {
      std::fprintf(stderr, "hg-overview: %s: no job request in the log (%zu events)\n", log_path.c_str(), log.events);
      return 1;
    }
    std::filesystem::create_directories(out_dir);
    hg::outline::io::StagedFiles files;
    if (job.outline) files.stage(out_dir + "/outline.json", hg::overview::outline_json(job).dump(1) + "\n");
    if (job.path) files.stage(out_dir + "/path.json", hg::overview::path_json(job.path->msg).dump(1) + "\n");
    auto png = hg::overview::overview_png(job, camera_to_base, &planner);
    files.stage(out_dir + "/overview.png", png.data(), png.size());
    auto summary = hg::overview::summary_json(job);
    files.stage(out_dir + "/summary.json", summary.dump(1) + "\n");
    files.commit();

    std::printf("job %s: %s%s%s\n", job.job_id.c_str(), summary["final_state"].get<std::string>().c_str(),
                job.final_status && !job.final_status->msg.message.empty() ? " - " : "",
                job.final_status ? job.final_status->msg.message.c_str() : "");
    if (summary.contains("cloud_points"))
      std::printf("  plate cloud   %d points\n", summary["cloud_points"].get<int>());
    if (summary.contains("outline_loops"))
      std::printf("  outline       %d loops (%d holes)\n", summary["outline_loops"].get<int>(), summary["outline_holes"].get<int>());
    if (summary.contains("path_waypoints"))
      std::printf("  grind path    %d waypoints\n", summary["path_waypoints"].get<int>());
    for (auto& [k, v] : summary["stages"].items()) std::printf("  %-22s %9.1f ms\n", k.c_str(), v.get<double>());
    std::printf("wrote %s/{%s%soverview.png, summary.json}\n", out_dir.c_str(), job.outline ? "outline.json, " : "",
                job.path ? "path.json, " : "");
    return summary["final_state"] == "DONE" ? 0 : 1;
  } catch (const std::exception& e) {
    std::fprintf(stderr, "hg-overview: %s\n", e.what());
    return 2;
  }
}
