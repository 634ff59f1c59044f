// The automatic radius against generated ground truth: noisy, holed scan grids over many seeds (global
// mode), and catalogue parts seen by a tilted camera whose spacing grows 2x and 5x across the part
// (local mode), scored by loop counts and a Hausdorff distance written here.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <random>
#include <string>
#include <vector>

#include "outline_core/alpha.hpp"
#include "tools/bench/core/synthetic_clouds.hpp"
#include "tools/bench/core/tilted_camera.hpp"
#include "outline_core/outline.hpp"
#include "sim/partgen/shapes.hpp"

using namespace hg::outline;
namespace partgen = hg::partgen;

namespace {

struct NoiseCase {
  double amp, sigma;
};
const NoiseCase kNoises[] = {{0, 0}, {0.25, 0}, {0.5, 0}, {0, 0.15}, {0, 0.3}};
struct DropCase {
  double total, clustered;
};
const DropCase kDrops[] = {{0, 0}, {0.02, 0}, {0.05, 0}, {0.05, 0.025}};

// Counts of a plate's loops against its truth: no ground truth value comes from the code under test.
void expect_plate_truth(const synth::PlateCloud& c, const Result& r, bool every_hole_found) {
  int outers = 0, spurious = 0, missed = 0;
  std::vector<int> hit(c.hole_centres.size(), 0);
  for (const Loop& L : r.loops) {
    if (!L.hole) {
      ++outers;
      continue;
    }
    bool real = false;
    for (std::size_t k = 0; k < c.hole_centres.size(); ++k)
      if (synth::inside_polygon(L.points, c.hole_centres[k])) real = true, hit[k] = 1;
    spurious += !real;
  }
  for (int h : hit) missed += !h;
  EXPECT_EQ(outers, 1);
  EXPECT_EQ(spurious, 0);
  if (every_hole_found) {
    EXPECT_EQ(missed, 0);
  }
}

// Distance from p to segment ab.
double segment_distance(const partgen::Vec2& p, const partgen::Vec2& a, const partgen::Vec2& b) {
  const partgen::Vec2 ab = b - a;
  const double t = std::clamp((p - a).dot(ab) / ab.squaredNorm(), 0.0, 1.0);
  return (a + t * ab - p).norm();
}

double ring_distance(const partgen::Vec2& p, const std::vector<partgen::Vec2>& ring) {
  double d = 1e300;
  for (std::size_t i = 0; i < ring.size(); ++i)
    d = std::min(d, segment_distance(p, ring[i], ring[(i + 1) % ring.size()]));
  return d;
}

// Directed distances both ways between the outline and the truth boundary, each divided by the local
// spacing (the longer side of the camera's pixel footprint there); returns the larger maximum.
double relative_hausdorff(const synth::TiltedView& view, const std::vector<Loop>& loops) {
  std::vector<std::vector<partgen::Vec2>> ours, truth{view.truth.outer};
  for (const auto& h : view.truth.holes) truth.push_back(h);
  for (const Loop& L : loops) {
    ours.emplace_back();
    for (const Vec2& p : L.points) ours.back().push_back({p.x, p.y});
  }
  auto to_set = [](const partgen::Vec2& p, const std::vector<std::vector<partgen::Vec2>>& rings) {
    double d = 1e300;
    for (const auto& r : rings) d = std::min(d, ring_distance(p, r));
    return d;
  };
  double worst = 0;
  for (const auto& ring : ours)
    for (const partgen::Vec2& p : ring) worst = std::max(worst, to_set(p, truth) / view.spacing(p, true));
  for (const auto& ring : truth)  // the truth boundary sampled at a quarter of the local spacing
    for (std::size_t i = 0; i < ring.size(); ++i) {
      const partgen::Vec2 a = ring[i], b = ring[(i + 1) % ring.size()];
      const double step = view.spacing(a, false) / 4;
      const int n = std::max(1, int(std::ceil((b - a).norm() / step)));
      for (int k = 0; k < n; ++k) {
        const partgen::Vec2 p = a + (b - a) * (double(k) / n);
        worst = std::max(worst, to_set(p, ours) / view.spacing(p, true));
      }
    }
  return worst;
}

}  // namespace

