#include "camera_bridge/camera_bridge.hpp"

int main(int argc, char** argv) { return hg::camera_bridge::run_main(argc, argv); }
