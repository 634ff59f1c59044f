// No-return pixels and degenerate 3-D input: NaN/Inf points are read (kept at their file position) and
// counted by every reader and encoding, organized PCD clouds (HEIGHT > 1) with NaN pixels included;
// the plane fit ignores them; a cloud collinear in space gives the core's collinear error.
#include <gtest/gtest.h>

#include <cmath>
#include <cstring>
#include <limits>
#include <string>
#include <vector>

#include "lzf_test_compressor.hpp"
#include "outline_io/cloud.hpp"

using namespace hg::outline_io;
using hg::outline::OutlineError;

namespace {

constexpr float kNaN = std::numeric_limits<float>::quiet_NaN();

// An organized W x H depth-camera cloud on the plane z = 0.25 x + 0.5 y + 3 (exact in float), with
// fields x y z rgb; pixels with (i + 2 j) % 5 == 0 and the whole row j == 2 give no return (NaN x y z).
struct Organized {
  int w = 9, h = 6;
  std::vector<std::array<float, 4>> px;  // x y z rgb, row-major
  std::size_t nan_count = 0;
  Organized() {
    for (int j = 0; j < h; ++j)
      for (int i = 0; i < w; ++i) {
        const bool none = (i + 2 * j) % 5 == 0 || j == 2;
        nan_count += none;
        const float x = static_cast<float>(i), y = static_cast<float>(j);
        px.push_back(none ? std::array<float, 4>{kNaN, kNaN, kNaN, 7.0f}
                          : std::array<float, 4>{x, y, 0.25f * x + 0.5f * y + 3, 7.0f});
      }
  }
  std::string header(const std::string& kind) const {
    return "# .PCD v0.7 - Point Cloud Data file format\nVERSION 0.7\nFIELDS x y z rgb\nSIZE 4 4 4 4\nTYPE F F F F\n"
           "COUNT 1 1 1 1\nWIDTH " +
           std::to_string(w) + "\nHEIGHT " + std::to_string(h) + "\nVIEWPOINT 0 0 0 1 0 0 0\nPOINTS " +
           std::to_string(w * h) + "\nDATA " + kind + "\n";
  }
  std::string ascii() const {
    std::string s = header("ascii");
    for (auto& p : px) {
      for (int k = 0; k < 4; ++k)
        s += (std::isnan(p[k]) ? std::string("nan") : std::to_string(p[k])) + (k < 3 ? " " : "\n");
    }
    return s;
  }
  std::string binary() const {
    std::string s = header("binary");
    for (auto& p : px) s.append(reinterpret_cast<const char*>(p.data()), 16);
    return s;
  }
  std::string compressed() const {  // fields one after the other, LZF-compressed
    std::string raw;
    for (int k = 0; k < 4; ++k)
      for (auto& p : px) raw.append(reinterpret_cast<const char*>(&p[k]), 4);
    const std::string c = hg_test::lzf_compress(raw);
    std::string s = header("binary_compressed");
    const std::uint32_t sizes[2] = {static_cast<std::uint32_t>(c.size()), static_cast<std::uint32_t>(raw.size())};
    s.append(reinterpret_cast<const char*>(sizes), 8);
    return s + c;
  }
  void expect_read(const Cloud& c) const {
    ASSERT_EQ(c.size(), px.size());
    EXPECT_TRUE(c.has_z);
    EXPECT_EQ(c.nonfinite, nan_count);
    for (std::size_t i = 0; i < px.size(); ++i)
      for (int k = 0; k < 3; ++k) {
        if (std::isnan(px[i][k])) EXPECT_TRUE(std::isnan(c.xyz[3 * i + k])) << i;
        else
          EXPECT_EQ(c.xyz[3 * i + k], px[i][k]) << i;
      }
  }
};

}  // namespace

TEST(OutlineIoNonFinite, OrganizedPcdWithNoReturnPixelsInEveryEncoding) {
  const Organized o;
  ASSERT_GT(o.nan_count, 9u);
  o.expect_read(parse_pcd(o.ascii(), "org_ascii.pcd"));
  o.expect_read(parse_pcd(o.binary(), "org_binary.pcd"));
  o.expect_read(parse_pcd(o.compressed(), "org_compressed.pcd"));
}

