// Cloud synthesis: scan-line order, agreement with a brute-force pixel test, the paper's point counts,
// noise/dropout/jagged statistics, determinism.
#include "sim/partgen/presets.hpp"
#include "sim/partgen/shapes.hpp"
#include "sim/partgen/synth.hpp"

#include <gtest/gtest.h>

#include <Eigen/Geometry>

#include <algorithm>
#include <cmath>
#include <map>
#include <numbers>
#include <set>

using namespace hg::partgen;
namespace {
constexpr double deg = std::numbers::pi / 180;

void expect_scan_order(const Cloud& c) {
  for (size_t i = 1; i < c.size(); ++i) {
    ASSERT_GE(c.pixel_row[i], c.pixel_row[i - 1]) << "point " << i;
    if (c.pixel_row[i] == c.pixel_row[i - 1]) {
      ASSERT_GT(c.pixel_col[i], c.pixel_col[i - 1]) << "point " << i;
    }
  }
}
}  // namespace

TEST(PartgenSynth, NoiseFreeCloudIsScanOrderedGridOfPixelCentres) {
  const Scene scene = single_part_scene(make_shape("plate-hole-slot"), 3 * deg);
  CloudOptions o;
  o.pitch = 0.004;
  const Cloud c = synthesize(scene, o);
  ASSERT_GT(c.size(), 1000u);
  expect_scan_order(c);
  for (size_t i = 1; i < c.size(); ++i) {
    const double y0 = c.xyz[3 * i - 2], y1 = c.xyz[3 * i + 1], x0 = c.xyz[3 * i - 3], x1 = c.xyz[3 * i];
    if (c.pixel_row[i] == c.pixel_row[i - 1]) {
      ASSERT_EQ(y1, y0);  // one row is one y
      ASSERT_GT(x1, x0);  // left to right
    } else {
      ASSERT_LT(y1, y0);  // the next row is lower: top to bottom
    }
    ASSERT_EQ(c.xyz[3 * i + 2], 0.012);  // z = plate thickness exactly without depth noise
  }
  // Pixel centres lie on the table-anchored lattice (k + 1/2) pitch.
  for (size_t i = 0; i < c.size(); i += 97) {
    const double kx = c.xyz[3 * i] / o.pitch - 0.5, ky = c.xyz[3 * i + 1] / o.pitch - 0.5;
    EXPECT_NEAR(kx, std::round(kx), 1e-6);
    EXPECT_NEAR(ky, std::round(ky), 1e-6);
  }
}

TEST(PartgenSynth, PointsAreExactlyThePixelCentresInsideTheParts) {
  // Brute force over every pixel of the grid with contains(): the rasteriser must agree pixel for pixel,
  // on a rotated single part and on the multi-part scene.
  std::vector<std::pair<Scene, double>> cases;
  for (const Shape& s : catalogue()) cases.emplace_back(single_part_scene(s, 11 * deg), 0.0037);
  cases.emplace_back(demo_scene(), 0.006);
  for (const auto& [scene, pitch] : cases) {
    SCOPED_TRACE(scene.parts[0].shape.name + " parts " + std::to_string(scene.parts.size()));
    CloudOptions o;
    o.pitch = pitch;
    const Cloud c = synthesize(scene, o);
    std::set<std::pair<int, int>> got;
    for (size_t i = 0; i < c.size(); ++i) {
      got.insert({c.pixel_row[i], c.pixel_col[i]});
      const PlacedPart& part = scene.parts.at(c.part[i]);
      ASSERT_TRUE(contains(part.placed, c.xyz[3 * i], c.xyz[3 * i + 1])) << "point " << i << " outside its part";
      ASSERT_EQ(c.xyz[3 * i + 2], part.shape.thickness);
    }
    ASSERT_EQ(got.size(), c.size());
    size_t expected = 0;
    for (int r = 0; r < c.grid.rows; ++r)
      for (int k = 0; k < c.grid.cols; ++k) {
        bool in = false;
        for (const PlacedPart& p : scene.parts) in = in || contains(p.placed, c.grid.x(k), c.grid.y(r));
        if (!in) continue;
        ++expected;
        ASSERT_TRUE(got.count({r, k})) << "interior pixel " << r << "," << k << " missing";
      }
    EXPECT_EQ(expected, c.size());
    EXPECT_EQ(count_pixel_centres(scene, pitch), c.size());
    // With no noise the count approximates area / pitch^2 to within the boundary pixels.
    const double ideal = scene.total_area() / (pitch * pitch), boundary = scene.total_perimeter() / pitch;
    EXPECT_NEAR(double(c.size()), ideal, boundary);
  }
}

