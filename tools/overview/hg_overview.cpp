// hg-overview: turns a recorded pipeline run into out/: outline.json, path.json, overview.png and
// summary.json, and prints the stage timings and the job's final state.
#include <cstdio>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <sstream>
#include <string>

#include "outline_io/outline_writers.hpp"
#include "runtime/config.hpp"
#include "path_planner/io.hpp"
#include "path_file/path_file.hpp"
#include "tools/overview/overview.hpp"
#include "path_planner/path_planner.hpp"
#include "runtime/node.hpp"
#include "runtime/params.hpp"

namespace {

const char* kUsage = R"(usage: hg-overview LOG.lcmlog --out DIR [--job-id J] [--cell FILE] [--planner-config FILE]
                   [--NAME VALUE ...] [--planner-args ARG ...]
Reads a recorded run (tools/record) and writes, for one job (default: the last START request):
  DIR/outline.json   the outline the job was planned on, in hg-outline's JSON schema ("frame": "camera")
  DIR/path.json      the grind path, in the path file schema (docs/path_file.md)
  DIR/overview.png   top view on the plate in the station's colours: cloud, outline (holes light blue), path
                     by kind (grind orange), edge out of the tool's reach (red: the planner's coverage check
                     redone with the planner's settings below), scale bar, frames, legend
  DIR/summary.json   stage timings (ms) and every job status
The picture brings the path (robot base frame) back onto the plate with the camera-to-base calibration of
the cell file the planner used; give the cell and the planner's settings as the run gave them: --cell,
--planner-config, any planner parameter (--NAME VALUE, e.g. --pixel-pitch 0.001342), or the planner's own
command line after --planner-args (tools/run.sh passes the pipeline file's).
The calibration used is printed; a grind path more than 5 mm off the outline's plane is warned about (on
stderr and in the picture): the settings given are not the ones the planner ran with.
Exit status: 0 the job is DONE, 1 it is not (or not in the log), 2 bad usage or unreadable log.

)";

// hg-overview's own options, then every planner parameter (--NAME VALUE, as hg-plan takes them), then
// --planner-args: the rest of the command line is the planner process's own.
std::vector<hg::runtime::Param> overview_params() {
  using namespace hg::runtime;
  std::vector<Param> params = {
      positional(text_param("log", "", "the recorded run (tools/record), an LCM log")),
      text_param("out", "", "the folder to write (required)"),
      text_param("job-id", "", "the job to draw (default: the last START request)"),
      text_param("planner-config", "", "the planner's config file [default: config/path_planner.yaml]")};
  set_value_names(params, {{"log", "LOG.lcmlog"}, {"out", "DIR"}, {"job-id", "J"}, {"planner-config", "FILE"}});
  for (Param& p : hg::path_planner::planner_params()) params.push_back(std::move(p));
  params.push_back(rest_param("planner-args",
                              "the rest of the command line is the planner's own (as in the pipeline file, without the "
                              "program), parsed as hg-path-planner parses it; its --config wins over --planner-config "
                              "and its parameters over the --NAME VALUE above"));
  return params;
}

// The planner's parameters as the run gave them: --planner-args parsed with hg-path-planner's own declarations
// (an option it does not know is an error, as it would be for the planner), its config file (else
// --planner-config), and the planner parameters given to hg-overview (command line or its --config) that
// --planner-args does not give.
hg::runtime::Params planner_settings(const hg::runtime::Params& p) {
  hg::runtime::Params planner(hg::runtime::process_params(hg::path_planner::process_info().params));
  std::vector<std::string> args = p.rest("planner-args");
  args.insert(args.begin(), "hg-path-planner");
  std::vector<const char*> argv;
  for (const std::string& a : args) argv.push_back(a.c_str());
  try {
    if (planner.parse(int(argv.size()), argv.data()) != hg::runtime::Params::Action::Run)
      throw hg::runtime::ConfigError("command line: --help and --version are hg-overview's own");
  } catch (const hg::runtime::ConfigError& e) {
    throw hg::runtime::ConfigError(std::string("--planner-args: ") + e.what());
  }
  if (planner.config().empty())
    planner.use_config(hg::runtime::Config::load(
        p.given("planner-config") ? p.text("planner-config") : hg::runtime::default_file("config/path_planner.yaml")));
  for (const hg::runtime::Param& d : hg::path_planner::planner_params())
    if (d.moved_to.empty() && p.given(d.name) && planner.origin(d.name) != "command line")
      planner.set(d.name, p.text(d.name));
  return planner;
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

int run(const hg::runtime::Params& p) {
  const std::string log_path = p.text("log"), out_dir = p.text("out"), job_id = p.text("job-id");
  try {
    // Camera -> base from the cell file, through the planner's own configuration code, as the run gave them.
    const hg::runtime::Params planner_params = planner_settings(p);
    auto planner = hg::path_planner::config_from(hg::path_planner::lookup_from(planner_params));
    auto log = hg::overview::read_run_log(log_path);
    auto job = hg::overview::trace_job(log, job_id);
    if (job.job_id.empty()) {
      std::fprintf(stderr, "hg-overview: %s: no job request in the log (%zu events)\n", log_path.c_str(), log.events);
      return 1;
    }
    if (log.undecodable > 0)  // e.g. a log recorded before a change to a message type: its fingerprint differs
      std::fprintf(stderr,
                   "hg-overview: warning: %s: %zu messages on the cloud, outline, path, request or status channel do "
                   "not decode with this build's message types (recorded by another version?): left out\n",
                   log_path.c_str(), log.undecodable);
    // Eye-in-hand: the outline's flange pose at capture, as the planner placed it.
    if (const std::string why = job.outline ? hg::path_planner::place_outline(job.outline->msg, planner) : "";
        !why.empty())
      std::fprintf(stderr, "hg-overview: warning: %s\n", why.c_str());
    const Eigen::Isometry3d camera_to_base = planner.camera_to_base;
    std::printf("camera-to-base calibration (from the cell file %s): %s\n", planner.cell_file.c_str(),
                hg::path_planner::matrix_text(camera_to_base).c_str());
    std::filesystem::create_directories(out_dir);
    hg::outline_io::StagedFiles files;
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

}  // namespace

int main(int argc, char** argv) {
  hg::runtime::Params p(overview_params());
  if (const int rc = hg::runtime::parse_tool(p, argc, argv, "hg-overview", hg::runtime::usage_with(kUsage)); rc >= 0)
    return rc;
  if (!p.given("log") || p.text("out").empty()) {
    std::fprintf(stderr, "hg-overview: command line: give LOG.lcmlog and --out DIR (see --help)\n");
    return 2;
  }
  return run(p);
}
