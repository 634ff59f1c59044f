// Every effect off: the renderer's frames are those it gave before the sensor effects existed (the
// committed logs and every test that renders depend on that). Hashes of depth and ground-truth labels of
// every scene preset without effects, both camera profiles, frames 0 and 1, taken from the renderer at
// main 7e71404 (before the effects).
#include <gtest/gtest.h>

#include <cstdint>
#include <cstdio>
#include <map>
#include <string>

#include "sim/scene/scene.hpp"

namespace {

// FNV-1a 64 over the rows of a matrix.
std::uint64_t fnv(const cv::Mat& m, std::uint64_t h = 1469598103934665603ull) {
  for (int r = 0; r < m.rows; ++r) {
    const auto* p = m.ptr<std::uint8_t>(r);
    for (std::size_t i = 0; i < m.cols * m.elemSize(); ++i) h = (h ^ p[i]) * 1099511628211ull;
  }
  return h;
}

const std::map<std::string, std::uint64_t> kBefore = {
    {"empty@pm806#0", 0xe7c0b2b716982df1ull},
    {"empty@pm806#1", 0x88516e07ed1b7791ull},
    {"empty@lsr-l#0", 0x119d5d4547c74575ull},
    {"empty@lsr-l#1", 0xf3bc79e4a6ef4019ull},
    {"plate-hole-slot@pm806#0", 0x851d15a4b530a3deull},
    {"plate-hole-slot@pm806#1", 0x54bd2dc37540d832ull},
    {"plate-hole-slot@lsr-l#0", 0x7ec56d16d6b99b64ull},
    {"plate-hole-slot@lsr-l#1", 0x775c46f8e5d9c012ull},
    {"l-bracket@pm806#0", 0xd318a0bce23e94f8ull},
    {"l-bracket@pm806#1", 0xc318235522e0d09dull},
    {"l-bracket@lsr-l#0", 0x6faf3a022cc61d50ull},
    {"l-bracket@lsr-l#1", 0x7ba5fe87b17c1952ull},
    {"knee-scallop@pm806#0", 0x2e5f2006bb8abd6bull},
    {"knee-scallop@pm806#1", 0xfac1ceef6ce55b20ull},
    {"knee-scallop@lsr-l#0", 0xad0e38986980452cull},
    {"knee-scallop@lsr-l#1", 0x4e917bcf0ea2e62full},
    {"collar-notch@pm806#0", 0x2ae0d01e3164e57eull},
    {"collar-notch@pm806#1", 0x245f70e8eb6f46d4ull},
    {"collar-notch@lsr-l#0", 0x95573147b704ce2eull},
    {"collar-notch@lsr-l#1", 0x4bc872766af8051eull},
    {"ring-flange@pm806#0", 0x043ab2b583b1b683ull},
    {"ring-flange@pm806#1", 0xdafd7c5a57211c7bull},
    {"ring-flange@lsr-l#0", 0x6add1a6e965b4730ull},
    {"ring-flange@lsr-l#1", 0x5af8d5ecdd1764c4ull},
    {"trapezoid-holes@pm806#0", 0x3109b7154898004eull},
    {"trapezoid-holes@pm806#1", 0x5e15a1078523ab19ull},
    {"trapezoid-holes@lsr-l#0", 0xd6a8bbd36de72f09ull},
    {"trapezoid-holes@lsr-l#1", 0x241f726743f6dc71ull},
    {"three-parts@pm806#0", 0xa40839c6cc30643cull},
    {"three-parts@pm806#1", 0x304667def598a0cdull},
    {"three-parts@lsr-l#0", 0x34efe05c412d408bull},
    {"three-parts@lsr-l#1", 0x6e7a64da6d870c7cull},
    {"demo@pm806#0", 0xfd4fc1b950019224ull},
    {"demo@pm806#1", 0x47bb76395bb62b8cull},
    {"demo@lsr-l#0", 0x4594e326c6354704ull},
    {"demo@lsr-l#1", 0x6f8eab9370a9489eull},
};

}  // namespace

TEST(SceneUnchanged, EffectsOffGiveTheFramesOfBefore) {
  int compared = 0;
  for (const char* scene : {"empty", "plate-hole-slot", "l-bracket", "knee-scallop", "collar-notch", "ring-flange",
                            "trapezoid-holes", "three-parts", "demo"})
    for (const char* profile : {"pm806", "lsr-l"})
      for (std::uint64_t k = 0; k < 2; ++k) {
        const hg::sim::RenderedFrame f =
            hg::sim::render(hg::sim::scene_preset(scene), hg::sim::camera_profile(profile), k);
        const std::uint64_t h = fnv(f.truth_labels, fnv(f.depth));
        const std::string key = std::string(scene) + "@" + profile + "#" + std::to_string(k);
        const auto it = kBefore.find(key);
        if (it == kBefore.end()) {
          ADD_FAILURE() << key;
          continue;
        }
        EXPECT_EQ(h, it->second) << key;
        ++compared;
      }
  EXPECT_EQ(compared, 36);
}