TEST(PartgenSynth, PresetCountsMatchThePaperWithinThreePercent) {
  // The paper's Tables 1, 4 and 6, typed from the paper.
  const std::map<std::string, double> paper = {
      {"low-1", 3716},     {"low-2", 3161},    {"low-3", 2179},    {"low-4", 8258},    {"low-5", 8828},
      {"low-6", 8696},     {"high-1", 763685}, {"high-2", 513513}, {"high-3", 406434}, {"high-4", 1591649},
      {"high-5", 1015985}, {"high-6", 997571}, {"down-1", 17604},  {"down-2", 16295},  {"down-3", 12263},
      {"down-4", 17130},   {"down-5", 15531},  {"down-6", 14809}};
  ASSERT_EQ(presets().size(), paper.size());
  for (const auto& [name, n] : paper) {
    const Preset& p = find_preset(name);
    const Cloud c = synthesize(preset_scene(p), preset_options(p));
    EXPECT_LE(std::abs(double(c.size()) - n), 0.03 * n) << name << ": " << c.size() << " points, paper " << n;
    if (name.rfind("high", 0) == 0) continue;
    expect_scan_order(c);
  }
  // Same physical piece in every table: same shape and rotation, only the pitch changes.
  for (int k = 1; k <= 6; ++k) {
    const Preset& lo = find_preset("low-" + std::to_string(k));
    const Preset& hi = find_preset("high-" + std::to_string(k));
    EXPECT_EQ(lo.shape, hi.shape);
    EXPECT_EQ(lo.rotation_deg, hi.rotation_deg);
    EXPECT_LT(hi.pitch, lo.pitch);
  }
  EXPECT_THROW(find_preset("low-7"), std::invalid_argument);
}

TEST(PartgenSynth, DropoutFractionIsBinomial) {
  const Scene scene = single_part_scene(make_shape("trapezoid-holes"), 4 * deg);
  CloudOptions o;
  o.pitch = 0.001;
  const size_t all = synthesize(scene, o).size();
  for (double f : {0.02, 0.3}) {
    o.dropout = f;
    o.seed = 7;
    const Cloud c = synthesize(scene, o);
    ASSERT_EQ(c.candidates, all);
    const double mean = all * (1 - f), sigma = std::sqrt(all * f * (1 - f));
    EXPECT_NEAR(double(c.size()), mean, 3 * sigma) << "dropout " << f;
    expect_scan_order(c);
  }
  o.dropout = 1.0;
  EXPECT_EQ(synthesize(scene, o).size(), 0u);
}

TEST(PartgenSynth, NoiseHasTheRequestedSigma) {
  const Scene scene = single_part_scene(make_shape("ring-flange"), 0);
  CloudOptions o;
  o.pitch = 0.002;
  o.in_plane_sigma = 0.0004;
  o.depth_sigma = 0.0007;
  o.seed = 99;
  const Cloud c = synthesize(scene, o);
  const size_t n = c.size();
  ASSERT_GT(n, 20000u);
  double s[3] = {0, 0, 0}, ss[3] = {0, 0, 0};
  for (size_t i = 0; i < n; ++i) {
    const double d[3] = {c.xyz[3 * i] - c.grid.x(c.pixel_col[i]), c.xyz[3 * i + 1] - c.grid.y(c.pixel_row[i]),
                         c.xyz[3 * i + 2] - 0.025};
    for (int k = 0; k < 3; ++k) {
      s[k] += d[k];
      ss[k] += d[k] * d[k];
    }
  }
  const double sig[3] = {o.in_plane_sigma, o.in_plane_sigma, o.depth_sigma};
  for (int k = 0; k < 3; ++k) {
    const double mean = s[k] / n, var = ss[k] / n - mean * mean, v = sig[k] * sig[k];
    EXPECT_NEAR(mean, 0.0, 4 * sig[k] / std::sqrt(double(n))) << "axis " << k;
    // Sample variance of a normal has standard deviation v sqrt(2 / (n - 1)).
    EXPECT_NEAR(var, v, 4 * v * std::sqrt(2.0 / (n - 1))) << "axis " << k;
  }
  // Noise does not change which pixels are seen.
  CloudOptions clean = o;
  clean.in_plane_sigma = clean.depth_sigma = 0;
  EXPECT_EQ(synthesize(scene, clean).size(), n);
}

