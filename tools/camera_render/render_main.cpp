// hg-camera-render: synthetic depth frames to files, the input format of `hg-camera-bridge --source files`:
// OUT/depth_000000.png ... (16-bit PNG), OUT/intrinsics.yaml, OUT/truth.json (ground truth of frame 0), and
// OUT/intensity_000000.png ... (8-bit) for scenes that render the intensity image (the realistic presets).
#include <cstdio>
#include <cstdlib>
#include <filesystem>
#include <string>

#include <opencv2/imgcodecs.hpp>

#include "sim/scene/scene.hpp"
#include "camera_bridge/sources.hpp"
#include "runtime/version.hpp"

using namespace hg::camera_bridge;
using namespace hg::sim;

int main(int argc, char** argv) {
  if (hg::runtime::answer_version(argc, argv, "hg-camera-render")) return 0;
  std::string scene = "three-parts", profile = "pm806", out;
  int frames = 1;
  for (int i = 1; i < argc; ++i) {
    const std::string a = argv[i];
    if (a == "--scene" && i + 1 < argc) scene = argv[++i];
    else if (a == "--profile" && i + 1 < argc)
      profile = argv[++i];
    else if (a == "--frames" && i + 1 < argc)
      frames = std::atoi(argv[++i]);
    else if (a == "--out" && i + 1 < argc)
      out = argv[++i];
    else if (a == "--help" || a == "-h") {
      std::printf(
          "usage: hg-camera-render --out DIR [--scene NAME] [--profile pm806|lsr-l] [--frames N]\n"
          "Writes DIR/depth_NNNNNN.png (16-bit), DIR/intrinsics.yaml and DIR/truth.json; scenes with the\n"
          "intensity image (NAME-realistic) also DIR/intensity_NNNNNN.png (8-bit).\n"
          "Scenes: %s\n",
          [] {
            std::string s;
            for (const auto& n : scene_preset_names()) s += (s.empty() ? "" : ", ") + n;
            return s;
          }()
              .c_str());
      return 0;
    } else {
      std::fprintf(stderr, "hg-camera-render: command line: unknown option %s (see --help)\n", a.c_str());
      return 2;
    }
  }
  if (out.empty() || frames < 1) {
    std::fprintf(stderr, "hg-camera-render: need --out DIR and --frames >= 1\n");
    return 2;
  }
  try {
    const SceneSpec spec = scene_preset(scene);
    const CameraProfile prof = camera_profile(profile);
    std::filesystem::create_directories(out);
    for (int k = 0; k < frames; ++k) {
      const RenderedFrame f = render(spec, prof, k);
      char name[64];
      std::snprintf(name, sizeof name, "/depth_%06d.png", k);
      if (!cv::imwrite(out + name, f.depth)) throw std::runtime_error(std::string("cannot write ") + out + name);
      if (!f.intensity.empty()) {
        std::snprintf(name, sizeof name, "/intensity_%06d.png", k);
        if (!cv::imwrite(out + name, f.intensity)) throw std::runtime_error(std::string("cannot write ") + out + name);
      }
      if (k == 0) {
        write_intrinsics(f.intrinsics, out + "/intrinsics.yaml");
        write_truth(spec, prof, f, 0, out + "/truth.json");
      }
    }
    std::printf("wrote %d frame(s) of scene %s at %s to %s\n", frames, scene.c_str(), profile.c_str(), out.c_str());
  } catch (const std::exception& e) {
    std::fprintf(stderr, "hg-camera-render: %s\n", e.what());
    return 1;
  }
  return 0;
}
