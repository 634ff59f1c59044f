// Plane projection against analytic expectations, and the writers (JSON keys, triangle list, pictures,
// files written whole or not at all).
#include <gtest/gtest.h>

#include <cmath>
#include <filesystem>
#include <fstream>
#include <opencv2/imgcodecs.hpp>
#include <random>
#include <sstream>

#include "outline_io/cloud.hpp"
#include "outline_io/outline_writers.hpp"

using namespace hg::outline;
using namespace hg::outline_io;
namespace fs = std::filesystem;

namespace {

// Rotation about x by a, then about z by b (columns: images of the plane's e1, e2, and its normal).
struct Tilt {
  double m[3][3];
  Tilt(double a, double b) {
    const double ca = std::cos(a), sa = std::sin(a), cb = std::cos(b), sb = std::sin(b);
    const double rx[3][3] = {{1, 0, 0}, {0, ca, -sa}, {0, sa, ca}}, rz[3][3] = {{cb, -sb, 0}, {sb, cb, 0}, {0, 0, 1}};
    for (int i = 0; i < 3; ++i)
      for (int j = 0; j < 3; ++j) {
        m[i][j] = 0;
        for (int k = 0; k < 3; ++k) m[i][j] += rz[i][k] * rx[k][j];
      }
  }
  std::array<double, 3> apply(double x, double y, std::array<double, 3> off) const {
    return {m[0][0] * x + m[0][1] * y + off[0], m[1][0] * x + m[1][1] * y + off[1], m[2][0] * x + m[2][1] * y + off[2]};
  }
};

std::string read_all(const fs::path& p) {
  std::ifstream f(p, std::ios::binary);
  std::stringstream ss;
  ss << f.rdbuf();
  return ss.str();
}

Result two_loop_result() {
  Result r;
  r.points_read = 10;
  r.points_used = 9;
  r.duplicates_merged = 1;
  r.alpha_radius = 1.5;
  r.mode = Mode::DS;
  r.order = Order::Hilbert;
  r.stats.triangles = 8;
  r.stats.search_cost = 42;
  r.stats.search_cost_locate = 30;
  r.stats.search_cost_cavity = 12;
  r.time = {1.0, 2.0, 3.0, 7.0};
  Loop outer;
  outer.points = {{0, 0}, {4, 0}, {4, 4}, {0, 4}};
  outer.point_index = {0, 1, 2, 3};
  outer.area = 16;
  outer.perimeter = 16;
  Loop hole;
  hole.hole = true;
  hole.points = {{1, 1}, {1, 3}, {3, 3}, {3, 1}};
  hole.point_index = {4, 5, 6, 7};
  hole.area = 4;
  hole.perimeter = 8;
  r.loops = {outer, hole};
  r.delaunay_triangles = {{0, 1, 2}, {2, 3, 0}, {4, 8, 5}};
  return r;
}

}  // namespace