TEST(OutlineIoNonFinite, TextAndPlyCountNanAndInfPoints) {
  const Cloud t = parse_text_cloud("0 0 1\nnan 1 2\n1 inf 3\n2 2 -inf\n4 4 NaN\n5,6,7\n", "mem.xyz");
  ASSERT_EQ(t.size(), 6u);
  EXPECT_EQ(t.nonfinite, 4u);
  EXPECT_EQ(t.xyz[15], 5.0);
  const Cloud t2 = parse_text_cloud("1 2\n3 nan\n-infinity 4\n5 6\n", "mem.txt");
  EXPECT_EQ(t2.nonfinite, 2u);
  EXPECT_FALSE(t2.has_z);
  const std::string head =
      "ply\nformat ascii 1.0\nelement vertex 4\nproperty float x\nproperty float y\nproperty float z\nend_header\n";
  const Cloud pa = parse_ply(head + "0 0 0\nnan 1 1\n2 2 inf\n3 3 3\n", "mem.ply");
  EXPECT_EQ(pa.nonfinite, 2u);
  std::string pb =
      "ply\nformat binary_little_endian 1.0\nelement vertex 3\nproperty float x\nproperty float y\nend_header\n";
  const float v[6] = {0, 0, kNaN, 1, 2, std::numeric_limits<float>::infinity()};
  pb.append(reinterpret_cast<const char*>(v), sizeof v);
  const Cloud pbc = parse_ply(pb, "mem.ply");
  ASSERT_EQ(pbc.size(), 3u);
  EXPECT_EQ(pbc.nonfinite, 2u);
  EXPECT_TRUE(std::isnan(pbc.xyz[3]));
}

TEST(OutlineIoNonFinite, PlaneFitIgnoresNonFinitePoints) {
  // The organized cloud's plane fit equals that of its finite points alone, and NaN pixels project to
  // NaN at their own index; the plane is z = 0.25 x + 0.5 y + 3.
  const Organized o;
  const Cloud c = parse_pcd(o.binary(), "org.pcd");
  Cloud finite;
  finite.has_z = true;
  std::vector<std::size_t> where;
  for (std::size_t i = 0; i < c.size(); ++i)
    if (std::isfinite(c.xyz[3 * i])) {
      finite.xyz.insert(finite.xyz.end(), c.xyz.begin() + 3 * i, c.xyz.begin() + 3 * i + 3);
      where.push_back(i);
    }
  const PlanarPoints a = to_plane(c, "org.pcd"), b = to_plane(finite, "finite");
  ASSERT_TRUE(a.projected);
  ASSERT_EQ(a.points.size(), c.size());
  std::size_t k = 0, nan = 0;
  for (std::size_t i = 0; i < c.size(); ++i) {
    if (k < where.size() && where[k] == i) {
      EXPECT_EQ(a.points[i].x, b.points[k].x);
      EXPECT_EQ(a.points[i].y, b.points[k].y);
      ++k;
    } else {
      EXPECT_TRUE(std::isnan(a.points[i].x) && std::isnan(a.points[i].y));
      ++nan;
    }
  }
  EXPECT_EQ(nan, o.nan_count);
  const double norm = std::sqrt(0.25 * 0.25 + 0.5 * 0.5 + 1);
  EXPECT_NEAR(a.plane.normal[0], -0.25 / norm, 1e-12);
  EXPECT_NEAR(a.plane.normal[1], -0.5 / norm, 1e-12);
  EXPECT_NEAR(a.plane.normal[2], 1 / norm, 1e-12);
  EXPECT_LT(a.max_distance, 1e-9);
  // Planar input (every finite z equal) with NaN: x, y kept, NaN points NaN.
  const PlanarPoints p = to_plane(parse_text_cloud("0 0 5\n1 0 5\nnan 0 5\n0 1 nan\n1 1 5\n", "flat.xyz"));
  EXPECT_TRUE(p.projected);  // on the plane z = 5, with x, y as they are
  EXPECT_EQ(p.plane.origin[2], 5.0);
  EXPECT_EQ(p.points[4].x, 1.0);
  EXPECT_TRUE(std::isnan(p.points[2].x) && std::isnan(p.points[3].x));
}

TEST(OutlineIoNonFinite, CloudCollinearInSpaceIsTheCollinearError) {
  // On the line (1, 2, 3) t through (5, -1, 0.5), with repeats and a NaN point: exactly collinear (the
  // coordinates are small integers and halves), 9 distinct points.
  Cloud c;
  c.has_z = true;
  for (int t : {0, 1, 2, 3, 4, 5, 6, 7, 8, 3, 0}) c.xyz.insert(c.xyz.end(), {5.0 + t, -1.0 + 2 * t, 0.5 + 3 * t});
  c.xyz.insert(c.xyz.end(), {std::nan(""), 1, 1});
  try {
    to_plane(c, "line.xyz");
    FAIL() << "no error";
  } catch (const OutlineError& e) {
    EXPECT_EQ(std::string(e.what()), "all 9 distinct points are collinear");
  }
  // One point off the line: a plane exists.
  c.xyz[3 * 4 + 2] += 1;
  EXPECT_NO_THROW(to_plane(c, "bent.xyz"));
  // Two distinct points only.
  Cloud two;
  two.has_z = true;
  two.xyz = {1, 2, 3, 4, 5, 6, 1, 2, 3};
  EXPECT_THROW(to_plane(two, "two.xyz"), OutlineError);
}
