// libFuzzer target: one point-cloud reader (HG_FUZZ_PARSE, set per target in CMakeLists.txt) on arbitrary
// bytes, then the plane fit hg-outline runs on what it accepts. The documented refusals are answers: the
// readers' ReadError ("FILE: line N: ...") and the core's OutlineError from to_plane ("need at least 3
// distinct points", "all N distinct points are collinear", a coordinate too finely resolved), which hg-outline
// reports as a clear error. Anything else (crash, sanitizer report, other exception, absurd allocation) is a bug.
#include <cmath>
#include <cstddef>
#include <cstdint>
#include <string_view>

#include "outline_io/cloud.hpp"
#include "outline_core/types.hpp"

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  try {
    auto cloud = hg::outline_io::HG_FUZZ_PARSE(std::string_view(reinterpret_cast<const char*>(data), size), "fuzz");
    if (cloud.size() == 0) __builtin_trap();  // readers promise at least one point or an error
    // The plane fit runs on whatever a reader accepts: finite plane coordinates for every finite point (a point
    // with a NaN or infinite coordinate stays NaN, the core skips it), or a documented refusal.
    auto planar = hg::outline_io::to_plane(cloud, "fuzz");
    if (planar.points.size() != cloud.size()) __builtin_trap();
    for (std::size_t i = 0; i < cloud.size(); ++i) {
      const double* q = &cloud.xyz[3 * i];
      const bool finite = std::isfinite(q[0]) && std::isfinite(q[1]) && std::isfinite(q[2]);
      if (finite && (!std::isfinite(planar.points[i].x) || !std::isfinite(planar.points[i].y))) __builtin_trap();
    }
  } catch (const hg::outline_io::ReadError&) {
  } catch (const hg::outline::OutlineError&) {
  }
  return 0;
}
