// The exact predicates (orient2d, incircle, circumradius_vs, their exact fallbacks) against GMP rationals:
// every double is a dyadic rational, so mpq_class gives the true sign. Full-precision random doubles over
// many seeds and scales, near-degenerate inputs built to defeat the floating-point filter (points rounded
// onto lines and circles, ulp nudges), few-bit camera-like coordinates, exact cocircular integer points.
#include <gtest/gtest.h>

#include <cmath>
#include <cstdint>
#include <random>
#include <utility>

#include "clouds.hpp"
#include "exact_checker.hpp"
#include "outline_core/predicates.hpp"

using namespace hg::outline;
using namespace hg::outline::testing;

namespace {

int sign_of(double v) { return (v > 0) - (v < 0); }

int orient_sign_q(Vec2 a, Vec2 b, Vec2 c) { return sgn(orient_q(exact(a), exact(b), exact(c))); }

int incircle_sign_q(Vec2 a, Vec2 b, Vec2 c, Vec2 d) { return sgn(incircle_q(exact(a), exact(b), exact(c), exact(d))); }

// Both the filtered predicate and the exact fallback called directly must give the rational sign.
void expect_orient(Vec2 a, Vec2 b, Vec2 c, int want, std::uint64_t seed, int it) {
  ASSERT_EQ(sign_of(pred::orient2d(a.x, a.y, b.x, b.y, c.x, c.y)), want) << "seed " << seed << " it " << it;
  ASSERT_EQ(sign_of(pred::orient2d_exact(a.x, a.y, b.x, b.y, c.x, c.y)), want) << "seed " << seed << " it " << it;
}

void expect_incircle(const Vec2 (&p)[4], int want, std::uint64_t seed, int it) {
  const double s = pred::incircle(p[0].x, p[0].y, p[1].x, p[1].y, p[2].x, p[2].y, p[3].x, p[3].y);
  const double e = pred::incircle_exact(p[0].x, p[0].y, p[1].x, p[1].y, p[2].x, p[2].y, p[3].x, p[3].y);
  ASSERT_EQ(sign_of(s), want) << "seed " << seed << " it " << it;
  ASSERT_EQ(sign_of(e), want) << "seed " << seed << " it " << it;
}

// A full-precision double: uniform in [-1, 1) times a random power of ten, plus a random offset, so the
// 53 mantissa bits are all in use and the points sit anywhere from 1e-15 to 1e15 from the origin
// (within the predicates' exact range: predicates.hpp).
struct FullPrecision {
  std::mt19937_64 rng;
  std::uniform_real_distribution<double> u{-1, 1};
  std::uniform_int_distribution<int> exponent{-15, 15};
  explicit FullPrecision(std::uint64_t seed) : rng(seed) {}
  double operator()() { return u(rng); }
  double scale() { return std::pow(10.0, exponent(rng)); }
};

// x nudged by k ulps (k may be negative).
double nudge(double x, int k) {
  for (; k > 0; --k) x = std::nextafter(x, INFINITY);
  for (; k < 0; ++k) x = std::nextafter(x, -INFINITY);
  return x;
}

}  // namespace

TEST(OutlinePredicates, Orient2dRandomFullPrecisionDoublesManySeeds) {
  for (std::uint64_t seed = 1; seed <= 20; ++seed) {
    FullPrecision r(seed);
    for (int it = 0; it < 2000; ++it) {
      const double s = r.scale(), ox = r() * r.scale(), oy = r() * r.scale();
      const Vec2 a{ox + s * r(), oy + s * r()}, b{ox + s * r(), oy + s * r()}, c{ox + s * r(), oy + s * r()};
      expect_orient(a, b, c, orient_sign_q(a, b, c), seed, it);
    }
  }
}

