#include "path_planner/path_planner.hpp"
#include "runtime/process.hpp"

int main(int argc, char** argv) {
  return hg::runtime::run_process(hg::path_planner::process_info(), argc, argv, hg::path_planner::attach);
}
