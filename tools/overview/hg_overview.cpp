// hg-overview: turns a recorded pipeline run into out/: outline.json, path.json, overview.png and
// summary.json, and prints the stage timings and the job's final state.
#include <cstdio>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <map>
#include <sstream>
#include <string>

#include "cloud_io/outline_writers.hpp"
#include "runtime/config.hpp"
#include "path_planner/io.hpp"
#include "runtime/path_file.hpp"
#include "tools/overview/overview.hpp"
#include "runtime/version.hpp"

namespace {

const char* kUsage = R"(usage: hg-overview LOG.lcmlog --out DIR [--job-id J] [--cell FILE] [--planner-config FILE]
                   [--NAME VALUE ...] [--planner-args ARG ...]
Reads a recorded run (tools/record) and writes, for one job (default: the last START request):
  DIR/outline.json   the outline the job was planned on, in hg-outline's JSON schema ("frame": "camera")
  DIR/path.json      the grind path, in the path file schema (docs/path_file.md)
  DIR/overview.png   top view on the plate: cloud, outline (holes red), grind path, edge out of the tool's
                     reach (magenta: the planner's coverage check redone with the planner's settings below),
                     scale bar, frames, legend
  DIR/summary.json   stage timings (ms) and every job status
The picture brings the path (robot base frame) back onto the plate with the camera-to-base calibration of
the cell file the planner used; give the cell and the planner's settings as the run gave them:
  --cell FILE            the cell file (docs/cell.md): calibration.camera-to-base [default: config/cell.yaml]
  --planner-config FILE  the planner's config file [default: config/path_planner.yaml]
  --NAME VALUE           any planner parameter (hg-plan --help lists them), e.g. --pixel-pitch 0.001342
  --planner-args ARG...  the rest of the command line is the planner's own (as in the pipeline file, without
                         the program): its --config, --cell and planner parameters are taken, other options
                         skipped
The calibration used is printed; a grind path more than 5 mm off the outline's plane is warned about (on
stderr and in the picture): the settings given are not the ones the planner ran with.
Exit status: 0 the job is DONE, 1 it is not (or not in the log), 2 bad usage or unreadable log.
)";

bool is_planner_param(const std::string& name) {
  for (const auto& p : hg::path_planner::planner_params())
    if (p.name == name) return true;
  return false;
}

// The planner's own command line: --config and planner parameters are kept, other options (the
// process's: --lcm-url, ...) skipped with their value.
void take_planner_args(int argc, char** argv, int first, std::string& config, std::map<std::string, std::string>& cli) {
  for (int i = first; i < argc; ++i) {
    const std::string a = argv[i];
    if (a.rfind("--", 0) != 0) continue;
    const bool has_value = i + 1 < argc && std::string(argv[i + 1]).rfind("--", 0) != 0;
    const std::string value = has_value ? argv[i + 1] : "true";
    if (a == "--config") config = value;
    else if (is_planner_param(a.substr(2)))
      cli[a.substr(2)] = value;
    if (has_value) ++i;
  }
}

// What the run did, as lines for a person: final state, sizes of cloud, outline and path, stage times.
void print_summary(const hg::overview::JobTrace& job, const nlohmann::ordered_json& summary,
                   const std::string& out_dir) {
  std::printf("job %s: %s%s%s\n", job.job_id.c_str(), summary["final_state"].get<std::string>().c_str(),
              job.final_status && !job.final_status->msg.message.empty() ? " - " : "",
              job.final_status ? job.final_status->msg.message.c_str() : "");
  if (summary.contains("cloud_points")) std::printf("  plate cloud   %d points\n", summary["cloud_points"].get<int>());
  if (summary.contains("outline_loops"))
    std::printf("  outline       %d loops (%d holes)\n", summary["outline_loops"].get<int>(),
                summary["outline_holes"].get<int>());
  if (summary.contains("path_waypoints"))
    std::printf("  grind path    %d waypoints\n", summary["path_waypoints"].get<int>());
  for (auto& [k, v] : summary["stages"].items()) std::printf("  %-22s %9.1f ms\n", k.c_str(), v.get<double>());
  std::printf("wrote %s/{%s%soverview.png, summary.json}\n", out_dir.c_str(), job.outline ? "outline.json, " : "",
              job.path ? "path.json, " : "");
}

}  // namespace

