#include <cstring>
#include <exception>
#include <vector>

#include "robot_bridge/robot_bridge.hpp"
#include "runtime/log.hpp"

int main(int argc, char** argv) {
  // The one-shot export needs no bus: give it an in-process LCM unless the caller chose one.
  std::vector<char*> args(argv, argv + argc);
  bool has_path = false, has_url = false;
  for (int i = 1; i < argc; ++i) {
    has_path |= std::strncmp(argv[i], "--path", 6) == 0;
    has_url |= std::strncmp(argv[i], "--lcm-url", 9) == 0;
  }
  static char url_opt[] = "--lcm-url", memq[] = "memq://";
  if (has_path && !has_url) args.insert(args.end(), {url_opt, memq});
  args.push_back(nullptr);
  hg::runtime::Node node(hg::robot_bridge::process_info(), int(args.size()) - 1, args.data());
  try {
    if (node.param_given("path")) return hg::robot_bridge::export_script(node);
    auto process = hg::robot_bridge::attach(node);
    return node.run();
  } catch (const std::exception& e) {
    hg::runtime::logf(hg::runtime::Level::Error, "%s", e.what());
    return 2;
  }
}
