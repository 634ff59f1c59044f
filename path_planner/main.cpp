#include "path_planner/path_planner.hpp"

#include <cstdio>

int main(int argc, char** argv) {
  hg::runtime::Node node(hg::path_planner::process_info(), argc, argv);
  try {
    hg::path_planner::attach(node);
  } catch (const hg::runtime::ConfigError& e) {
    std::fprintf(stderr, "hg-path-planner: %s\n", e.what());
    return 2;
  }
  return node.run();
}
