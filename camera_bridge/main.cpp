#include "camera_bridge/camera_bridge.hpp"

int main(int argc, char** argv) {
  hg::runtime::Node node(hg::camera_bridge::process_info(), argc, argv);
  hg::camera_bridge::attach(node);
  return node.run();
}
