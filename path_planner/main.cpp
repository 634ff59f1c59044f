#include "path_planner/path_planner.hpp"

int main(int argc, char** argv) {
  hg::runtime::Node node(hg::path_planner::process_info(), argc, argv);
  hg::path_planner::attach(node);
  return node.run();
}