TEST(OutlinePredicates, Orient2dNearCollinearFullPrecisionManySeeds) {
  // Three full-precision points on one line: a horizontal line or the diagonal y = x (exactly collinear),
  // or c = a + t (b - a) rounded to doubles (collinear to within an ulp); c then nudged by up to 3 ulps
  // per coordinate in two cases of three. The true sign is 0 or decided far below the filter's bound.
  // Every sign must occur, else the test proves nothing.
  int zero = 0, pos = 0, neg = 0;
  for (std::uint64_t seed = 1; seed <= 20; ++seed) {
    FullPrecision r(100 + seed);
    std::uniform_int_distribution<int> k(-3, 3);
    for (int it = 0; it < 3000; ++it) {
      const double s = r.scale(), ox = r() * r.scale(), oy = r() * r.scale();
      Vec2 a{ox + s * r(), oy + s * r()}, b{ox + s * r(), oy + s * r()}, c;
      if (it % 3 == 0) {
        const double y = a.y;
        b.y = y;
        c = {ox + s * r(), y};
      } else if (it % 3 == 1) {
        a.y = a.x;
        b.y = b.x;
        c.x = c.y = ox + s * r();
      } else {
        const double t = (r() + 1) * 0.75 - 0.25;  // inside the segment and beyond both ends
        c = {a.x + t * (b.x - a.x), a.y + t * (b.y - a.y)};
      }
      if (it % 2 == 0) c = {nudge(c.x, k(r.rng)), nudge(c.y, k(r.rng))};
      const int want = orient_sign_q(a, b, c);
      expect_orient(a, b, c, want, seed, it);
      expect_orient(b, c, a, want, seed, it);   // cyclic permutation: the same sign
      expect_orient(b, a, c, -want, seed, it);  // swap: the opposite sign
      (want == 0 ? zero : want > 0 ? pos : neg)++;
    }
  }
  EXPECT_GT(zero, 1000);
  EXPECT_GT(pos, 1000);
  EXPECT_GT(neg, 1000);
}

TEST(OutlinePredicates, IncircleRandomFullPrecisionDoublesManySeeds) {
  for (std::uint64_t seed = 1; seed <= 20; ++seed) {
    FullPrecision r(200 + seed);
    for (int it = 0; it < 2000; ++it) {
      const double s = r.scale(), ox = r() * r.scale(), oy = r() * r.scale();
      Vec2 p[4];
      for (auto& q : p) q = {ox + s * r(), oy + s * r()};
      if (pred::orient2d(p[0].x, p[0].y, p[1].x, p[1].y, p[2].x, p[2].y) < 0) std::swap(p[1], p[2]);
      expect_incircle(p, incircle_sign_q(p[0], p[1], p[2], p[3]), seed, it);
    }
  }
}

TEST(OutlinePredicates, IncircleNearCocircularFullPrecisionManySeeds) {
  // Four points on one circle, each rounded to doubles (cocircular to within an ulp), the fourth nudged by
  // up to 4 ulps; circles of every size and far from the origin. Inside and outside must both occur.
  int inside = 0, outside = 0;
  for (std::uint64_t seed = 1; seed <= 20; ++seed) {
    FullPrecision r(300 + seed);
    std::uniform_int_distribution<int> k(-4, 4);
    for (int it = 0; it < 2000; ++it) {
      const double radius = r.scale() * (1.5 + r()), cx = r() * r.scale(), cy = r() * r.scale();
      Vec2 p[4];
      for (auto& q : p) {
        const double t = M_PI * r();
        q = {cx + radius * std::cos(t), cy + radius * std::sin(t)};
      }
      p[3] = {nudge(p[3].x, k(r.rng)), nudge(p[3].y, k(r.rng))};
      const double o = pred::orient2d(p[0].x, p[0].y, p[1].x, p[1].y, p[2].x, p[2].y);
      if (o == 0) continue;  // three rounded points collinear: no circle
      if (o < 0) std::swap(p[1], p[2]);
      const int want = incircle_sign_q(p[0], p[1], p[2], p[3]);
      expect_incircle(p, want, seed, it);
      (want > 0 ? inside : outside) += want != 0;
    }
  }
  EXPECT_GT(inside, 1000);
  EXPECT_GT(outside, 1000);
}