TEST(OutlineIoPlane, TiltedPlanarCloudKeepsInPlaneDistances) {
  std::mt19937 rng(1);
  std::uniform_real_distribution<double> d(0, 1000);
  const Tilt t(0.5, 0.3);
  const std::array<double, 3> off{1500, -700, 2200};
  std::vector<Vec2> flat;
  Cloud c;
  c.has_z = true;
  for (int i = 0; i < 2000; ++i) {
    Vec2 p{d(rng), d(rng) * 0.6};
    flat.push_back(p);
    auto q = t.apply(p.x, p.y, off);
    c.xyz.insert(c.xyz.end(), q.begin(), q.end());
  }
  PlanarPoints pp = to_plane(c);
  ASSERT_TRUE(pp.projected);
  ASSERT_EQ(pp.points.size(), flat.size());
  // Normal = third column of the rotation (pointing to +z, as the plane's normal is oriented).
  const double n_dot = pp.plane.normal[0] * t.m[0][2] + pp.plane.normal[1] * t.m[1][2] + pp.plane.normal[2] * t.m[2][2];
  EXPECT_NEAR(n_dot, 1.0, 1e-12);
  EXPECT_LT(pp.rms_distance, 1e-9);
  for (int k = 0; k < 3000; ++k) {
    std::size_t i = rng() % flat.size(), j = rng() % flat.size();
    double want = std::hypot(flat[i].x - flat[j].x, flat[i].y - flat[j].y);
    double got = std::hypot(pp.points[i].x - pp.points[j].x, pp.points[i].y - pp.points[j].y);
    EXPECT_NEAR(got, want, 1e-9 * 1000);
  }
  // Orientation kept as seen from the normal's side: signed areas agree with the flat points.
  for (int k = 0; k < 200; ++k) {
    std::size_t a = rng() % flat.size(), b = rng() % flat.size(), e = rng() % flat.size();
    auto cross = [](Vec2 p, Vec2 q, Vec2 r) { return (q.x - p.x) * (r.y - p.y) - (q.y - p.y) * (r.x - p.x); };
    double want = cross(flat[a], flat[b], flat[e]), got = cross(pp.points[a], pp.points[b], pp.points[e]);
    EXPECT_NEAR(got, want, 1e-6 * 1e6);
    if (std::abs(want) > 1.0) {
      EXPECT_EQ(got > 0, want > 0);
    }
  }
  // Back to 3-D: the plane coordinates give the input points again.
  for (std::size_t i = 0; i < flat.size(); i += 97) {
    auto q = plane_to_3d(pp.plane, pp.points[i]);
    for (int k = 0; k < 3; ++k) EXPECT_NEAR(q[k], c.xyz[3 * i + k], 1e-9 * 3000);
  }
  // (u, v, normal) is orthonormal and right-handed.
  auto dot = [](auto& a, auto& b) { return a[0] * b[0] + a[1] * b[1] + a[2] * b[2]; };
  EXPECT_NEAR(dot(pp.plane.u, pp.plane.v), 0, 1e-12);
  EXPECT_NEAR(dot(pp.plane.u, pp.plane.u), 1, 1e-12);
  const auto& u = pp.plane.u;
  const auto& v = pp.plane.v;
  std::array<double, 3> uxv{u[1] * v[2] - u[2] * v[1], u[2] * v[0] - u[0] * v[2], u[0] * v[1] - u[1] * v[0]};
  EXPECT_NEAR(dot(uxv, pp.plane.normal), 1, 1e-12);
}

TEST(OutlineIoPlane, PlanarInputKeepsItsCoordinates) {
  Cloud no_z;
  no_z.xyz = {1.25, 2.5, 0, -3, 4, 0, 7, 7, 0};
  PlanarPoints a = to_plane(no_z);
  EXPECT_FALSE(a.projected);
  Cloud flat_z = no_z;
  flat_z.has_z = true;
  for (int i = 0; i < 3; ++i) flat_z.xyz[3 * i + 2] = 812.5;
  PlanarPoints b = to_plane(flat_z);
  // A flat 3-D cloud is on its own plane z = 812.5 with the input's axes: the plane is written, x, y kept.
  ASSERT_TRUE(b.projected);
  EXPECT_EQ(b.plane.origin, (std::array<double, 3>{0, 0, 812.5}));
  EXPECT_EQ(b.plane.normal, (std::array<double, 3>{0, 0, 1}));
  EXPECT_EQ(b.plane.u, (std::array<double, 3>{1, 0, 0}));
  EXPECT_EQ(b.plane.v, (std::array<double, 3>{0, 1, 0}));
  for (int i = 0; i < 3; ++i) {
    EXPECT_EQ(a.points[i].x, no_z.xyz[3 * i]);
    EXPECT_EQ(a.points[i].y, no_z.xyz[3 * i + 1]);
    EXPECT_EQ(b.points[i].x, no_z.xyz[3 * i]);
    EXPECT_EQ(b.points[i].y, no_z.xyz[3 * i + 1]);
  }
}

TEST(OutlineIoPlane, NoisyNearlyHorizontalPlateKeepsItsAxes) {
  // Camera looking down at a plate: z noise of 0.5 on a 1000 x 600 plate, plane tilted by 1 degree.
  std::mt19937 rng(2);
  std::uniform_real_distribution<double> d(0, 1), noise(-0.5, 0.5);
  const Tilt t(std::acos(-1.0) / 180, 0);
  Cloud c;
  c.has_z = true;
  for (int i = 0; i < 5000; ++i) {
    auto q = t.apply(1000 * d(rng), 600 * d(rng), {0, 0, 1200});
    q[2] += noise(rng);
    c.xyz.insert(c.xyz.end(), q.begin(), q.end());
  }
  PlanarPoints pp = to_plane(c);
  ASSERT_TRUE(pp.projected);
  EXPECT_GT(pp.plane.u[0], 0.999);  // u is the x axis on the plane
  EXPECT_GT(pp.plane.v[1], 0.999);
  EXPECT_GT(pp.plane.normal[2], 0.999);
  EXPECT_NEAR(pp.rms_distance, 0.5 / std::sqrt(3.0), 0.02);  // RMS of uniform noise in [-0.5, 0.5]
  EXPECT_LE(pp.max_distance, 0.5 + 0.02);                    // noise bound + the fitted plane's own small error
}

