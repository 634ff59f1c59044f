// hg-plan: plan a grind path from an outline JSON file (as hg-outline writes it) and write path.json.
// The same pipeline and parameters as hg-path-planner, without the bus.
#include <cstdio>
#include <fstream>
#include <iostream>
#include <map>
#include <optional>
#include <sstream>

#include "path_planner/io.hpp"
#include "runtime/params.hpp"

using namespace hg::path_planner;

namespace {

void usage(std::FILE* f, const hg::runtime::Params& params) {
  std::fprintf(
      f,
      "usage: hg-plan [options] OUTLINE.json\n"
      "Plans a grind path from an outline file (docs/outline_file.md, as hg-outline writes it: loops [{hole,\n"
      "points [[u, v], ...]}], plane {origin, normal, u, v}, frame and spacing optional) and writes a path file\n"
      "(docs/path_file.md:\n"
      "{\"job_id\", \"frame\", \"outline_seq\", \"tool_radius\", \"tilt\", \"flipped\", \"waypoints\": [{position,\n"
      "orientation [w, x, y, z], speed, kind, loop}], coverage {tolerance, unreached_length, loops [{loop, hole,\n"
      "length, reached_fraction, unreached [{start, length, concave, points}]}]}}) in the robot base frame, metres.\n"
      "Loops without a plane (a 2-D outline) are placed on the plane given by plane-* below in the camera frame,\n"
      "and on z = 0 in the base frame (--outline-frame robot_base). The pixel pitch of the smoothing is the\n"
      "outline's \"spacing\" (hg-outline writes it; --pixel-pitch overrides), else estimated from its loops.\n"
      "The cell file (--cell, docs/cell.md) gives the camera-to-base calibration, the tool (tool.radius,\n"
      "tool.tilt), the limits the path is validated against, home and the base frame (frames.base); a speed\n"
      "above its max-speed is refused.\n"
      "Frames: the outline file's \"frame\" says which frame its plane is in: camera (the cell's camera-to-base\n"
      "is applied), robot_base (the cell's frames.base: used as it is) or cloud (hg-outline: the input cloud's own\n"
      "coordinates, taken as the camera frame). --outline-frame overrides it: a cloud in robot base\n"
      "coordinates plans with --outline-frame robot_base. The transform applied is printed on stderr.\n"
      "The start point is the loop point nearest to the cell's home (no robot is heard here). The passes after\n"
      "sequencing are the path-modifiers (docs/path_planner.md, \"Path modifiers\").\n"
      "Prints a one-line summary on stderr. Exit status: 0 planned, 1 planning failed (reason on stderr),\n"
      "2 bad command line, config or input file.\n\n"
      "options (command line > --config FILE, the same keys as hg-path-planner, config/path_planner.yaml > default):\n");
  params.print_options(f);
  std::fprintf(f,
               "  --config FILE                      YAML config file (keys as the options above, without --)\n"
               "  --help, --help-markdown, --version this text, the options as a Markdown table, the version\n");
}

std::vector<hg::runtime::Param> hg_plan_params() {
  std::vector<hg::runtime::Param> params = planner_params();
  hg::runtime::Param output = hg::runtime::text_param("output", "", "write the path here (default: standard output)");
  output.alias = "-o";
  params.insert(params.begin(),
                {output, hg::runtime::text_param("job-id", "hg-plan", "job id written into the path"),
                 hg::runtime::flag_param("check-config",
                                         "read the configuration and the cell file, plan nothing: exit 0 "
                                         "when they are good (tools/run.sh checks a cell with it)")});
  return params;
}

// The outline file in the frame the planner works in; throws naming the problem (exit 2): a bad file
// (outline_io::ReadError names the file and the key) or a frame that does not fit the cell.
OutlineInput read_input(const std::string& input, const PlannerConfig& cfg, const std::string& chosen_frame,
                        OutlineFrame& frame) {
  OutlineInput outline = read_outline_file(input, cfg.default_plane);
  try {
    frame = resolve_outline_frame(outline.frame, chosen_frame, cfg);
  } catch (const std::exception& e) {
    throw std::runtime_error(input + ": " + e.what());
  }
  return outline;
}

// An outline without a plane: in the camera frame it lies on the configured plane-* (the table as the camera
// sees it); in the base frame its loops are that frame's own x, y (a flat cloud in robot base coordinates,
// whose plane hg-outline does not write when there is no z), on z = 0 of that frame.
void place_default_plane(OutlineInput& outline, const OutlineFrame& frame, const PlannerConfig& cfg) {
  if (outline.plane_given) return;
  if (frame.used != cfg.base_frame) {
    std::fprintf(stderr, "hg-plan: the outline has no plane: the configured plane-* (camera frame) is used\n");
    return;
  }
  outline.plane = Plane{};
  std::fprintf(stderr, "hg-plan: the outline has no plane: its loops are x, y of %s, on z = 0\n",
               cfg.base_frame.c_str());
}

const char* pitch_source_text(const std::string& source) {
  if (source == "pixel-pitch") return "--pixel-pitch";
  if (source == "outline") return "the outline's point spacing";
  if (source == "staircase") return "estimated from the loops' pixel staircase";
  if (source == "vertices") return "estimated from the loops' vertex spacing; no edge compensation";
  return "none: a drawn polygon, not smoothed";
}

bool write_text(const std::string& output, const std::string& text) {
  if (output.empty()) return bool(std::cout << text);
  std::ofstream o(output, std::ios::binary);
  o << text;
  return bool(o);
}

}  // namespace

int main(int argc, char** argv) {
  hg::runtime::Params params(hg_plan_params());
  PlannerConfig cfg;
  OutlineInput outline;
  OutlineFrame frame;
  std::string input;
  try {
    const hg::runtime::Params::Action action = params.parse(argc, argv);
    if (action != hg::runtime::Params::Action::Run) return hg::runtime::answer(action, "hg-plan", params, usage);
    if (params.flag("check-config")) {
      cfg = config_from(lookup_from(params));
      std::fprintf(stderr, "hg-plan: the configuration and cell file %s are good\n", cfg.cell_file.c_str());
      return 0;
    }
    if (params.positional().size() != 1)
      throw hg::runtime::ConfigError("command line: give one OUTLINE.json (see --help)");
    input = params.positional()[0];
    cfg = config_from(lookup_from(params));
  } catch (const std::exception& e) {
    std::fprintf(stderr, "hg-plan: %s\n", e.what());
    return 2;
  }
  try {
    outline = read_input(input, cfg, params.text("outline-frame"), frame);
  } catch (const std::exception& e) {
    std::fprintf(stderr, "hg-plan: %s\n", e.what());
    return 2;
  }
  place_default_plane(outline, frame, cfg);
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
      std::fprintf(stderr, "hg-plan: is the outline in robot base coordinates? then give --outline-frame %s\n",
                   cfg.base_frame.c_str());
    return 1;
  }
  if (!write_text(params.text("output"),
                  path_json(params.text("job-id"), cfg.base_frame, r, outline.seq).dump(1) + "\n")) {
    std::fprintf(stderr, "hg-plan: cannot write %s\n", params.text("output").c_str());
    return 2;
  }
  std::fprintf(stderr,
               "hg-plan: %zu waypoints, %d loops, %d speeds lowered at corners, pitch %.3f mm (%s), planned in %.2f "
               "ms\n",
               r.path.size(), r.loops_planned, r.slowed, r.pitch * 1e3, pitch_source_text(r.pitch_source),
               r.seconds * 1e3);
  return 0;
}
