// Best-fit plane of a 3-D cloud by least squares (PCA of the centred covariance, Eigen) over its finite
// points, and the projection of the points to plane coordinates.
#include <Eigen/Dense>
#include <algorithm>
#include <cmath>
#include <limits>

#include "outline_io/cloud.hpp"
#include "outline_core/predicates.hpp"

namespace hg::outline_io {

namespace {

bool finite_point(const double* q) { return std::isfinite(q[0]) && std::isfinite(q[1]) && std::isfinite(q[2]); }

// The finite points all on one line in space (exactly: every cross product (q - a) x (b - a) is zero,
// its three components being the exact 2-D orientations in the xy, yz and zx planes); throws the core's
// collinear error then, as for 2-D input. Points equal to a are skipped until a second one is found.
void refuse_collinear(const double* p, const std::vector<std::size_t>& finite) {
  const double* a = p + 3 * finite[0];
  const double* b = nullptr;
  for (std::size_t i : finite) {
    const double* q = p + 3 * i;
    if (!b) {
      if (q[0] != a[0] || q[1] != a[1] || q[2] != a[2]) b = q;
      continue;
    }
    for (int k = 0; k < 3; ++k) {
      const int x = k, y = (k + 1) % 3;
      if (outline::pred::orient2d(a[x], a[y], b[x], b[y], q[x], q[y]) != 0) return;
    }
  }
  std::vector<std::array<double, 3>> distinct;
  for (std::size_t i : finite) distinct.push_back({p[3 * i] + 0.0, p[3 * i + 1] + 0.0, p[3 * i + 2] + 0.0});
  std::sort(distinct.begin(), distinct.end());
  const std::size_t count = static_cast<std::size_t>(std::unique(distinct.begin(), distinct.end()) - distinct.begin());
  if (count < 3) throw OutlineError("need at least 3 distinct points, got " + std::to_string(count));
  throw OutlineError("all " + std::to_string(count) + " distinct points are collinear");
}

// A flat 3-D cloud (every z equal) lies on the plane z = that z, with the input's own x, y as its axes:
// written as such, so that a planner places the outline at that height and not on a guessed plane.
void set_flat_plane(double z, PlanarPoints& out) {
  out.projected = true;
  out.plane.origin = {0, 0, z};
  out.plane.normal = {0, 0, 1};
  out.plane.u = {1, 0, 0};
  out.plane.v = {0, 1, 0};
}

}  // namespace

PlanarPoints to_plane(const Cloud& cloud, const std::string& name) {
  PlanarPoints out;
  const std::size_t n = cloud.size();
  const double* p = cloud.xyz.data();
  out.points.resize(n);
  std::vector<std::size_t> finite;  // points with three finite coordinates; the others become NaN
  finite.reserve(n);
  for (std::size_t i = 0; i < n; ++i)
    if (finite_point(p + 3 * i)) finite.push_back(i);
  constexpr double kNaN = std::numeric_limits<double>::quiet_NaN();
  bool planar = !cloud.has_z || finite.empty();
  if (!planar) {
    planar = true;
    for (std::size_t i : finite) planar = planar && p[3 * i + 2] == p[3 * finite[0] + 2];
  }
  if (planar) {
    for (std::size_t i = 0; i < n; ++i)
      out.points[i] = finite_point(p + 3 * i) ? Vec2{p[3 * i], p[3 * i + 1]} : Vec2{kNaN, kNaN};
    if (cloud.has_z && !finite.empty()) set_flat_plane(p[3 * finite[0] + 2], out);
    return out;
  }
  refuse_collinear(p, finite);

  // Two passes (centroid, then centred covariance) keep the sums well conditioned far from the origin.
  const std::size_t nf = finite.size();
  Eigen::Vector3d c = Eigen::Vector3d::Zero();
  for (std::size_t i : finite) c += Eigen::Vector3d(p[3 * i], p[3 * i + 1], p[3 * i + 2]);
  c /= static_cast<double>(nf);
  Eigen::Matrix3d cov = Eigen::Matrix3d::Zero();
  for (std::size_t i : finite) {
    Eigen::Vector3d d = Eigen::Vector3d(p[3 * i], p[3 * i + 1], p[3 * i + 2]) - c;
    cov.noalias() += d * d.transpose();
  }
  Eigen::SelfAdjointEigenSolver<Eigen::Matrix3d> eig(cov);
  Eigen::Vector3d normal = eig.eigenvectors().col(0).normalized();  // smallest eigenvalue
  // Sign: towards +z (then +y, +x) so the result does not flip between runs or similar clouds.
  for (int k : {2, 1, 0})
    if (normal[k] != 0) {
      if (normal[k] < 0) normal = -normal;
      break;
    }
  Eigen::Vector3d u, v;
  const Eigen::Vector3d ex = Eigen::Vector3d::UnitX(), ey = Eigen::Vector3d::UnitY();
  if (std::abs(normal.dot(ex)) < 0.9) {
    u = (ex - normal.dot(ex) * normal).normalized();
    v = normal.cross(u);
  } else {
    v = (ey - normal.dot(ey) * normal).normalized();
    u = v.cross(normal);
  }
  out.projected = true;
  for (int k = 0; k < 3; ++k) {
    out.plane.origin[k] = c[k];
    out.plane.normal[k] = normal[k];
    out.plane.u[k] = u[k];
    out.plane.v[k] = v[k];
  }
  double sum2 = 0, maxd = 0;
  for (std::size_t i = 0; i < n; ++i) out.points[i] = {kNaN, kNaN};
  for (std::size_t i : finite) {
    Eigen::Vector3d d = Eigen::Vector3d(p[3 * i], p[3 * i + 1], p[3 * i + 2]) - c;
    out.points[i] = {d.dot(u), d.dot(v)};
    double h = std::abs(d.dot(normal));
    sum2 += h * h;
    maxd = std::max(maxd, h);
  }
  // Coordinates near the double range overflow the covariance: say so instead of passing NaN on.
  bool ok = normal.allFinite() && std::isfinite(sum2);
  for (std::size_t k = 0; k < nf && ok; ++k)
    ok = std::isfinite(out.points[finite[k]].x) && std::isfinite(out.points[finite[k]].y);
  if (!ok) throw ReadError(name + ": coordinates too large for the plane fit (overflow in the least-squares sums)");
  out.rms_distance = std::sqrt(sum2 / static_cast<double>(nf));
  out.max_distance = maxd;
  return out;
}

std::array<double, 3> plane_to_3d(const Plane& pl, Vec2 q) {
  return {pl.origin[0] + q.x * pl.u[0] + q.y * pl.v[0], pl.origin[1] + q.x * pl.u[1] + q.y * pl.v[1],
          pl.origin[2] + q.x * pl.u[2] + q.y * pl.v[2]};
}

}  // namespace hg::outline_io