TEST(OutlineIoJson, HasTheKeysAndValues) {
  Result r = two_loop_result();
  PlanarPoints planar;
  RunInfo info{"in.xyz", "xyz", false, 5.5, 0.5};
  auto j = outline_json(r, planar, info);
  for (const char* key : {"points_read", "points_used", "duplicates_merged", "alpha_radius", "mode", "order",
                          "triangles", "search_cost", "time_ms", "loops"})
    EXPECT_TRUE(j.contains(key)) << key;
  EXPECT_EQ(j["points_read"], 10);
  EXPECT_EQ(j["points_used"], 9);
  EXPECT_EQ(j["duplicates_merged"], 1);
  EXPECT_EQ(j["alpha_radius"], 1.5);
  EXPECT_EQ(j["mode"], "ds");
  EXPECT_EQ(j["order"], "hilbert");
  EXPECT_EQ(j["triangles"], 8);
  EXPECT_EQ(j["search_cost"], 42);
  EXPECT_EQ(j["search_cost_locate"], 30);
  EXPECT_EQ(j["search_cost_cavity"], 12);
  EXPECT_EQ(j["time_ms"]["read"], 5.5);
  EXPECT_EQ(j["time_ms"]["triangulate"], 1.0);
  EXPECT_EQ(j["time_ms"]["alpha"], 2.0);
  EXPECT_EQ(j["time_ms"]["loops"], 3.0);
  EXPECT_EQ(j["time_ms"]["total"], 7.5);  // projection + compute_outline
  ASSERT_EQ(j["loops"].size(), 2u);
  EXPECT_EQ(j["loops"][0]["hole"], false);
  EXPECT_EQ(j["loops"][1]["hole"], true);
  EXPECT_EQ(j["loops"][1]["area"], 4.0);
  EXPECT_EQ(j["loops"][1]["perimeter"], 8.0);
  EXPECT_EQ(j["loops"][0]["points"][2], nlohmann::json::array({4.0, 4.0}));
  EXPECT_FALSE(j.contains("plane"));
  EXPECT_FALSE(j["loops"][0].contains("points_3d"));

  // 3-D input: plane and points_3d on it.
  planar.projected = true;
  planar.plane = {{10, 20, 30}, {0, 0, 1}, {0, 1, 0}, {-1, 0, 0}};
  auto j3 = outline_json(r, planar, info);
  ASSERT_TRUE(j3.contains("plane"));
  EXPECT_EQ(j3["plane"]["origin"], nlohmann::json::array({10.0, 20.0, 30.0}));
  EXPECT_EQ(j3["plane"]["normal"], nlohmann::json::array({0.0, 0.0, 1.0}));
  // (4, 4) in the plane = origin + 4 u + 4 v = (10 - 4, 20 + 4, 30).
  EXPECT_EQ(j3["loops"][0]["points_3d"][2], nlohmann::json::array({6.0, 24.0, 30.0}));
}

TEST(OutlineIoWriters, TriangleListOnePerLine) {
  EXPECT_EQ(triangles_text(two_loop_result()), "0 1 2\n2 3 0\n4 8 5\n");
}

TEST(OutlineIoWriters, StagedFilesAreWholeOrAbsent) {
  const fs::path dir = fs::temp_directory_path() / ("hg_outline_io_test_" + std::to_string(::getpid()));
  fs::remove_all(dir);
  fs::create_directories(dir);
  {
    std::ofstream(dir / "keep.json") << "old";
    StagedFiles f;
    f.stage((dir / "keep.json").string(), std::string("new"));
    f.stage((dir / "b.txt").string(), std::string("bbb"));
    // Not committed: the old file stays, the new one never appears, no temp file is left.
  }
  EXPECT_EQ(read_all(dir / "keep.json"), "old");
  EXPECT_FALSE(fs::exists(dir / "b.txt"));
  EXPECT_EQ(std::distance(fs::directory_iterator(dir), fs::directory_iterator()), 1);
  {
    StagedFiles f;
    f.stage((dir / "keep.json").string(), std::string("new"));
    f.stage((dir / "b.txt").string(), std::string("bbb"));
    f.commit();
  }
  EXPECT_EQ(read_all(dir / "keep.json"), "new");
  EXPECT_EQ(read_all(dir / "b.txt"), "bbb");
  EXPECT_EQ(std::distance(fs::directory_iterator(dir), fs::directory_iterator()), 2);
  StagedFiles f;
  EXPECT_THROW(f.stage((dir / "no" / "such" / "dir.json").string(), std::string("x")), WriteError);
  fs::remove_all(dir);
}

