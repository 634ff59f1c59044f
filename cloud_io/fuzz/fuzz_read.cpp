// libFuzzer target: one point-cloud reader (HG_FUZZ_PARSE, set per target in CMakeLists.txt) on arbitrary
// bytes. A ReadError is the expected answer to garbage; anything else (crash, sanitizer report, other
// exception, absurd allocation) is a bug.
#include <cmath>
#include <cstddef>
#include <cstdint>
#include <string_view>

#include "cloud_io/cloud_io.hpp"

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  try {
    auto cloud = hg::outline::io::HG_FUZZ_PARSE(std::string_view(reinterpret_cast<const char*>(data), size), "fuzz");
    if (cloud.size() == 0) __builtin_trap();  // readers promise at least one point or an error
    // The plane fit runs on whatever a reader accepts: finite plane coordinates or a ReadError.
    auto planar = hg::outline::io::to_plane(cloud, "fuzz");
    for (auto& p : planar.points)
      if (!std::isfinite(p.x) || !std::isfinite(p.y)) __builtin_trap();
  } catch (const hg::outline::io::ReadError&) {
  }
  return 0;
}
