#include "robot_bridge/robot_bridge.hpp"
#include "runtime/process.hpp"

int main(int argc, char** argv) {
  return hg::runtime::run_process(hg::robot_bridge::process_info(), argc, argv, hg::robot_bridge::attach);
}