int main(int argc, char** argv) {
  if (hg::runtime::answer_version(argc, argv, "hg-overview")) return 0;
  std::string log_path, out_dir, job_id, planner_config = hg::runtime::default_file("config/path_planner.yaml");
  std::map<std::string, std::string> planner_cli;
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
    } else if (a == "--out")
      out_dir = value();
    else if (a == "--job-id")
      job_id = value();
    else if (a == "--planner-config")
      planner_config = value();
    else if (a == "--planner-args") {
      take_planner_args(argc, argv, i + 1, planner_config, planner_cli);
      break;
    } else if (a.rfind("--", 0) == 0 && is_planner_param(a.substr(2)))
      planner_cli[a.substr(2)] = value();
    else if (!a.empty() && a[0] == '-') {
      std::fprintf(stderr, "hg-overview: command line: unknown option %s (see --help)\n", a.c_str());
      return 2;
    } else
      log_path = a;
  }
  if (log_path.empty() || out_dir.empty()) {
    std::fprintf(stderr, "hg-overview: command line: give LOG.lcmlog and --out DIR (see --help)\n");
    return 2;
  }
  try {
    // Camera -> base from the cell file, through the planner's own configuration code, as the run gave them.
    const hg::runtime::Config cfg = hg::runtime::Config::load(planner_config);
    auto planner = hg::path_planner::config_from(hg::path_planner::lookup_from(planner_cli, cfg));
    auto log = hg::overview::read_run_log(log_path);
    auto job = hg::overview::trace_job(log, job_id);
    if (job.job_id.empty()) {
      std::fprintf(stderr, "hg-overview: %s: no job request in the log (%zu events)\n", log_path.c_str(), log.events);
      return 1;
    }
    // Eye-in-hand: the outline's flange pose at capture, as the planner placed it.
    if (const std::string why = job.outline ? hg::path_planner::place_outline(job.outline->msg, planner) : "";
        !why.empty())
      std::fprintf(stderr, "hg-overview: warning: %s\n", why.c_str());
    const Eigen::Isometry3d camera_to_base = planner.camera_to_base;
    std::printf("camera-to-base calibration (from the cell file %s): %s\n", planner.cell_file.c_str(),
                hg::path_planner::matrix_text(camera_to_base).c_str());
    std::filesystem::create_directories(out_dir);
    hg::outline::io::StagedFiles files;
    if (job.outline) files.stage(out_dir + "/outline.json", hg::overview::outline_json(job).dump(1) + "\n");
    if (job.path) files.stage(out_dir + "/path.json", hg::path_file::to_text(job.path->msg));
    const double off_plane = hg::overview::path_on_plate(job, camera_to_base).grind_height_median();
    if (off_plane > hg::overview::kOffPlaneWarning)
      std::fprintf(stderr,
                   "hg-overview: warning: the grind path lies %.1f mm off the outline's plane with this calibration: "
                   "the planner ran with another cell file or settings (give them: --cell, --planner-args)\n",
                   off_plane * 1e3);
    auto png = hg::overview::overview_png(job, camera_to_base, &planner);
    files.stage(out_dir + "/overview.png", png.data(), png.size());
    auto summary = hg::overview::summary_json(job);
    files.stage(out_dir + "/summary.json", summary.dump(1) + "\n");
    files.commit();

    print_summary(job, summary, out_dir);
    return summary["final_state"] == "DONE" ? 0 : 1;
  } catch (const std::exception& e) {
    std::fprintf(stderr, "hg-overview: %s\n", e.what());
    return 2;
  }
}