TEST(PartgenSynth, JaggedEdgesKeepTheAreaOnAverage) {
  // Edge pixels kept with probability = covered fraction: the expected count is area / pitch^2 exactly,
  // with binomial spread over at most ~2 perimeter / pitch edge pixels.
  for (const Shape& s : catalogue()) {
    SCOPED_TRACE(s.name);
    const Scene scene = single_part_scene(s, 13 * deg);
    CloudOptions o;
    o.pitch = 0.0025;
    o.jagged = true;
    o.seed = 5;
    const Cloud c = synthesize(scene, o);
    expect_scan_order(c);
    const double ideal = s.exact_area / (o.pitch * o.pitch), edge_pixels = 2 * s.exact_perimeter / o.pitch;
    EXPECT_NEAR(c.expected_points, ideal, edge_pixels / 64 + 1);  // coverage sampled on 8 sub-lines
    EXPECT_NEAR(double(c.size()), ideal, 4 * std::sqrt(edge_pixels / 4) + edge_pixels / 64);
    // It is really random at the edge: a different seed gives a different cloud of similar size.
    o.seed = 6;
    const Cloud d = synthesize(scene, o);
    EXPECT_NE(c.pixel_col, d.pixel_col);
    // Jagged adds only edge pixels: an added pixel has a pixel centre inside the part within 3 pixels
    // (the sharpest corner, 45 degrees, holds a lattice point within 2.6 pixels of its tip).
    CloudOptions centres;
    centres.pitch = o.pitch;
    const Cloud strict = synthesize(scene, centres);
    std::set<std::pair<int, int>> inside;
    for (size_t i = 0; i < strict.size(); ++i) inside.insert({strict.pixel_row[i], strict.pixel_col[i]});
    size_t added = 0;
    for (size_t i = 0; i < c.size(); ++i) {
      if (inside.count({c.pixel_row[i], c.pixel_col[i]})) continue;
      ++added;
      bool near = false;
      for (int dr = -3; dr <= 3 && !near; ++dr)
        for (int dc = -3; dc <= 3 && !near; ++dc) near = inside.count({c.pixel_row[i] + dr, c.pixel_col[i] + dc}) > 0;
      EXPECT_TRUE(near);
    }
    EXPECT_GT(added, 0u);
  }
}

TEST(PartgenSynth, SameSeedSameCloudDifferentSeedDifferentNoise) {
  const Scene scene = single_part_scene(make_shape("collar-notch"), -5 * deg);
  CloudOptions o;
  o.pitch = 0.003;
  o.in_plane_sigma = 0.0003;
  o.depth_sigma = 0.0005;
  o.dropout = 0.05;
  o.jagged = true;
  o.seed = 1234;
  const Cloud a = synthesize(scene, o), b = synthesize(scene, o);
  EXPECT_EQ(a.xyz, b.xyz);
  EXPECT_EQ(a.pixel_row, b.pixel_row);
  o.seed = 1235;
  EXPECT_NE(synthesize(scene, o).xyz, a.xyz);
  // The generators are ours, so the first values are fixed across standard libraries: mt19937_64's
  // 10000th output is fixed by the C++ standard ([rand.predef]).
  std::mt19937_64 ref;
  ref.discard(9999);
  EXPECT_EQ(ref(), 9981545732273789042ull);
  Rng r(5489u);  // default seed of mt19937_64: uniform() is the top 53 bits of its first output
  std::mt19937_64 ref2;
  EXPECT_EQ(r.uniform(), double(ref2() >> 11) / 9007199254740992.0);
}

TEST(PartgenSynth, NormalGeneratorMomentsAndRange) {
  Rng r(3);
  const int n = 200000;
  double s = 0, ss = 0, s4 = 0;
  int within1 = 0;
  for (int i = 0; i < n; ++i) {
    const double v = r.normal();
    s += v;
    ss += v * v;
    s4 += v * v * v * v;
    within1 += std::abs(v) < 1;
  }
  EXPECT_NEAR(s / n, 0, 4 / std::sqrt(double(n)));
  EXPECT_NEAR(ss / n, 1, 4 * std::sqrt(2.0 / n));
  EXPECT_NEAR(s4 / n, 3, 4 * std::sqrt(96.0 / n));  // E v^4 = 3, Var v^4 = 105 - 9
  const double p1 = std::erf(1 / std::sqrt(2.0));   // P(|v| < 1) = 0.6827
  EXPECT_NEAR(double(within1) / n, p1, 4 * std::sqrt(p1 * (1 - p1) / n));
}

