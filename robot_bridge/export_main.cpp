// hg-robot-export: the URScript of a path file, checked against the cell's limits as hg-robot-bridge checks
// a path before running it; no bus. Reads the robot bridge's keys (config/robot_bridge.yaml) and the cell file.
#include <cstdio>
#include <exception>

#include "robot_bridge/robot_bridge.hpp"
#include "runtime/params.hpp"

namespace {

void usage(std::FILE* f, const hg::runtime::Params& params) {
  std::fprintf(
      f,
      "usage: hg-robot-export [options] PATH.json -o JOB.script\n"
      "Writes the URScript program of a path file (docs/path_file.md) after the robot bridge's checks\n"
      "(workspace box, table height, speed, corner acceleration: the limits of the cell file, --cell; from the\n"
      "first waypoint, as the robot's pose is unknown offline). Exit status: 0 written, 1 refused by the checks\n"
      "(nothing written), 2 bad command line, config, cell or path file.\n\n"
      "options (the keys of hg-robot-bridge; only --cell and the script options matter here):\n");
  params.print_options(f);
  std::fprintf(f,
               "  --config FILE                      YAML config file, e.g. config/robot_bridge.yaml\n"
               "  --help, --help-markdown, --version this text, the options as a Markdown table, the version\n");
}

std::vector<hg::runtime::Param> export_params() {
  std::vector<hg::runtime::Param> params = hg::robot_bridge::process_info().params;
  hg::runtime::Param output = hg::runtime::text_param("output", "", "the URScript file to write");
  output.alias = "-o";
  params.insert(params.begin(), output);
  return params;
}

}  // namespace

int main(int argc, char** argv) {
  hg::runtime::Params params(export_params());
  try {
    const auto action = params.parse(argc, argv);
    if (action != hg::runtime::Params::Action::Run)
      return hg::runtime::answer(action, "hg-robot-export", params, usage);
    if (params.positional().size() != 1 || params.text("output").empty())
      throw hg::runtime::ConfigError("command line: give one PATH.json and -o JOB.script (see --help)");
    return hg::robot_bridge::export_script(params, params.positional()[0], params.text("output"));
  } catch (const std::exception& e) {
    std::fprintf(stderr, "hg-robot-export: %s\n", e.what());
    return 2;
  }
}
