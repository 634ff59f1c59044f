// Exactness for the points as given: full-precision doubles (every mantissa bit used), ulp-level
// neighbours, points on circles and rotated lattices rounded to doubles, rescaled copies, near-collinear
// runs and a large clustered set in map coordinates. Every mode and order; the independent GMP checker
// (exact_checker.hpp) proves the triangulation exactly Delaunay for the input coordinates and covering
// their convex hull, and the number of points used must be the number of distinct input points
// (counted here with a std::set of the values, -0.0 and 0.0 being one number).
#include <gtest/gtest.h>

#include <cmath>
#include <numbers>
#include <random>
#include <set>
#include <string>
#include <utility>
#include <vector>

#include "exact_checker.hpp"
#include "outline_core/delaunay.hpp"
#include "outline_core/outline.hpp"

using namespace hg::outline;
using namespace hg::outline::testing;

namespace {

std::size_t distinct_points(const std::vector<Vec2>& pts) {
  std::set<std::pair<double, double>> s;
  for (const Vec2& p : pts)
    if (std::isfinite(p.x) && std::isfinite(p.y)) s.insert({p.x + 0.0, p.y + 0.0});
  return s.size();
}

// Every mode (Ordinary only up to `ordinary_limit` points: it is quadratic) and order.
void expect_exact(const std::vector<Vec2>& pts, const std::string& name, std::size_t ordinary_limit = 3000) {
  SCOPED_TRACE(name);
  const std::size_t distinct = distinct_points(pts);
  for (Mode m : {Mode::Ordinary, Mode::DS, Mode::DSHI}) {
    if (m == Mode::Ordinary && pts.size() > ordinary_limit) continue;
    for (Order o : {Order::AsIs, Order::Hilbert, Order::Brio}) {
      SCOPED_TRACE(std::string(to_string(m)) + " " + to_string(o));
      const Triangulation T = triangulate(pts, m, o);
      EXPECT_EQ(check_delaunay(pts, T), "");
      EXPECT_EQ(T.inserted, distinct);
    }
  }
  Options opt;
  opt.alpha_radius = 0;  // automatic
  EXPECT_EQ(compute_outline(pts, opt).points_used, distinct);
}

// Uniform in [lo, lo + span) per axis: at these offsets every mantissa bit is random.
std::vector<Vec2> full_mantissa_cloud(std::size_t n, std::uint64_t seed, Vec2 lo, double span) {
  std::mt19937_64 rng(seed);
  std::uniform_real_distribution<double> u(0, 1);
  std::vector<Vec2> p(n);
  for (auto& q : p) q = {lo.x + span * u(rng), lo.y + span * u(rng)};
  return p;
}

// A double with all 52 mantissa bits random, of either sign, magnitude log-uniform in [2^-40, 1) * scale:
// small coordinates then carry bits far below the large ones' ulps (unlike lo + span * u, whose values
// all lie on the grid of lo's ulp).
double full_precision(std::mt19937_64& rng, double scale) {
  std::uniform_int_distribution<std::uint64_t> mant(0, (std::uint64_t{1} << 52) - 1);
  std::uniform_int_distribution<int> expo(-41, -1), sign(0, 1);
  const double m = 1.0 + std::ldexp(static_cast<double>(mant(rng)), -52);  // exact: 53 bits
  return (sign(rng) ? -1.0 : 1.0) * std::ldexp(m, expo(rng)) * scale;      // scale: a power of ten, rounds
}

std::vector<Vec2> full_precision_cloud(std::size_t n, std::uint64_t seed, double scale) {
  std::mt19937_64 rng(seed);
  std::vector<Vec2> p(n);
  for (auto& q : p) q = {full_precision(rng, scale), full_precision(rng, scale)};
  return p;
}

// Random points across the axes (full-precision coordinates, as above), each followed by copies 1 to 3
// ulps away in x, y or both, plus exact repeats and signed zeros.
std::vector<Vec2> ulp_neighbours(std::size_t n, std::uint64_t seed) {
  std::mt19937_64 rng(seed);
  std::uniform_int_distribution<int> steps(1, 3), axis(0, 2);
  std::vector<Vec2> p;
  for (std::size_t i = 0; i < n; ++i) {
    const Vec2 b{full_precision(rng, 1.0) + (i % 2 ? 0.3 : 0.0), full_precision(rng, 1.0)};
    p.push_back(b);
    Vec2 c = b;
    const int a = axis(rng);
    for (int k = steps(rng); k > 0; --k) {
      if (a != 1) c.x = std::nextafter(c.x, INFINITY);
      if (a != 0) c.y = std::nextafter(c.y, -INFINITY);
    }
    p.push_back(c);
    if (i % 7 == 0) p.push_back(b);  // an exact repeat: one point
  }
  p.push_back({0.0, 0.5});
  p.push_back({-0.0, 0.5});   // equal to the previous as numbers: one point
  p.push_back({1e-20, 0.5});  // tiny, far below the others' ulps: a different point
  std::shuffle(p.begin(), p.end(), rng);
  return p;
}

// n points on three quarters of the unit circle around the origin (cos, sin rounded to doubles: the
// small ones carry low-order bits) and the centre; the arc moves the centroid away from the origin.
std::vector<Vec2> circle_points(std::size_t n, std::uint64_t seed) {
  std::mt19937_64 rng(seed);
  std::uniform_real_distribution<double> phase(0, 7);
  const double ph = phase(rng);
  std::vector<Vec2> p{{0, 0}};
  for (std::size_t k = 0; k < n; ++k) {
    const double t = ph + 1.5 * std::numbers::pi * static_cast<double>(k) / static_cast<double>(n);
    p.push_back({std::cos(t), std::sin(t)});
  }
  return p;
}

// A lattice of spacing 0.1 (rounded) rotated by a random angle about the origin, off-centre.
std::vector<Vec2> rotated_lattice(int side, std::uint64_t seed) {
  std::mt19937_64 rng(seed);
  std::uniform_real_distribution<double> angle(0.01, 1.5);
  const double a = angle(rng), ca = std::cos(a), sa = std::sin(a);
  std::vector<Vec2> p;
  for (int i = -side / 4; i < side - side / 4; ++i)
    for (int j = -side / 3; j < side - side / 3; ++j) {
      const double x = i * 0.1, y = j * 0.1;
      p.push_back({ca * x - sa * y, sa * x + ca * y});
    }
  return p;
}

std::vector<Vec2> scaled(std::vector<Vec2> p, double s) {
  for (Vec2& q : p) q = {q.x * s, q.y * s};
  return p;
}

}  // namespace

