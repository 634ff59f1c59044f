// The smoothing step's geometry: ring moments, TLS line and circle fits, residuals, intersections.
#include "path_planner/smooth/fits.hpp"

#include <Eigen/Cholesky>

#include <algorithm>

namespace hg::path_planner::smooth {

Unrolled::Unrolled(const Ring& ring) : n(int(ring.size())), origin(ring[0]) {
  const int m = 3 * n;
  q.resize(m);
  s.resize(m);
  for (int k = 0; k < m; ++k) q[k] = ring[k % n] - origin;
  double length = 0;
  for (int k = 0; k < n; ++k) length += (ring[(k + 1) % n] - ring[k]).norm();
  double acc = -length;
  for (int k = 0; k < m; ++k) {
    s[k] = acc;
    acc += (ring[(k + 1) % n] - ring[k % n]).norm();
  }
  mx.assign(m + 1, 0), my.assign(m + 1, 0), mxx.assign(m + 1, 0), mxy.assign(m + 1, 0), myy.assign(m + 1, 0);
  for (int k = 0; k < m; ++k) {
    const Vec2& p = q[k];
    mx[k + 1] = mx[k] + p.x();
    my[k + 1] = my[k] + p.y();
    mxx[k + 1] = mxx[k] + p.x() * p.x();
    mxy[k + 1] = mxy[k] + p.x() * p.y();
    myy[k + 1] = myy[k] + p.y() * p.y();
  }
}

Line fit_line(const Unrolled& u, long j0, long j1) {
  Line f;
  const double cnt = double(j1 - j0 + 1);
  if (cnt < 2) return f;
  const long a = j0 + u.n, b = j1 + u.n + 1;
  const double sx = u.mx[b] - u.mx[a], sy = u.my[b] - u.my[a];
  const Vec2 c(sx / cnt, sy / cnt);
  const double cxx = (u.mxx[b] - u.mxx[a]) / cnt - c.x() * c.x();
  const double cxy = (u.mxy[b] - u.mxy[a]) / cnt - c.x() * c.y();
  const double cyy = (u.myy[b] - u.myy[a]) / cnt - c.y() * c.y();
  // Major axis of the 2x2 covariance in closed form (no trigonometry: this runs for every vertex); the
  // minor eigenvalue is the mean squared residual.
  const double tr = cxx + cyy, det = cxx * cyy - cxy * cxy;
  const double root = std::sqrt(std::max(0.0, 0.25 * tr * tr - det));
  const double major = 0.5 * tr + root, minor = 0.5 * tr - root;
  // eigenvector of `major`: (cxy, major - cxx) or (major - cyy, cxy), whichever is better conditioned
  Vec2 dir =
      (major - cxx) * (major - cxx) > (major - cyy) * (major - cyy) ? Vec2(cxy, major - cxx) : Vec2(major - cyy, cxy);
  const double len = dir.norm();
  dir = len > 0 ? Vec2(dir / len) : Vec2(u.at(j1) - u.at(j0)).normalized();
  if (dir.dot(u.at(j1) - u.at(j0)) < 0) dir = -dir;
  f.centre = c;
  f.dir = dir;
  f.rms = std::sqrt(std::max(0.0, minor));
  f.ok = true;
  return f;
}

bool fit_circle(const Unrolled& u, long j0, long j1, Primitive& c) {
  const long m = j1 - j0 + 1;
  if (m < 5) return false;
  const Vec2 ref = u.at((j0 + j1) / 2);
  // Kasa: x^2 + y^2 + D x + E y + F = 0 in least squares.
  double sxx = 0, sxy = 0, syy = 0, sx = 0, sy = 0, sz = 0, sxz = 0, syz = 0;
  for (long j = j0; j <= j1; ++j) {
    const Vec2 p = u.at(j) - ref;
    const double z = p.squaredNorm();
    sxx += p.x() * p.x(), sxy += p.x() * p.y(), syy += p.y() * p.y();
    sx += p.x(), sy += p.y(), sz += z, sxz += p.x() * z, syz += p.y() * z;
  }
  Eigen::Matrix3d A;
  A << sxx, sxy, sx, sxy, syy, sy, sx, sy, double(m);
  const Eigen::Vector3d rhs(-sxz, -syz, -sz);
  const Eigen::Vector3d def = A.ldlt().solve(rhs);
  if (!def.allFinite()) return false;
  Vec2 centre(-def[0] / 2, -def[1] / 2);
  double r2 = centre.squaredNorm() - def[2];
  if (!(r2 > 0)) return false;
  double r = std::sqrt(r2);
  for (int it = 0; it < 4; ++it) {
    Eigen::Matrix3d JtJ = Eigen::Matrix3d::Zero();
    Eigen::Vector3d Jtr = Eigen::Vector3d::Zero();
    for (long j = j0; j <= j1; ++j) {
      const Vec2 d = u.at(j) - ref - centre;
      const double dn = d.norm();
      if (dn <= 0) continue;
      const Eigen::Vector3d J(-d.x() / dn, -d.y() / dn, -1);
      const double res = dn - r;
      JtJ += J * J.transpose();
      Jtr += J * res;
    }
    const Eigen::Vector3d step = JtJ.ldlt().solve(-Jtr);
    if (!step.allFinite()) return false;
    centre += step.head<2>();
    r += step[2];
    if (step.norm() < 1e-10) break;
  }
  if (!(r > 0) || !std::isfinite(r)) return false;
  double area2 = 0;  // orientation of travel about the centre
  for (long j = j0; j < j1; ++j) area2 += cross(u.at(j) - ref - centre, u.at(j + 1) - ref - centre);
  c.circle = true;
  c.centre = ref + centre;
  c.radius = r;
  c.ccw = area2 > 0;
  c.first = j0, c.last = j1;
  return true;
}

void refit_tangent(const Unrolled& u, Primitive& c, const std::vector<const Primitive*>& lines) {
  const long m = c.last - c.first + 1;
  if (lines.empty() || m < 5) return;
  const double weight = std::sqrt(100.0 * double(m));
  std::vector<double> side;
  for (const Primitive* l : lines) side.push_back(cross(l->dir, c.centre - l->centre) >= 0 ? 1.0 : -1.0);
  Vec2 centre = c.centre;
  double r = c.radius;
  for (int it = 0; it < 8; ++it) {
    Eigen::Matrix3d JtJ = Eigen::Matrix3d::Zero();
    Eigen::Vector3d Jtr = Eigen::Vector3d::Zero();
    for (long j = c.first; j <= c.last; ++j) {
      const Vec2 d = u.at(j) - centre;
      const double dn = d.norm();
      if (dn <= 0) continue;
      const Eigen::Vector3d J(-d.x() / dn, -d.y() / dn, -1);
      JtJ += J * J.transpose();
      Jtr += J * (dn - r);
    }
    for (std::size_t k = 0; k < lines.size(); ++k) {
      const Primitive& l = *lines[k];
      const double res = weight * (side[k] * cross(l.dir, centre - l.centre) - r);
      const Eigen::Vector3d J(-weight * side[k] * l.dir.y(), weight * side[k] * l.dir.x(), -weight);
      JtJ += J * J.transpose();
      Jtr += J * res;
    }
    const Eigen::Vector3d step = JtJ.ldlt().solve(-Jtr);
    if (!step.allFinite()) return;
    centre += step.head<2>();
    r += step[2];
    if (step.norm() < 1e-10) break;
  }
  if (!(r > 0) || !std::isfinite(r) || !centre.allFinite()) return;
  c.centre = centre;
  c.radius = r;
}

double residual(const Primitive& p, const Vec2& q) {
  if (p.circle) return (q - p.centre).norm() - p.radius;
  return cross(p.dir, q - p.centre);  // left of travel positive
}

double worst_window_mean(const Unrolled& u, const Primitive& p, long j0, long j1, int w, std::vector<double>& r) {
  const long m = j1 - j0 + 1;
  r.resize(m);
  for (long j = j0; j <= j1; ++j) r[j - j0] = residual(p, u.at(j));
  const long win = std::min<long>(w, m);
  double sum = 0, worst = 0;
  for (long k = 0; k < m; ++k) {
    sum += r[k];
    if (k >= win) sum -= r[k - win];
    if (k >= win - 1) worst = std::max(worst, std::abs(sum) / double(win));
  }
  return worst;
}

Vec2 tangent_at(const Primitive& p, const Vec2& q) {
  if (!p.circle) return p.dir;
  const Vec2 radial = (q - p.centre).normalized();
  return p.ccw ? Vec2(-radial.y(), radial.x()) : Vec2(radial.y(), -radial.x());
}

double edge_bias(const Vec2& t, double pitch) { return 0.5 * pitch * std::max(std::abs(t.x()), std::abs(t.y())); }

bool intersect(const Primitive& a, const Primitive& b, double pitch, double bias_scale, const Vec2& near, Vec2& x) {
  auto shifted_line = [&](const Primitive& p, Vec2& c, Vec2& d) {
    d = p.dir;
    c = p.centre + bias_scale * edge_bias(d, pitch) * right_of(d);
  };
  auto shifted_radius = [&](const Primitive& p, const Vec2& at) {
    // outward is away from the centre when travelling counter-clockwise (material inside)
    const double b = bias_scale * edge_bias(tangent_at(p, at), pitch);
    return p.radius + (p.ccw ? b : -b);
  };
  if (!a.circle && !b.circle) {
    Vec2 ca, da, cb, db;
    shifted_line(a, ca, da);
    shifted_line(b, cb, db);
    const double den = cross(da, db);
    if (std::abs(den) < 1e-12) return false;
    x = ca + (cross(cb - ca, db) / den) * da;
    return true;
  }
  if (a.circle != b.circle) {
    const Primitive& l = a.circle ? b : a;
    const Primitive& c = a.circle ? a : b;
    Vec2 cl, dl;
    shifted_line(l, cl, dl);
    const double r = shifted_radius(c, near);
    const double t0 = (c.centre - cl).dot(dl);
    const Vec2 foot = cl + t0 * dl;
    const double h2 = r * r - (foot - c.centre).squaredNorm();
    if (h2 < 0) return false;
    const double h = std::sqrt(h2);
    const Vec2 x1 = foot + h * dl, x2 = foot - h * dl;
    x = (x1 - near).squaredNorm() < (x2 - near).squaredNorm() ? x1 : x2;
    return true;
  }
  const double ra = shifted_radius(a, near), rb = shifted_radius(b, near);
  const Vec2 d = b.centre - a.centre;
  const double L = d.norm();
  if (!(L > 0) || L > ra + rb || L < std::abs(ra - rb)) return false;
  const double t = (L * L + ra * ra - rb * rb) / (2 * L);
  const double h = std::sqrt(std::max(0.0, ra * ra - t * t));
  const Vec2 e = d / L, base = a.centre + t * e, perp(-e.y(), e.x());
  const Vec2 x1 = base + h * perp, x2 = base - h * perp;
  x = (x1 - near).squaredNorm() < (x2 - near).squaredNorm() ? x1 : x2;
  return true;
}

}  // namespace hg::path_planner::smooth
