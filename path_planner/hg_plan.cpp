// hg-plan: plan a grind path from an outline JSON file (as hg-outline writes it) and write path.json.
// The same pipeline and parameters as hg-path-planner, without the bus.
#include <cstdio>
#include <fstream>
#include <iostream>
#include <map>
#include <optional>
#include <sstream>

#include "path_planner/io.hpp"
#include "runtime/config.hpp"

using namespace hg::path_planner;

namespace {

void usage(std::FILE* f) {
  std::fprintf(f,
               "usage: hg-plan [options] OUTLINE.json\n"
               "Plans a grind path from an outline JSON file (hg-outline's format: loops [{hole, points [[x, y], ...]}],\n"
               "plane {origin, normal, u, v} optional, frame optional) and writes a path file (docs/path_file.md:\n"
               "{\"job_id\", \"frame\", \"outline_seq\", \"tool_radius\", \"tilt\", \"flipped\", \"waypoints\": [{position,\n"
               "orientation [w, x, y, z], speed, kind, loop}], coverage {tolerance, unreached_length, loops [{loop, hole,\n"
               "length, reached_fraction, unreached [{start, length, concave, points}]}]}}) in the robot base frame, metres.\n"
               "Loops without a plane (a 2-D outline) are placed on the plane given by plane_* below (camera frame).\n"
               "Frames: the outline file's \"frame\" says which frame its plane is in: camera (camera_to_base is\n"
               "applied), robot_base (the base_frame: used as it is) or cloud (hg-outline: the input cloud's own\n"
               "coordinates, taken as the camera frame). --outline_frame overrides it: a cloud in robot base\n"
               "coordinates plans with --outline_frame robot_base. The transform applied is printed on stderr.\n"
               "The start point is the loop point nearest to `home` (no robot is heard here).\n"
               "Prints a one-line summary on stderr. Exit status: 0 planned, 1 planning failed (reason on stderr),\n"
               "2 bad command line, config or input file.\n\n"
               "options:\n"
               "  -o, --output FILE   write the path here (default: standard output)\n"
               "  --job-id ID         job id written into the path (default: hg-plan)\n"
               "  --config FILE       YAML config (the same keys as hg-path-planner; see config/path_planner.yaml)\n"
               "  --help              this text\n"
               "  --NAME VALUE        any planner parameter (command line > config > default):\n");
  for (const auto& p : planner_params())
    std::fprintf(f, "    --%-22s %s%s%s\n", p.name.c_str(), p.help.c_str(), p.default_value.empty() ? "" : " [default ",
                 p.default_value.empty() ? "" : (p.default_value + "]").c_str());
}

}  // namespace

int main(int argc, char** argv) {
  std::map<std::string, std::string> cli;
  std::string input, output, job_id = "hg-plan", config_path;
  const auto params = planner_params();
  auto find = [&](const std::string& n) -> const hg::runtime::Param* {
    for (const auto& p : params)
      if (p.name == n) return &p;
    return nullptr;
  };
  for (int i = 1; i < argc; ++i) {
    const std::string a = argv[i];
    auto value = [&]() -> std::string {
      if (i + 1 >= argc) {
        std::fprintf(stderr, "hg-plan: %s needs a value\n", a.c_str());
        std::exit(2);
      }
      return argv[++i];
    };
    if (a == "--help" || a == "-h") {
      usage(stdout);
      return 0;
    } else if (a == "-o" || a == "--output") {
      output = value();
    } else if (a == "--job-id") {
      job_id = value();
    } else if (a == "--config") {
      config_path = value();
    } else if (a.rfind("--", 0) == 0) {
      const hg::runtime::Param* p = find(a.substr(2));
      if (!p) {
        std::fprintf(stderr, "hg-plan: unknown option %s (see --help)\n", a.c_str());
        return 2;
      }
      cli[p->name] = p->is_flag ? "true" : value();
    } else if (input.empty()) {
      input = a;
    } else {
      std::fprintf(stderr, "hg-plan: more than one input file (%s)\n", a.c_str());
      return 2;
    }
  }
  if (input.empty()) {
    usage(stderr);
    return 2;
  }
  PlannerConfig cfg;
  OutlineInput outline;
  OutlineFrame frame;
  try {
    hg::runtime::Config config = config_path.empty() ? hg::runtime::Config() : hg::runtime::Config::load(config_path);
    const ParamLookup lookup = lookup_from(cli, config);
    cfg = config_from(lookup);
    std::ifstream f(input, std::ios::binary);
    if (!f) throw std::runtime_error("cannot open");
    std::stringstream ss;
    ss << f.rdbuf();
    outline = read_outline_json(ss.str(), cfg.default_plane);
    frame = resolve_outline_frame(outline.frame, lookup.text("outline_frame"), cfg);
  } catch (const std::exception& e) {
    std::fprintf(stderr, "hg-plan: %s: %s\n", input.c_str(), e.what());
    return 2;
  }
  if (!outline.plane_given && frame.used == cfg.base_frame) {
    // The default plane is a camera-frame plane: put it where the calibration says, in the base frame.
    const Eigen::Isometry3d& T = cfg.camera_to_base;
    outline.plane = {T * outline.plane.origin, T.linear() * outline.plane.u, T.linear() * outline.plane.v,
                     T.linear() * outline.plane.normal};
    std::fprintf(stderr, "hg-plan: the outline has no plane: the configured plane_* (camera frame) is used\n");
  }
  cfg.camera_to_base = frame.camera_to_base;
  std::fprintf(stderr, "hg-plan: outline plane in frame '%s' (the file says %s); camera-to-base applied: %s\n",
               frame.used.c_str(), frame.declared.c_str(),
               frame.used == cfg.base_frame ? "none (identity)" : matrix_text(cfg.camera_to_base).c_str());
  if (!frame.note.empty()) std::fprintf(stderr, "hg-plan: note: %s\n", frame.note.c_str());
  const PlanResult r = plan(outline, cfg.defaults, cfg, std::nullopt);
  for (const std::string& w : r.warnings) std::fprintf(stderr, "hg-plan: warning: %s\n", w.c_str());
  if (!r.ok) {
    std::fprintf(stderr, "hg-plan: planning failed: %s\n", r.reason.c_str());
    if (r.reason.find("workspace box") != std::string::npos && frame.used != cfg.base_frame)
      std::fprintf(stderr, "hg-plan: is the outline in robot base coordinates? then give --outline_frame %s\n",
                   cfg.base_frame.c_str());
    return 1;
  }
  const std::string text = path_json(job_id, cfg.base_frame, r, outline.seq).dump(1) + "\n";
  if (output.empty()) {
    std::cout << text;
  } else {
    std::ofstream o(output, std::ios::binary);
    o << text;
    if (!o) {
      std::fprintf(stderr, "hg-plan: cannot write %s\n", output.c_str());
      return 2;
    }
  }
  std::fprintf(stderr, "hg-plan: %zu waypoints, %d loops, %d speeds lowered at corners, pitch %.3f mm, planned in %.2f ms\n",
               r.path.size(), r.loops_planned, r.slowed, r.pitch * 1e3, r.seconds * 1e3);
  return 0;
}
