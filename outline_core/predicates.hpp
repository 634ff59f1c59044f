// Exact geometric predicates on doubles: orientation, incircle, circumradius-vs-R.
// Adaptive: a floating-point evaluation with a proven error bound decides almost always; when the bound
// cannot decide, the sign is computed exactly with floating-point expansions (Shewchuk's method:
// error-free two-sum / two-product, sums of non-overlapping components). Written from the published
// method. The library is compiled with -ffp-contract=off: a fused multiply-add would break the
// error-free transforms.
// Limits (exact as long as no intermediate overflows or underflows; only coordinate differences enter):
// with every coordinate a multiple of 2^-170 (no set bit below 2^-170, about 7e-52: true of any double of
// magnitude >= 1e-35 and of 0), every expansion component of a product of up to six differences is zero
// or at least 2^-1020, so nothing underflows. orient2d and incircle (degree 2 and 4) are then exact for
// differences up to 2^250 (1.8e75); circumradius_vs (degree 6, and R^2 D^2) for differences and R up to
// 2^165 (4.7e49), R also a multiple of 2^-170 (any R >= 1e-35). triangulate() enforces the resolution and a
// span below 1e60 (within the first bound); a larger span than 4.7e49 with the alpha test is not checked.
#pragma once

#include <cmath>
#include <cstddef>
#include <cstdint>
#include <cstring>

namespace hg::outline::pred {

// a - b is a double exactly: the error term of the rounded subtraction (two-diff tail) is zero.
inline bool difference_is_exact(double a, double b) {
  const double x = a - b, bv = a - x, av = x + bv;
  return (a - av) + (bv - b) == 0;
}

// v is 0 or a multiple of 2^-170 (no set bit below 2^-170; subnormals never are): see the limits above.
inline bool within_exact_resolution(double v) {
  std::uint64_t bits;
  std::memcpy(&bits, &v, 8);
  const int e = static_cast<int>((bits >> 52) & 0x7ff);
  const std::uint64_t mant = bits & ((std::uint64_t{1} << 52) - 1);
  if (e == 0) return mant == 0;                                                // zero, or subnormal
  return e - 1075 + __builtin_ctzll(mant | (std::uint64_t{1} << 52)) >= -170;  // v = mant' 2^(e - 1075)
}

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
// The filter works on (x, y) pairs (two-lane vectors: SSE2 on x86-64, baseline): the same operations on
// the same operands as the scalar formula, lane by lane, so the same rounded values and the same error
// bound (Shewchuk's incircle permanent), in about two thirds of the instructions.
inline double incircle(double ax, double ay, double bx, double by, double cx, double cy, double dx, double dy) {
  using v2 = double __attribute__((vector_size(16)));
  const v2 d = {dx, dy};
  const v2 a = v2{ax, ay} - d, b = v2{bx, by} - d, c = v2{cx, cy} - d;  // (adx, ady), (bdx, bdy), (cdx, cdy)
  const v2 bc = b * __builtin_shufflevector(c, c, 1, 0);                // (bdx cdy, bdy cdx)
  const v2 ca = c * __builtin_shufflevector(a, a, 1, 0);                // (cdx ady, cdy adx)
  const v2 ab = a * __builtin_shufflevector(b, b, 1, 0);                // (adx bdy, ady bdx)
  const v2 aa = a * a, bb = b * b, cc = c * c;
  const double alift = aa[0] + aa[1], blift = bb[0] + bb[1], clift = cc[0] + cc[1];
  const double det = alift * (bc[0] - bc[1]) + blift * (ca[0] - ca[1]) + clift * (ab[0] - ab[1]);
  using v2i = long long __attribute__((vector_size(16)));
  const v2i magnitude = {0x7fffffffffffffffLL, 0x7fffffffffffffffLL};  // clears the sign bits: |x| per lane
  const v2 abc = reinterpret_cast<v2>(reinterpret_cast<v2i>(bc) & magnitude);
  const v2 aca = reinterpret_cast<v2>(reinterpret_cast<v2i>(ca) & magnitude);
  const v2 aab = reinterpret_cast<v2>(reinterpret_cast<v2i>(ab) & magnitude);
  const double permanent = (abc[0] + abc[1]) * alift + (aca[0] + aca[1]) * blift + (aab[0] + aab[1]) * clift;
  const double bound = kIncircleBound * permanent;
  if (det > bound || -det > bound) return det;
  return incircle_exact(ax, ay, bx, by, cx, cy, dx, dy);
}

// Sign of (circumradius of a, b, c)^2 - R^2 for a non-degenerate triangle: > 0 exactly when r > R.
// r^2 = |ab|^2 |bc|^2 |ca|^2 / (4 D^2), D = orient2d determinant; compared without division.
// The exact sign, called only when the filter below cannot decide.
int circumradius_vs_exact(double ax, double ay, double bx, double by, double cx, double cy, double R);
inline int circumradius_vs(double ax, double ay, double bx, double by, double cx, double cy, double R) {
  // Filter. Relative rounding errors: each squared length <= 4.01 eps, the product N of three <= 14.1 eps.
  const double abx = ax - bx, aby = ay - by, bcx = bx - cx, bcy = by - cy, cax = cx - ax, cay = cy - ay;
  const double ab2 = abx * abx + aby * aby, bc2 = bcx * bcx + bcy * bcy, ca2 = cax * cax + cay * cay;
  const double N = ab2 * bc2 * ca2;
  const double l = (ax - cx) * (by - cy), r = (ay - cy) * (bx - cx);
  const double D = l - r;
  const double errD = kOrientBound * (std::fabs(l) + std::fabs(r));
  const double absD = std::fabs(D);
  if (absD > 4 * errD && std::isnormal(N)) {
    // |D - fl(D)| <= errD < |D| / 4, so the relative error of D is relD < (4/3) errD / |D| < 1/3 and that
    // of D^2 below 2.34 relD; M = 4 R^2 D^2 then errs by at most 2.5 relD M + 8 eps M, and
    // relD M < (4/3) errD |D| 4 R^2 (no division needed).
    const double R4 = 4.0 * (R * R);
    const double M = R4 * (D * D);
    const double margin = 1.01 * (16 * kEps * N + 2.5 * (4.0 / 3.0) * errD * absD * R4 + 8 * kEps * M);
    if (std::isnormal(M)) {
      if (N - M > margin) return 1;
      if (M - N > margin) return -1;
    }
  }
  return circumradius_vs_exact(ax, ay, bx, by, cx, cy, R);
}

}  // namespace hg::outline::pred
