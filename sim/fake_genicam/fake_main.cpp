// hg-fake-genicam: a fake GigE Vision 3-D camera on 127.0.0.1 serving the scene renderer's depth as
// Coord3D_C16 range images (FakeGenicamCamera), for `tools/run.sh --camera genicam` and trying the
// `genicam` source by hand. It answers GVCP discovery broadcasts and streams GVSP, so it refuses to run
// unless its network namespace has no interface but `lo` (run it under tests/netns.sh or run.sh).
#include <csignal>
#include <cstdio>
#include <cstdlib>
#include <fstream>
#include <set>
#include <sstream>
#include <string>
#include <thread>

#include "sim/fake_genicam/fake_camera.hpp"
#include "runtime/version.hpp"

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

int usage() {
  std::fprintf(stdout,
               "usage: hg-fake-genicam [--scene NAME] [--profile pm806|lsr-l] [--seed N] [--noise-scale K]\n"
               "                       [--serial S] [--scale-mm MM] [--offset-mm MM] [--rate HZ] [--xml FILE]\n"
               "A fake GigE Vision 3-D camera on 127.0.0.1 (Aravis's fake camera with hullgrind's GenICam XML)\n"
               "serving the scene renderer's depth as Coord3D_C16: raw = (depth_mm - offset) / scale. Discovered\n"
               "by Aravis as Aravis-Fake-SERIAL. Runs until SIGINT/SIGTERM. Only in a network namespace with\n"
               "nothing but lo (tests/netns.sh): it answers discovery broadcasts.\n"
               "Defaults: --scene plate-hole-slot --profile pm806 --serial HG3D-0001 --scale-mm 0.05\n"
               "--offset-mm 400 --rate 5 --noise-scale 1 (frame n is the rendering at index n).\n");
  return 0;
}

int refuse(const std::string& what) {  // one line (the failure contract of every program, docs/RUNNING.md)
  std::fprintf(stderr, "hg-fake-genicam: command line: %s (see --help)\n", what.c_str());
  return 2;
}

}  // namespace

int main(int argc, char** argv) {
  if (hg::runtime::answer_version(argc, argv, "hg-fake-genicam")) return 0;
  FakeGenicamOptions o;
  std::string scene = "plate-hole-slot", profile = "pm806", seed;
  double noise = 1.0;
  o.offset_mm = 400;
  o.frame_rate = 5;
  for (int i = 1; i < argc; ++i) {
    const std::string a = argv[i];
    const bool has = i + 1 < argc;
    if (a == "--help" || a == "-h") return usage();
    if (a.rfind("--", 0) != 0) return refuse("unknown argument " + a);
    if (!has) return refuse(a + " needs a value");
    const std::string v = argv[++i];
    if (a == "--scene") scene = v;
    else if (a == "--profile")
      profile = v;
    else if (a == "--seed")
      seed = v;
    else if (a == "--noise-scale")
      noise = std::atof(v.c_str());
    else if (a == "--serial")
      o.serial = v;
    else if (a == "--scale-mm")
      o.scale_mm = std::atof(v.c_str());
    else if (a == "--offset-mm")
      o.offset_mm = std::atof(v.c_str());
    else if (a == "--rate")
      o.frame_rate = std::atof(v.c_str());
    else if (a == "--xml")
      o.xml_path = v;
    else
      return refuse("unknown option " + a);
  }
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
    if (!seed.empty()) o.scene.seed = std::strtoull(seed.c_str(), nullptr, 10);
    o.profile = camera_profile(profile);
    if (!(noise >= 0)) throw std::invalid_argument("--noise-scale must be >= 0");
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