TEST(OutlineAutoRadius, NoisyPlatesOverManySeedsGiveTheirTrueLoops) {
  // Guarantee of docs/outline-auto-radius.md, default options: one outer loop, no spurious hole (random
  // dropout up to 5 %, 3x3 dropout gaps), every cut-out 6 spacings wide or more found; noise up to +-0.5
  // spacing uniform or sigma 0.3. About 2 k and 17 k points.
  struct Size {
    int W, H, seeds;
    std::vector<double> holes;
  };
  const Size sizes[] = {{60, 34, 12, {6, 8}}, {170, 100, 3, {6, 7, 9, 12, 20}}};
  for (const Size& sz : sizes)
    for (const NoiseCase& n : kNoises)
      for (const DropCase& d : kDrops)
        for (int s = 0; s < sz.seeds; ++s) {
          synth::PlateSpec spec;
          spec.W = sz.W, spec.H = sz.H, spec.hole_diameters = sz.holes;
          spec.uniform_amp = n.amp, spec.gauss_sigma = n.sigma, spec.dropout = d.total, spec.clustered = d.clustered;
          spec.seed = 7000 + 31 * s + sz.W;
          SCOPED_TRACE(std::to_string(sz.W) + "x" + std::to_string(sz.H) + " amp " + std::to_string(n.amp) + " sigma " +
                       std::to_string(n.sigma) + " dropout " + std::to_string(d.total) + " clustered " +
                       std::to_string(d.clustered) + " seed " + std::to_string(spec.seed));
          const synth::PlateCloud c = synth::make_plate(spec);
          if (d.clustered > 0) {
            ASSERT_GT(c.clusters, 0);
          }
          const Result r = compute_outline(c.points);
          expect_plate_truth(c, r, true);
          // Without noise every 3x3 gap (circumradius 2 spacings > R) is a hole of the alpha shape: dropped.
          if (n.amp == 0 && n.sigma == 0) {
            EXPECT_GE(r.holes_dropped, std::size_t(c.clusters));
          }
        }
}

TEST(OutlineAutoRadius, WithoutTheHoleRuleEveryHoleFourSpacingsWideIsFoundAndDropoutMakesNone) {
  // Random dropout only (no 3x3 gaps): the radius alone opens every cut-out of 4 spacings and more, at
  // any position, and random dropout opens no hole even at +-0.5 spacing noise.
  for (const NoiseCase& n : kNoises)
    for (const DropCase& d : {kDrops[0], kDrops[1], kDrops[2]})
      for (int s = 0; s < 4; ++s) {
        synth::PlateSpec spec;
        spec.W = 150, spec.H = 60, spec.hole_diameters = {4, 4, 4.5, 5, 6};
        spec.uniform_amp = n.amp, spec.gauss_sigma = n.sigma, spec.dropout = d.total;
        spec.seed = 9100 + s;
        SCOPED_TRACE("amp " + std::to_string(n.amp) + " sigma " + std::to_string(n.sigma) + " dropout " +
                     std::to_string(d.total) + " seed " + std::to_string(spec.seed));
        const synth::PlateCloud c = synth::make_plate(spec);
        Options o;
        o.min_hole_spacings = 0;
        const Result r = compute_outline(c.points, o);
        expect_plate_truth(c, r, true);
      }
}

TEST(OutlineAutoRadius, StronglyNoisyPlatesGiveTheirTrueLoops) {
  // Noise of 0.45 to 1.3 spacings (Gaussian sigma) with 2 % dropout, about 29 k points: the cloud is
  // nearly a random set, whose empty circles pass 1.7 h, so the automatic k rises with the measured
  // irregularity q (docs/outline-auto-radius.md). One outer loop, every cut-out (10 spacings and more)
  // found, no spurious hole, against the generator's truth.
  for (const double sigma : {0.45, 0.7, 1.0, 1.3})
    for (int s = 0; s < 3; ++s) {
      synth::PlateSpec spec;
      spec.W = 200, spec.H = 150, spec.hole_diameters = {10, 16, 24};
      spec.gauss_sigma = sigma, spec.dropout = 0.02;
      spec.seed = 9400 + 17 * s;
      SCOPED_TRACE("sigma " + std::to_string(sigma) + " seed " + std::to_string(spec.seed));
      const synth::PlateCloud c = synth::make_plate(spec);
      const Result r = compute_outline(c.points);
      expect_plate_truth(c, r, true);
    }
}

TEST(OutlineAutoRadius, UniformRandomPointsInASquareGiveOneLoopAndNoHole) {
  // A Poisson-like set (uniform random full-precision doubles in a square, no grid at all): the truth is
  // the square, one loop without holes, whatever the seed.
  for (const std::size_t n : {std::size_t(2000), std::size_t(30000)})
    for (int s = 0; s < 4; ++s) {
      std::mt19937_64 rng(9500 + s);
      std::uniform_real_distribution<double> coordinate(-3.7, 5.1);
      std::vector<Vec2> points(n);
      for (Vec2& p : points) p = {coordinate(rng), coordinate(rng)};
      SCOPED_TRACE("n " + std::to_string(n) + " seed " + std::to_string(9500 + s));
      const Result r = compute_outline(points);
      ASSERT_EQ(r.loops.size(), 1u);
      EXPECT_FALSE(r.loops[0].hole);
      EXPECT_GT(r.loops[0].area, 0.9 * 8.8 * 8.8);  // the square, not a fragment of it
    }
}

