// Best-fit plane of a 3-D cloud by least squares (PCA of the centred covariance, Eigen), and the
// projection of the points to plane coordinates.
#include <Eigen/Dense>
#include <cmath>

#include "outline_core/io/cloud_io.hpp"

namespace hg::outline::io {

PlanarPoints to_plane(const Cloud& cloud, const std::string& name) {
  PlanarPoints out;
  const std::size_t n = cloud.size();
  const double* p = cloud.xyz.data();
  out.points.resize(n);
  bool planar = !cloud.has_z;
  if (!planar) {
    planar = true;
    for (std::size_t i = 1; i < n && planar; ++i) planar = p[3 * i + 2] == p[2];
  }
  if (planar) {
    for (std::size_t i = 0; i < n; ++i) out.points[i] = {p[3 * i], p[3 * i + 1]};
    return out;
  }

  // Two passes (centroid, then centred covariance) keep the sums well conditioned far from the origin.
  Eigen::Vector3d c = Eigen::Vector3d::Zero();
  for (std::size_t i = 0; i < n; ++i) c += Eigen::Vector3d(p[3 * i], p[3 * i + 1], p[3 * i + 2]);
  c /= static_cast<double>(n);
  Eigen::Matrix3d cov = Eigen::Matrix3d::Zero();
  for (std::size_t i = 0; i < n; ++i) {
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
  for (std::size_t i = 0; i < n; ++i) {
    Eigen::Vector3d d = Eigen::Vector3d(p[3 * i], p[3 * i + 1], p[3 * i + 2]) - c;
    out.points[i] = {d.dot(u), d.dot(v)};
    double h = std::abs(d.dot(normal));
    sum2 += h * h;
    maxd = std::max(maxd, h);
  }
  // Coordinates near the double range overflow the covariance: say so instead of passing NaN on.
  bool finite = normal.allFinite() && std::isfinite(sum2);
  for (std::size_t i = 0; i < n && finite; ++i) finite = std::isfinite(out.points[i].x) && std::isfinite(out.points[i].y);
  if (!finite) throw ReadError(name + ": coordinates too large for the plane fit (overflow in the least-squares sums)");
  out.rms_distance = std::sqrt(sum2 / static_cast<double>(n));
  out.max_distance = maxd;
  return out;
}

std::array<double, 3> plane_to_3d(const Plane& pl, Vec2 q) {
  return {pl.origin[0] + q.x * pl.u[0] + q.y * pl.v[0], pl.origin[1] + q.x * pl.u[1] + q.y * pl.v[1],
          pl.origin[2] + q.x * pl.u[2] + q.y * pl.v[2]};
}

}  // namespace hg::outline::io