TEST(OutlineExactInput, FullMantissaCloudsFarFromTheOrigin) {
  for (std::uint64_t seed = 1; seed <= 5; ++seed)
    for (double offset : {1e6, 1e7}) {
      expect_exact(full_mantissa_cloud(300, seed, {offset, 0.7 * offset}, 1e3),
                   "1e3 span at " + std::to_string(offset));
      expect_exact(full_mantissa_cloud(300, seed + 100, {offset, -offset}, 1e-3),
                   "1e-3 span at " + std::to_string(offset));
      // Across the axes: the smallest coordinates have bits far below the largest ones' ulps.
      expect_exact(full_precision_cloud(300, seed + 200, offset),
                   "full precision across 0, scale " + std::to_string(offset));
    }
}

TEST(OutlineExactInput, UlpNeighboursAreDistinctPoints) {
  for (std::uint64_t seed = 1; seed <= 5; ++seed)
    for (double s : {1.0, 1e-9, 1e-2, 1e2, 1e9})
      expect_exact(scaled(ulp_neighbours(150, seed), s), "ulp pairs x" + std::to_string(s));
}

TEST(OutlineExactInput, CirclesAndRotatedLatticesRoundedToDoubles) {
  for (std::uint64_t seed = 1; seed <= 5; ++seed)
    for (double s : {1.0, 1e-9, 1e-2, 1e2, 1e9}) {
      expect_exact(scaled(circle_points(200 + 37 * seed, seed), s), "circle x" + std::to_string(s));
      expect_exact(scaled(rotated_lattice(16, seed), s), "lattice x" + std::to_string(s));
    }
}

TEST(OutlineExactInput, NearCollinearRuns) {
  for (double s : {1.0, 1e-9, 1e-2, 1e2, 1e9})
    for (int n : {50, 400}) {
      std::vector<Vec2> p;
      for (int i = 0; i < n; ++i) p.push_back({4.0 * i * s, (i / 3.0 + 100) * s});
      expect_exact(p, "run of " + std::to_string(n) + " x" + std::to_string(s));
    }
}

TEST(OutlineExactInput, LargeClusteredSetInMapCoordinates) {
  // 60 k points in clusters (sizes from centimetres to kilometres) around (1.5e6, 6.9e6), with exact
  // repeats and 1-ulp neighbours: the node set of a projected map.
  std::mt19937_64 rng(17);
  std::uniform_real_distribution<double> where(-2e4, 2e4), logsize(-2, 3);
  std::vector<Vec2> p;
  while (p.size() < 60000) {
    const Vec2 c{1.5e6 + where(rng), 6.9e6 + where(rng)};
    std::normal_distribution<double> g(0, std::pow(10.0, logsize(rng)));
    for (int k = 0; k < 400; ++k) {
      const Vec2 q{c.x + g(rng), c.y + g(rng)};
      p.push_back(q);
      if (k % 50 == 0) p.push_back({std::nextafter(q.x, 0.0), q.y});
      if (k % 97 == 0) p.push_back(q);
    }
  }
  ASSERT_GE(p.size(), 50000u);
  expect_exact(p, "clustered", 0);
}

TEST(OutlineExactInput, SignedZerosAreOnePointUlpsApartAreTwo) {
  const std::vector<Vec2> p{{0.0, 0.0},
                            {-0.0, 0.0},
                            {0.0, -0.0},
                            {-0.0, -0.0},
                            {1, 0},
                            {0, 1},
                            {std::nextafter(1.0, 2.0), 0},
                            {0, std::nextafter(1.0, 0.0)}};
  for (Mode m : {Mode::Ordinary, Mode::DS, Mode::DSHI})
    for (Order o : {Order::AsIs, Order::Hilbert, Order::Brio}) {
      const Triangulation T = triangulate(p, m, o);
      EXPECT_EQ(T.inserted, 5u);
      EXPECT_EQ(T.duplicates, 3u);
      EXPECT_EQ(check_delaunay(p, T), "");
    }
}