TEST(OutlinePredicates, PredicatesAgreeWithRationalArithmetic) {
  // Points near the line y = x, a few ulps apart: the floating determinant is mostly noise.
  std::mt19937_64 rng(4);
  std::uniform_int_distribution<int> k(0, 60);
  const double base = 0.5, ulp = std::nextafter(0.5, 1.0) - 0.5;
  int exact_zero = 0;
  for (int it = 0; it < 20000; ++it) {
    const Vec2 a{base + k(rng) * ulp, base + k(rng) * ulp}, b{12, 12}, c{24, 24};
    const double s = pred::orient2d(a.x, a.y, b.x, b.y, c.x, c.y);
    const int want = sgn(orient_q(exact(a), exact(b), exact(c)));
    ASSERT_EQ((s > 0) - (s < 0), want) << it;
    exact_zero += want == 0;
  }
  EXPECT_GT(exact_zero, 0);
  // Near-cocircular: rounded points on the unit circle, and a fourth point nudged by ulps.
  std::uniform_real_distribution<double> ang(0, 2 * M_PI);
  for (int it = 0; it < 20000; ++it) {
    Vec2 p[4];
    for (auto& q : p) {
      const double t = ang(rng);
      q = {std::cos(t) * 1e3 + 5e5, std::sin(t) * 1e3 - 7e5};
    }
    if (pred::orient2d(p[0].x, p[0].y, p[1].x, p[1].y, p[2].x, p[2].y) < 0) std::swap(p[1], p[2]);
    const double s = pred::incircle(p[0].x, p[0].y, p[1].x, p[1].y, p[2].x, p[2].y, p[3].x, p[3].y);
    const int want = sgn(incircle_q(exact(p[0]), exact(p[1]), exact(p[2]), exact(p[3])));
    ASSERT_EQ((s > 0) - (s < 0), want) << it;
  }
  // Exactly cocircular integer points.
  const auto c = cocircular_cloud();
  for (std::size_t i = 3; i + 3 < c.size(); ++i) {
    const Vec2 &a = c[i], &b = c[i + 1], &d = c[i + 2], &e = c[i + 3];
    EXPECT_EQ(pred::incircle(a.x, a.y, b.x, b.y, d.x, d.y, e.x, e.y), 0.0);
  }
}

TEST(OutlinePredicates, PredicatesOnFewBitPointsAgreeWithRationalArithmetic) {
  // Coordinates on a 2^-24 grid (like float32 camera data in metres): their differences have few bits, so
  // the exact fallback takes its integer path. Points on a circle rounded to the grid are cocircular to
  // ~1e-7, far below the filter's reach; a rectangle's corners (a grid cell) are exactly cocircular;
  // near-collinear triples rounded to the grid.
  auto g24 = [](double v) { return std::round(v * 0x1p24) * 0x1p-24; };
  std::mt19937_64 rng(17);
  std::uniform_real_distribution<double> ang(0, 2 * M_PI), u(-1, 1);
  int decided_nonzero = 0, zero = 0;
  for (int it = 0; it < 20000; ++it) {
    const double cxr = u(rng) * 0.3, cyr = u(rng) * 0.3, r = 1e-3 * (1 + std::fabs(u(rng)));
    Vec2 p[4];
    for (auto& q : p) {
      const double t = ang(rng);
      q = {g24(cxr + r * std::cos(t)), g24(cyr + r * std::sin(t))};
    }
    if (it % 4 == 0) {  // an axis-aligned rectangle
      p[1] = {p[2].x, p[0].y};
      p[3] = {p[0].x, p[2].y};
    }
    if (pred::orient2d(p[0].x, p[0].y, p[1].x, p[1].y, p[2].x, p[2].y) < 0) std::swap(p[1], p[2]);
    const double s = pred::incircle(p[0].x, p[0].y, p[1].x, p[1].y, p[2].x, p[2].y, p[3].x, p[3].y);
    const int want = sgn(incircle_q(exact(p[0]), exact(p[1]), exact(p[2]), exact(p[3])));
    ASSERT_EQ((s > 0) - (s < 0), want) << it;
    (want == 0 ? zero : decided_nonzero)++;
    // The exact fallback itself (its integer path), called directly, also off the degenerate cases.
    const double e = pred::incircle_exact(p[0].x, p[0].y, p[1].x, p[1].y, p[2].x, p[2].y, p[3].x, p[3].y);
    ASSERT_EQ((e > 0) - (e < 0), want) << it;
    const Vec2 far{g24(cxr + 3 * r * u(rng)), g24(cyr + 3 * r * u(rng))};
    const double f = pred::incircle_exact(p[0].x, p[0].y, p[1].x, p[1].y, p[2].x, p[2].y, far.x, far.y);
    ASSERT_EQ((f > 0) - (f < 0), sgn(incircle_q(exact(p[0]), exact(p[1]), exact(p[2]), exact(far)))) << it;
    const double oe = pred::orient2d_exact(p[0].x, p[0].y, p[1].x, p[1].y, far.x, far.y);
    ASSERT_EQ((oe > 0) - (oe < 0), sgn(orient_q(exact(p[0]), exact(p[1]), exact(far)))) << it;
    // Near-collinear: a third float point on the segment, rounded.
    const double t = (u(rng) + 1) / 2;
    const Vec2 m{g24(p[0].x + t * (p[1].x - p[0].x)), g24(p[0].y + t * (p[1].y - p[0].y))};
    const double o = pred::orient2d(p[0].x, p[0].y, p[1].x, p[1].y, m.x, m.y);
    ASSERT_EQ((o > 0) - (o < 0), sgn(orient_q(exact(p[0]), exact(p[1]), exact(m)))) << it;
  }
  EXPECT_GT(zero, 1000) << decided_nonzero;
  EXPECT_GT(decided_nonzero, 10000);
}

