// hg-fake-genicam: a fake GigE Vision 3-D camera on 127.0.0.1 serving the scene renderer's depth as
// Coord3D_C16 range images (FakeGenicamCamera), for `tools/run.sh --camera genicam` and trying the
// `genicam` source by hand. It answers GVCP discovery broadcasts and streams GVSP, so it refuses to run
// unless its network namespace has no interface but `lo` (run it under tests/netns.sh or run.sh).
#include <csignal>
#include <cstdio>
#include <cstdlib>
#include <fstream>
#include <limits>
#include <set>
#include <sstream>
#include <string>
#include <thread>
#include <vector>

#include "sim/fake_genicam/fake_camera.hpp"
#include "runtime/params.hpp"

using namespace hg::sim;

namespace {

volatile std::sig_atomic_t g_stop = 0;

// Interfaces of this network namespace other than lo (from /proc/net/dev).
std::set<std::string> non_loopback_interfaces() {
  std::ifstream dev("/proc/net/dev");
  std::set<std::string> names;
  std::string line;
  while (std::getline(dev, line)) {
    const auto colon = line.find(':');
    if (colon == std::string::npos) continue;
    std::istringstream in(line.substr(0, colon));
    std::string name;
    if (in >> name && name != "lo") names.insert(name);
  }
  return names;
}

constexpr const char* kUsageHead =
    "usage: hg-fake-genicam [options]\n"
    "A fake GigE Vision 3-D camera on 127.0.0.1 (Aravis's fake camera with hullgrind's GenICam XML)\n"
    "serving the scene renderer's depth as Coord3D_C16: raw = (depth_mm - offset) / scale. Discovered\n"
    "by Aravis as Aravis-Fake-SERIAL. Runs until SIGINT/SIGTERM. Only in a network namespace with\n"
    "nothing but lo (tests/netns.sh): it answers discovery broadcasts. Frame n is the rendering at index n.\n";

std::vector<hg::runtime::Param> fake_params() {
  using namespace hg::runtime;
  constexpr double inf = std::numeric_limits<double>::infinity();
  std::vector<Param> params = {
      text_param("scene", "plate-hole-slot", "scene preset of the renderer"),
      text_param("profile", "pm806", "camera profile", camera_profile_names()),
      integer_param("seed", "", "the scene's random seed (default: the preset's)", 0),
      number_param("noise-scale", "1", "multiplies the profile's depth noise, dropout and flying pixels", 0),
      text_param("serial", "HG3D-0001", "the camera's serial number"),
      number_param("scale-mm", "0.05", "depth per raw step, mm", 0, inf, true),
      number_param("offset-mm", "400", "depth of raw value 0, mm"),
      number_param("rate", "5", "frame rate, Hz", 0, inf, true),
      text_param("xml", "", "GenICam XML file to serve instead of hullgrind's")};
  set_value_names(params, {{"scene", "NAME"},
                           {"seed", "N"},
                           {"noise-scale", "K"},
                           {"serial", "S"},
                           {"scale-mm", "MM"},
                           {"offset-mm", "MM"},
                           {"rate", "HZ"},
                           {"xml", "FILE"}});
  return params;
}

int refuse(const std::string& what) {  // one line (the failure contract of every program, docs/RUNNING.md)
  std::fprintf(stderr, "hg-fake-genicam: command line: %s (see --help)\n", what.c_str());
  return 2;
}

}  // namespace

int main(int argc, char** argv) {
  hg::runtime::Params p(fake_params());
  if (const int rc = hg::runtime::parse_tool(p, argc, argv, "hg-fake-genicam", hg::runtime::usage_with(kUsageHead));
      rc >= 0)
    return rc;
  if (!p.positional().empty()) return refuse("unexpected argument '" + p.positional()[0] + "'");
  FakeGenicamOptions o;
  const std::string scene = p.text("scene"), profile = p.text("profile");
  const double noise = p.number("noise-scale");
  o.serial = p.text("serial");
  o.scale_mm = p.number("scale-mm");
  o.offset_mm = p.number("offset-mm");
  o.frame_rate = p.number("rate");
  o.xml_path = p.text("xml");
  if (!o.xml_path.empty() && !std::ifstream(o.xml_path)) return refuse("--xml '" + o.xml_path + "': cannot open");
  if (const auto others = non_loopback_interfaces(); !others.empty()) {
    std::fprintf(stderr,
                 "hg-fake-genicam: refusing to run: this network namespace has %s besides lo "
                 "(run it under tests/netns.sh)\n",
                 others.begin()->c_str());
    return 3;
  }
  try {
    o.scene = scene_preset(scene);
    if (p.given("seed")) o.scene.seed = std::uint64_t(p.integer("seed"));
    o.profile = camera_profile(profile);
    o.profile.noise_a *= noise;
    o.profile.noise_b *= noise;
    o.profile.dropout = std::min(1.0, o.profile.dropout * noise);
    o.profile.flying_pixel_prob = std::min(1.0, o.profile.flying_pixel_prob * noise);
    std::signal(SIGINT, [](int) { g_stop = 1; });
    std::signal(SIGTERM, [](int) { g_stop = 1; });
    FakeGenicamCamera cam(o);
    std::printf("hg-fake-genicam: %s on %s, scene %s, profile %s, %.4g mm per raw step, offset %.4g mm\n",
                cam.device_id().c_str(), o.interface.c_str(), scene.c_str(), profile.c_str(), o.scale_mm, o.offset_mm);
    std::fflush(stdout);
    while (!g_stop) std::this_thread::sleep_for(std::chrono::milliseconds(100));
    std::printf("hg-fake-genicam: stopping after %lld frames\n", (long long)cam.frames_served());
  } catch (const std::exception& e) {
    std::fprintf(stderr, "hg-fake-genicam: %s\n", e.what());
    return 1;
  }
  return 0;
}
