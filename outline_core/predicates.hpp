// Exact geometric predicates on doubles: orientation, incircle, circumradius-vs-R.
// Adaptive: a floating-point evaluation with a proven error bound decides almost always; when the bound
// cannot decide, the sign is computed exactly with floating-point expansions (Shewchuk's method:
// error-free two-sum / two-product, sums of non-overlapping components). Written from the published
// method. Exact as long as no intermediate overflows or underflows (coordinate differences roughly in
// [1e-60, 1e60]). The library is compiled with -ffp-contract=off: a fused multiply-add would break the
// error-free transforms.
#pragma once

#include <cmath>
#include <cstddef>

namespace hg::outline::pred {

inline constexpr double kEps = 1.1102230246251565e-16;  // 2^-53, half an ulp of 1
inline constexpr double kOrientBound = (3.0 + 16.0 * kEps) * kEps;
inline constexpr double kIncircleBound = (10.0 + 96.0 * kEps) * kEps;

// Exact signs, called only when the filter cannot decide.
double orient2d_exact(double ax, double ay, double bx, double by, double cx, double cy);
double incircle_exact(double ax, double ay, double bx, double by, double cx, double cy, double dx, double dy);

// > 0: a, b, c counter-clockwise; < 0 clockwise; 0 collinear. Only the sign is meaningful.
inline double orient2d(double ax, double ay, double bx, double by, double cx, double cy) {
  const double l = (ax - cx) * (by - cy);
  const double r = (ay - cy) * (bx - cx);
  const double det = l - r;
  const double bound = kOrientBound * (std::fabs(l) + std::fabs(r));
  if (det > bound || -det > bound) return det;
  return orient2d_exact(ax, ay, bx, by, cx, cy);
}

// > 0: d strictly inside the circle through a, b, c (a, b, c counter-clockwise); < 0 outside; 0 on it.
inline double incircle(double ax, double ay, double bx, double by, double cx, double cy, double dx, double dy) {
  const double adx = ax - dx, ady = ay - dy, bdx = bx - dx, bdy = by - dy, cdx = cx - dx, cdy = cy - dy;
  const double bdxcdy = bdx * cdy, cdxbdy = cdx * bdy;
  const double cdxady = cdx * ady, adxcdy = adx * cdy;
  const double adxbdy = adx * bdy, bdxady = bdx * ady;
  const double alift = adx * adx + ady * ady;
  const double blift = bdx * bdx + bdy * bdy;
  const double clift = cdx * cdx + cdy * cdy;
  const double det = alift * (bdxcdy - cdxbdy) + blift * (cdxady - adxcdy) + clift * (adxbdy - bdxady);
  const double permanent = (std::fabs(bdxcdy) + std::fabs(cdxbdy)) * alift +
                           (std::fabs(cdxady) + std::fabs(adxcdy)) * blift +
                           (std::fabs(adxbdy) + std::fabs(bdxady)) * clift;
  const double bound = kIncircleBound * permanent;
  if (det > bound || -det > bound) return det;
  return incircle_exact(ax, ay, bx, by, cx, cy, dx, dy);
}

// Sign of (circumradius of a, b, c)^2 - R^2 for a non-degenerate triangle: > 0 exactly when r > R.
// r^2 = |ab|^2 |bc|^2 |ca|^2 / (4 D^2), D = orient2d determinant; compared without division.
int circumradius_vs(double ax, double ay, double bx, double by, double cx, double cy, double R);

}  // namespace hg::outline::pred