TEST(OutlinePredicates, CircumradiusComparisonIsExact) {
  // r = 5 exactly for the 6-8-10 right triangle (and scaled copies): r == R must give 0.
  for (double s : {1.0, 0.125, 3.0, 1e-7, 1e7}) {
    EXPECT_EQ(pred::circumradius_vs(0, 0, 6 * s, 0, 0, 8 * s, 5 * s), 0);
    EXPECT_EQ(pred::circumradius_vs(0, 0, 6 * s, 0, 0, 8 * s, std::nextafter(5 * s, 0.0)), 1);
    EXPECT_EQ(pred::circumradius_vs(0, 0, 6 * s, 0, 0, 8 * s, std::nextafter(5 * s, 1e300)), -1);
  }
  std::mt19937_64 rng(6);
  std::uniform_real_distribution<double> u(-1, 1);
  for (int it = 0; it < 5000; ++it) {
    Vec2 p[3];
    for (auto& q : p) q = {u(rng), u(rng)};
    if (pred::orient2d(p[0].x, p[0].y, p[1].x, p[1].y, p[2].x, p[2].y) == 0) continue;
    const Q2 a = exact(p[0]), b = exact(p[1]), c = exact(p[2]);
    const mpq_class r2 = circumradius2_q(a, b, c);
    // R: the rounded circumradius and its neighbours, so r^2 - R^2 is tiny and of either sign.
    double R = std::sqrt(r2.get_d());
    for (double cand : {std::nextafter(R, 0.0), R, std::nextafter(R, 1e300), R * 0.5, R * 2}) {
      const mpq_class R2 = mpq_class(cand) * mpq_class(cand);
      const int want = r2 > R2 ? 1 : (r2 < R2 ? -1 : 0);
      ASSERT_EQ(pred::circumradius_vs(p[0].x, p[0].y, p[1].x, p[1].y, p[2].x, p[2].y, cand), want) << it;
    }
  }
}

namespace {

// The rational sign of r^2 - R^2 (r the circumradius of a, b, c; not collinear).
int circumradius_sign_q(Vec2 a, Vec2 b, Vec2 c, double R) {
  const mpq_class r2 = circumradius2_q(exact(a), exact(b), exact(c)), R2 = mpq_class(R) * mpq_class(R);
  return r2 > R2 ? 1 : (r2 < R2 ? -1 : 0);
}

// Both the filtered comparison and the exact fallback called directly must give the rational sign, for R
// the rounded circumradius and its neighbours (r^2 - R^2 tiny, of either sign) and for R far from it.
void expect_circumradius(const Vec2 (&p)[3], std::uint64_t seed, int it, int& ties) {
  const double R = std::sqrt(circumradius2_q(exact(p[0]), exact(p[1]), exact(p[2])).get_d());
  for (double cand : {std::nextafter(R, 0.0), R, std::nextafter(R, 1e300), R * 0.75, R * 1.5}) {
    const int want = circumradius_sign_q(p[0], p[1], p[2], cand);
    ASSERT_EQ(pred::circumradius_vs(p[0].x, p[0].y, p[1].x, p[1].y, p[2].x, p[2].y, cand), want)
        << "seed " << seed << " it " << it;
    ASSERT_EQ(pred::circumradius_vs_exact(p[0].x, p[0].y, p[1].x, p[1].y, p[2].x, p[2].y, cand), want)
        << "seed " << seed << " it " << it;
    ties += want == 0;
  }
}

}  // namespace

TEST(OutlinePredicates, CircumradiusFullPrecisionFarFromOriginManySeeds) {
  // Full-precision points anywhere from 1e-15 to 1e15 from the origin at every scale: most coordinate
  // differences are not doubles, so the exact fallback works on two-component differences.
  for (std::uint64_t seed = 1; seed <= 10; ++seed) {
    FullPrecision r(400 + seed);
    int ties = 0;
    for (int it = 0; it < 300; ++it) {
      const double s = r.scale(), ox = r() * r.scale(), oy = r() * r.scale();
      const Vec2 p[3] = {{ox + s * r(), oy + s * r()}, {ox + s * r(), oy + s * r()}, {ox + s * r(), oy + s * r()}};
      if (orient_sign_q(p[0], p[1], p[2]) == 0) continue;
      expect_circumradius(p, seed, it, ties);
    }
  }
}

