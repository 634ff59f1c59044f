#include "robot_bridge/robot_bridge.hpp"

int main(int argc, char** argv) {
  hg::runtime::Node node(hg::robot_bridge::process_info(), argc, argv);
  hg::robot_bridge::attach(node);
  return node.run();
}
