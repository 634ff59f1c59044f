// Geometry helpers, input checks, up-normalisation and the mirror for flipped parts.
#include "path_planner/pipeline.hpp"

#include <Eigen/Eigenvalues>

#include <algorithm>
#include <cmath>

namespace hg::path_planner {

double signed_area(const Ring& ring) {
  const std::size_t n = ring.size();
  if (n < 3) return 0;
  // Shoelace about the first vertex (keeps precision for rings far from the origin).
  double a = 0;
  const Vec2 o = ring[0];
  for (std::size_t i = 1; i + 1 < n; ++i) {
    const Vec2 p = ring[i] - o, q = ring[i + 1] - o;
    a += p.x() * q.y() - p.y() * q.x();
  }
  return a / 2;
}

double ring_length(const Ring& ring) {
  double L = 0;
  for (std::size_t i = 0; i < ring.size(); ++i) L += (ring[(i + 1) % ring.size()] - ring[i]).norm();
  return L;
}

void make_canonical(std::vector<Loop>& loops) {
  for (Loop& l : loops) {
    const double a = signed_area(l.points);
    if ((!l.hole && a < 0) || (l.hole && a > 0)) std::reverse(l.points.begin(), l.points.end());
  }
}

AreaMoments area_moments(const std::vector<Loop>& loops) {
  // Green's theorem over canonical rings: holes (clockwise) subtract by themselves. Moments about a
  // reference point for precision.
  AreaMoments m;
  Vec2 ref = Vec2::Zero();
  for (const Loop& l : loops)
    if (!l.points.empty()) {
      ref = l.points[0];
      break;
    }
  double A = 0, Sx = 0, Sy = 0, Sxx = 0, Syy = 0, Sxy = 0;
  for (const Loop& l : loops) {
    const std::size_t n = l.points.size();
    for (std::size_t i = 0; i < n; ++i) {
      const Vec2 p = l.points[i] - ref, q = l.points[(i + 1) % n] - ref;
      const double c = p.x() * q.y() - q.x() * p.y();
      A += c;
      Sx += (p.x() + q.x()) * c;
      Sy += (p.y() + q.y()) * c;
      Sxx += (p.x() * p.x() + p.x() * q.x() + q.x() * q.x()) * c;
      Syy += (p.y() * p.y() + p.y() * q.y() + q.y() * q.y()) * c;
      Sxy += (p.x() * q.y() + 2 * p.x() * p.y() + 2 * q.x() * q.y() + q.x() * p.y()) * c;
    }
  }
  A /= 2;
  m.area = A;
  if (std::abs(A) <= 0) return m;
  const Vec2 c(Sx / (6 * A), Sy / (6 * A));
  m.centroid = ref + c;
  // Central second moments.
  const double Ixx = Sxx / 12 - A * c.x() * c.x(), Iyy = Syy / 12 - A * c.y() * c.y(),
               Ixy = Sxy / 24 - A * c.x() * c.y();
  Eigen::Matrix2d C;
  C << Ixx, Ixy, Ixy, Iyy;
  Eigen::SelfAdjointEigenSolver<Eigen::Matrix2d> es(C);
  m.major_axis = es.eigenvectors().col(1).normalized();  // largest spread = the part's long axis
  return m;
}

std::string check_outline(const OutlineInput& in) {
  auto finite3 = [](const Vec3& v) { return v.allFinite(); };
  if (!finite3(in.plane.origin) || !finite3(in.plane.u) || !finite3(in.plane.v) || !finite3(in.plane.normal))
    return "plane has a non-finite value";
  const double nu = in.plane.u.norm(), nv = in.plane.v.norm(), nn = in.plane.normal.norm();
  if (std::abs(nu - 1) > 1e-3 || std::abs(nv - 1) > 1e-3 || std::abs(nn - 1) > 1e-3)
    return "plane axes are not unit vectors";
  if (std::abs(in.plane.u.dot(in.plane.v)) > 1e-3 || std::abs(in.plane.u.dot(in.plane.normal)) > 1e-3 ||
      std::abs(in.plane.v.dot(in.plane.normal)) > 1e-3)
    return "plane axes are not orthogonal";
  if (in.plane.u.cross(in.plane.v).dot(in.plane.normal) < 0) return "plane axes (u, v, normal) are not right-handed";
  if (in.loops.empty()) return "outline has no loops";
  bool outer = false;
  for (std::size_t k = 0; k < in.loops.size(); ++k) {
    const Loop& l = in.loops[k];
    if (l.points.size() < 3) return "loop " + std::to_string(k) + " has fewer than 3 points";
    for (std::size_t i = 0; i < l.points.size(); ++i)
      if (!l.points[i].allFinite())
        return "loop " + std::to_string(k) + " point " + std::to_string(i) + " is not finite";
    if (signed_area(l.points) == 0) return "loop " + std::to_string(k) + " has zero area";
    outer |= !l.hole;
  }
  if (!outer) return "outline has holes but no outer loop";
  return "";
}

void normalize_up(OutlineInput& in, const Eigen::Isometry3d& camera_to_base) {
  if ((camera_to_base.linear() * in.plane.normal).z() >= 0) return;
  in.plane.normal = -in.plane.normal;
  in.plane.v = -in.plane.v;  // keeps (u, v, normal) right-handed; the point p = o + x u + y v needs y -> -y
  for (Loop& l : in.loops) {
    for (Vec2& p : l.points) p.y() = -p.y();
    std::reverse(l.points.begin(), l.points.end());  // a mirror flips orientation; restore canonical
  }
}

std::vector<Loop> mirror_for_flip(const std::vector<Loop>& loops) {
  const AreaMoments m = area_moments(loops);
  const Eigen::Matrix2d reflect = 2 * m.major_axis * m.major_axis.transpose() - Eigen::Matrix2d::Identity();
  std::vector<Loop> out = loops;
  for (Loop& l : out) {
    for (Vec2& p : l.points) p = m.centroid + reflect * (p - m.centroid);
    std::reverse(l.points.begin(), l.points.end());
  }
  return out;
}

}  // namespace hg::path_planner