// The caption's R in the input's units with four significant digits: a radius in metres is not "0.0".
TEST(OutlineIoWriters, SvgCaptionPrintsTheRadius) {
  Result r = two_loop_result();
  std::vector<Vec2> pts = {{0, 0}, {0.4, 0}, {0.4, 0.4}, {0, 0.4}};
  r.alpha_radius = 0.00273431;
  EXPECT_NE(render_svg(pts, r, false).find("R = 0.002734</text>"), std::string::npos);
  r.alpha_radius = 12.5;
  EXPECT_NE(render_svg(pts, r, false).find("R = 12.5</text>"), std::string::npos);
}

TEST(OutlineIoWriters, PicturesShowPointsLoopsAndHoles) {
  Result r = two_loop_result();
  std::vector<Vec2> pts = {{0, 0}, {4, 0}, {4, 4}, {0, 4}, {1, 1}, {1, 3}, {3, 3}, {3, 1}, {2, 0}};
  std::string svg = render_svg(pts, r, true);
  EXPECT_EQ(svg.rfind("<?xml", 0), 0u);
  EXPECT_NE(svg.find("</svg>"), std::string::npos);
  std::size_t polys = 0;
  for (std::size_t at = 0; (at = svg.find("<polygon", at)) != std::string::npos; ++at) ++polys;
  EXPECT_EQ(polys, 2u);
  EXPECT_NE(svg.find("#40c4ff"), std::string::npos);  // hole colour: the station's (station/web/scene.js)
  EXPECT_NE(svg.find("9 points"), std::string::npos);

  auto png = render_png(pts, r, true);
  cv::Mat img = cv::imdecode(png, cv::IMREAD_COLOR);
  ASSERT_FALSE(img.empty());
  EXPECT_GE(std::max(img.cols, img.rows), 1150);
  EXPECT_LE(std::max(img.cols, img.rows), 1250);
  // The station's colours (station/web/scene.js): the outer edge white, holes light blue (0x40c4ff), on a
  // dark background. OpenCV's pixels are BGR.
  const auto outer_pixel = [](cv::Vec3b p) { return p[0] > 200 && p[1] > 200 && p[2] > 200; };
  const auto hole_pixel = [](cv::Vec3b p) { return p[0] > 200 && p[1] > 150 && p[1] < 230 && p[2] < 120; };
  int outer = 0, hole = 0;
  for (int y = 0; y < img.rows; ++y)
    for (int x = 0; x < img.cols; ++x) {
      auto p = img.at<cv::Vec3b>(y, x);
      outer += outer_pixel(p);
      hole += hole_pixel(p);
    }
  EXPECT_GT(outer, 4 * 1000);  // outer square, 4 sides of about 1100 px
  EXPECT_GT(hole, 4 * 500);    // hole, half the size
  // y up: a triangle with its long horizontal edge at y = 0 has that edge in the lower half of the picture.
  Result tri;
  Loop l;
  l.points = {{0, 0}, {4, 0}, {0, 4}};
  tri.loops = {l};
  cv::Mat img2 = cv::imdecode(render_png(std::vector<Vec2>{{0, 0}, {4, 0}, {0, 4}}, tri, false), cv::IMREAD_COLOR);
  int best_row = -1, best = 0;
  for (int y = 0; y < img2.rows; ++y) {
    int n = 0;
    for (int x = 0; x < img2.cols; ++x) {
      auto p = img2.at<cv::Vec3b>(y, x);
      n += outer_pixel(p);
    }
    if (n > best) best = n, best_row = y;
  }
  EXPECT_GT(best, 1000);
  EXPECT_GT(best_row, img2.rows / 2);
}

TEST(OutlineIoPlane, CoordinatesTooLargeForThePlaneFitAreAnErrorNotNaN) {
  Cloud c;
  c.has_z = true;
  c.xyz = {0, 0, 0, 1e200, 0, 1, 0, 1e200, 2, 1e200, 1e200, 3};  // squares overflow to inf
  try {
    to_plane(c, "huge.xyz");
    FAIL() << "no error";
  } catch (const ReadError& e) {
    EXPECT_EQ(std::string(e.what()).rfind("huge.xyz: coordinates too large", 0), 0u) << e.what();
  }
}