TEST(OutlineAutoRadius, ThreeByThreeGapIsExactlyAFourSpacingHoleOnAGridPoint) {
  // The boundary case, stated in the doc: a diameter-4 hole centred on a grid point removes the same 9
  // points as a 3x3 dropout gap, so the default rule drops it, and keeps it with the rule off.
  synth::PlateSpec spec;
  spec.W = 80, spec.H = 40, spec.hole_diameters = {4};
  spec.holes_on_grid_points = true;
  const synth::PlateCloud c = synth::make_plate(spec);
  ASSERT_EQ(c.points.size(), std::size_t(80 * 40 - 9));
  const Result r = compute_outline(c.points);
  EXPECT_EQ(r.loops.size(), 1u);
  EXPECT_EQ(r.holes_dropped, 1u);
  Options o;
  o.min_hole_spacings = 0;
  const Result all = compute_outline(c.points, o);
  ASSERT_EQ(all.loops.size(), 2u);
  ASSERT_TRUE(all.loops[1].hole);
  EXPECT_TRUE(synth::inside_polygon(all.loops[1].points, c.hole_centres[0]));
  EXPECT_LT(all.loops[1].area, 16.0);  // inside the 4 x 4 square through the ring of remaining points
}

TEST(OutlineAutoRadius, LocalModeFollowsATiltedCamerasSpacing) {
  // Every catalogue part seen with its spacing growing 2x and 5x from the near to the far side: local mode
  // gives one outer loop and the part's holes, each boundary within 2 local spacings of the truth.
  for (double gradient : {2.0, 5.0})
    for (const partgen::Shape& shape : partgen::catalogue()) {
      SCOPED_TRACE(shape.name + " gradient " + std::to_string(gradient));
      const synth::TiltedView view = synth::tilted_view(shape, gradient, 20000, 0.2, 3);
      EXPECT_NEAR(view.spacing_far / view.spacing_near, gradient, 0.05 * gradient);
      Options o;
      o.alpha_mode = AlphaMode::Local;
      const Result r = compute_outline(view.points, o);
      int outers = 0, holes = 0;
      for (const Loop& L : r.loops) (L.hole ? holes : outers)++;
      EXPECT_EQ(outers, 1);
      EXPECT_EQ(holes, int(view.truth.holes.size()));
      EXPECT_LT(relative_hausdorff(view, r.loops), 2.0);
    }
}

TEST(OutlineAutoRadius, LocalModeGivesTheSameLoopsForEveryModeAndOrder) {
  // R_t depends on the triangle's vertex set only: the loops may not depend on how the points were
  // inserted (jittered tilted view: points in general position, so the triangulation is unique).
  const synth::TiltedView view = synth::tilted_view(partgen::make_shape("trapezoid-holes"), 5, 8000, 0.3, 5);
  Options o;
  o.alpha_mode = AlphaMode::Local;
  const Result ref = compute_outline(view.points, o);
  for (Mode m : {Mode::Ordinary, Mode::DS, Mode::DSHI})
    for (Order ord : {Order::AsIs, Order::Hilbert, Order::Brio}) {
      SCOPED_TRACE(std::string(to_string(m)) + " " + to_string(ord));
      o.mode = m, o.order = ord;
      const Result r = compute_outline(view.points, o);
      ASSERT_EQ(r.loops.size(), ref.loops.size());
      for (std::size_t k = 0; k < r.loops.size(); ++k) EXPECT_EQ(r.loops[k].point_index, ref.loops[k].point_index);
      EXPECT_EQ(r.holes_dropped, ref.holes_dropped);
    }
}

TEST(OutlineAutoRadius, LocalRadiusIsASymmetricFunctionOfTheVertexSet) {
  const std::vector<float> s{1.0f, 2.5f, 0.75f, 2.5f};
  const std::uint32_t tri[][3] = {{0, 1, 2}, {0, 2, 1}, {1, 0, 2}, {1, 2, 0}, {2, 0, 1}, {2, 1, 0}};
  for (const auto& t : tri) EXPECT_EQ(local_radius(s, 1.7, t[0], t[1], t[2]), 1.7 * 1.0);  // the middle value
  EXPECT_EQ(local_radius(s, 2.0, 1, 3, 2), 5.0);
}

TEST(OutlineAutoRadius, LocalModeRefusesAnExplicitRadius) {
  Options o;
  o.alpha_mode = AlphaMode::Local;
  o.alpha_radius = 1;
  EXPECT_THROW(compute_outline(std::vector<Vec2>{{0, 0}, {1, 0}, {0, 1}}, o), OutlineError);
  EXPECT_THROW(parse_alpha_mode("tilted"), OutlineError);
  EXPECT_EQ(parse_alpha_mode("local"), AlphaMode::Local);
}
