// hg-camera-render: synthetic depth frames to files, the input format of `hg-camera-bridge --source files`:
// OUT/depth_000000.png ... (16-bit PNG), OUT/intrinsics.yaml, OUT/truth.json (ground truth of frame 0), and
// OUT/intensity_000000.png ... (8-bit) for scenes that render the intensity image (the realistic presets).
#include <cstdio>
#include <cstdlib>
#include <filesystem>
#include <string>
#include <vector>

#include <opencv2/imgcodecs.hpp>

#include "sim/scene/scene.hpp"
#include "camera_bridge/sources.hpp"
#include "runtime/params.hpp"

using namespace hg::camera_bridge;
using namespace hg::sim;

namespace {

constexpr const char* kUsageHead =
    "usage: hg-camera-render --out DIR [options]\n"
    "Writes DIR/depth_NNNNNN.png (16-bit), DIR/intrinsics.yaml and DIR/truth.json; scenes with the\n"
    "intensity image (NAME-realistic) also DIR/intensity_NNNNNN.png (8-bit).\n";

std::vector<hg::runtime::Param> render_params() {
  using namespace hg::runtime;
  std::vector<Param> params = {text_param("out", "", "output folder (required)"),
                               text_param("scene", "three-parts", "scene preset of the renderer", scene_preset_names()),
                               text_param("profile", "pm806", "camera profile", camera_profile_names()),
                               integer_param("frames", "1", "frames to render", 1, 1e6)};
  set_value_names(params, {{"out", "DIR"}, {"scene", "NAME"}, {"frames", "N"}});
  return params;
}

}  // namespace

int main(int argc, char** argv) {
  hg::runtime::Params p(render_params());
  if (const int rc = hg::runtime::parse_tool(p, argc, argv, "hg-camera-render", hg::runtime::usage_with(kUsageHead));
      rc >= 0)
    return rc;
  const std::string scene = p.text("scene"), profile = p.text("profile"), out = p.text("out");
  const int frames = int(p.integer("frames"));
  if (out.empty() || !p.positional().empty()) {
    std::fprintf(stderr, "hg-camera-render: command line: %s (see --help)\n",
                 out.empty() ? "need --out DIR" : ("unexpected argument '" + p.positional()[0] + "'").c_str());
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