TEST(PartgenSynth, BadOptionsAreClearErrors) {
  const Scene scene = single_part_scene(make_shape("l-bracket"));
  CloudOptions o;
  o.pitch = 0;
  EXPECT_THROW(synthesize(scene, o), std::invalid_argument);
  o.pitch = 1e-7;  // 3000 x 2000 m^2 of pixels at 0.1 um
  EXPECT_THROW(synthesize(scene, o), std::invalid_argument);
  o.pitch = 0.002;
  o.dropout = 1.5;
  EXPECT_THROW(synthesize(scene, o), std::invalid_argument);
  o.dropout = 0;
  o.in_plane_sigma = -1;
  EXPECT_THROW(synthesize(scene, o), std::invalid_argument);
  EXPECT_THROW(synthesize(Scene{}, CloudOptions{}), std::invalid_argument);
}

TEST(PartgenSynth, FitPitchHitsTarget) {
  const Scene scene = single_part_scene(make_shape("knee-scallop"), 7 * deg);
  for (size_t target : {500u, 5000u, 50000u}) {
    const double p = fit_pitch(scene, target);
    const double n = double(count_pixel_centres(scene, p));
    EXPECT_LE(std::abs(n - target), 0.01 * target) << target;
  }
}

// The staircase of a rotated rectangle and of a circle: every vertex a pixel centre within pitch/sqrt(2)
// of the ring, each step to a neighbouring pixel (one pitch in x, y or both), no step straight back, and
// the enclosed area within half a pitch times the perimeter of the ring's.
TEST(PartgenSynth, PixelStaircaseStepsThroughNeighbouringPixelCentresAlongTheRing) {
  const double p = 0.001;
  Ring rect;
  for (const Vec2& q : {Vec2(-0.1, -0.05), Vec2(0.1, -0.05), Vec2(0.1, 0.05), Vec2(-0.1, 0.05)})
    rect.push_back(Eigen::Rotation2Dd(0.3) * q + Vec2(0.0123, 0.0456));
  Ring circle;
  for (int k = 0; k < 720; ++k)
    circle.push_back(Vec2(0.3, 0.2) + 0.04 * Vec2(std::cos(k * deg / 2), std::sin(k * deg / 2)));
  for (const Ring* ring : {&rect, &circle}) {
    const Ring s = pixel_staircase(*ring, p);
    ASSERT_GT(s.size(), 100u);
    double perimeter = 0;
    for (size_t i = 0; i < ring->size(); ++i) perimeter += ((*ring)[(i + 1) % ring->size()] - (*ring)[i]).norm();
    for (size_t i = 0; i < s.size(); ++i) {
      const Vec2 v = s[i], next = s[(i + 1) % s.size()], prev = s[(i + s.size() - 1) % s.size()];
      EXPECT_NEAR(std::remainder(v.x() / p - 0.5, 1.0), 0.0, 1e-6) << i;
      EXPECT_NEAR(std::remainder(v.y() / p - 0.5, 1.0), 0.0, 1e-6) << i;
      const Vec2 step = next - v;
      EXPECT_NEAR(std::max(std::abs(step.x()), std::abs(step.y())), p, 1e-9) << i;
      EXPECT_GT((next - prev).norm(), 1e-9) << "step back at " << i;
      double d = 1e9;
      for (size_t k = 0; k < ring->size(); ++k) {
        const Vec2 a = (*ring)[k], ab = (*ring)[(k + 1) % ring->size()] - a;
        d = std::min(d, (a + std::clamp((v - a).dot(ab) / ab.squaredNorm(), 0.0, 1.0) * ab - v).norm());
      }
      EXPECT_LE(d, p / std::sqrt(2.0) + 1e-9) << i;
    }
    EXPECT_NEAR(std::abs(signed_area(s)), std::abs(signed_area(*ring)), 0.5 * p * perimeter);
  }
}