TEST(OutlinePredicates, PredicatesOnExactManyBitDifferencesManySeeds) {
  // Full-precision points in [1, 2)^2: every coordinate difference is an exact double (Sterbenz) of up
  // to 52 bits, too many for the integer path, so the exact fallbacks take their one-component expansion
  // paths. Near-degenerate by construction: rounded onto a circle (incircle), onto a line (orient), and
  // R = the rounded circumradius (circumradius_vs).
  int inside = 0, outside = 0, collinear = 0, decided = 0;
  for (std::uint64_t seed = 1; seed <= 10; ++seed) {
    std::mt19937_64 rng(500 + seed);
    std::uniform_real_distribution<double> u(0, 1), ang(0, 2 * M_PI);
    std::uniform_int_distribution<int> k(-2, 2);
    int ties = 0;
    for (int it = 0; it < 1000; ++it) {
      const double cx = 1.5 + 0.1 * (u(rng) - 0.5), cy = 1.5 + 0.1 * (u(rng) - 0.5), rad = 0.05 + 0.3 * u(rng);
      Vec2 p[4];
      for (auto& q : p) q = {cx + rad * std::cos(ang(rng)), cy + rad * std::sin(ang(rng))};
      p[3] = {nudge(p[3].x, k(rng)), nudge(p[3].y, k(rng))};
      const int o = orient_sign_q(p[0], p[1], p[2]);
      if (o == 0) continue;
      if (o < 0) std::swap(p[1], p[2]);
      const int want = incircle_sign_q(p[0], p[1], p[2], p[3]);
      expect_incircle(p, want, seed, it);
      (want > 0 ? inside : outside) += want != 0;
      // Near-collinear: on the line through two of the points, rounded (and nudged on odd iterations);
      // every third line horizontal, where the rounded point is exactly on it.
      const Vec2 a = p[0], b = it % 3 ? p[1] : Vec2{p[1].x, p[0].y};
      const double t = u(rng) * 1.5 - 0.25;
      Vec2 m{a.x + t * (b.x - a.x), a.y + t * (b.y - a.y)};
      if (it % 2) m = {nudge(m.x, k(rng)), nudge(m.y, k(rng))};
      const int want_o = orient_sign_q(a, b, m);
      expect_orient(a, b, m, want_o, seed, it);
      (want_o == 0 ? collinear : decided) += 1;
      const Vec2 tri[3] = {p[0], p[1], p[2]};
      expect_circumradius(tri, seed, it, ties);
    }
  }
  EXPECT_GT(inside, 1000);
  EXPECT_GT(outside, 1000);
  EXPECT_GT(collinear, 1000);
  EXPECT_GT(decided, 1000);
}

TEST(OutlinePredicates, CircumradiusOnFewBitPointsExactTies) {
  // Right triangles on a 2^-24 grid (float32 camera data): the circumradius is half the hypotenuse, and
  // for a hypotenuse of even integer length in grid units (Pythagorean triples scaled) R = half of it is a
  // tie the comparison must call exactly 0; one ulp either side decides.
  const int triples[][3] = {{3, 4, 5}, {5, 12, 13}, {8, 15, 17}, {7, 24, 25}, {20, 21, 29}};
  std::mt19937_64 rng(23);
  std::uniform_int_distribution<int> origin(-(1 << 22), 1 << 22), mult(1, 1000);
  for (int it = 0; it < 2000; ++it) {
    const auto& t = triples[it % 5];
    const double unit = 0x1p-24, ox = origin(rng) * unit, oy = origin(rng) * unit, m = 2 * mult(rng);
    const Vec2 a{ox, oy}, b{ox + m * t[0] * unit, oy}, c{ox, oy + m * t[1] * unit};
    const double R = m * t[2] * unit / 2;                 // exact: an integer times a power of two
    ASSERT_EQ(circumradius_sign_q(a, b, c, R), 0) << it;  // the construction is a tie
    EXPECT_EQ(pred::circumradius_vs(a.x, a.y, b.x, b.y, c.x, c.y, R), 0) << it;
    EXPECT_EQ(pred::circumradius_vs_exact(a.x, a.y, b.x, b.y, c.x, c.y, R), 0) << it;
    EXPECT_EQ(pred::circumradius_vs(a.x, a.y, b.x, b.y, c.x, c.y, std::nextafter(R, 0.0)), 1) << it;
    EXPECT_EQ(pred::circumradius_vs(a.x, a.y, c.x, c.y, b.x, b.y, std::nextafter(R, 1.0)), -1) << it;
  }
}
