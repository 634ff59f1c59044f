#include "camera_bridge/camera_bridge.hpp"
#include "runtime/process.hpp"

int main(int argc, char** argv) {
  return hg::runtime::run_process(hg::camera_bridge::process_info(), argc, argv, hg::camera_bridge::attach);
}
