#include "polygon/polygon.hpp"

#include <cmath>

namespace hg::polygon {

double signed_area(std::span<const Vec2> ring) {
  const std::size_t n = ring.size();
  if (n < 3) return 0;
  double a = 0;
  const Vec2 o = ring[0];
  for (std::size_t i = 1; i + 1 < n; ++i) {
    const Vec2 p = ring[i] - o, q = ring[i + 1] - o;
    a += p.x() * q.y() - p.y() * q.x();
  }
  return a / 2;
}

double ring_length(std::span<const Vec2> ring) {
  double length = 0;
  for (std::size_t i = 0, n = ring.size(); i < n; ++i) length += (ring[(i + 1) % n] - ring[i]).norm();
  return length;
}

void MomentSum::add(std::span<const Vec2> ring) {
  for (std::size_t i = 0, n = ring.size(); i < n; ++i) {
    const Vec2 p = ring[i] - ref_, q = ring[(i + 1) % n] - ref_;
    const double c = p.x() * q.y() - q.x() * p.y();
    a_ += c;
    sx_ += (p.x() + q.x()) * c;
    sy_ += (p.y() + q.y()) * c;
    sxx_ += (p.x() * p.x() + p.x() * q.x() + q.x() * q.x()) * c;
    syy_ += (p.y() * p.y() + p.y() * q.y() + q.y() * q.y()) * c;
    sxy_ += (p.x() * q.y() + 2 * p.x() * p.y() + 2 * q.x() * q.y() + q.x() * p.y()) * c;
  }
}

AreaMoments MomentSum::moments() const {
  AreaMoments m;
  m.area = a_ / 2;
  m.centroid = ref_;
  if (m.area == 0) return m;
  const Vec2 c(sx_ / (6 * m.area), sy_ / (6 * m.area));
  m.centroid = ref_ + c;
  m.ixx = sxx_ / 12 - m.area * c.x() * c.x();
  m.iyy = syy_ / 12 - m.area * c.y() * c.y();
  m.ixy = sxy_ / 24 - m.area * c.x() * c.y();
  return m;
}

double AreaMoments::principal_axis_angle() const {
  // The eigenvector of the larger eigenvalue of [[ixx, ixy], [ixy, iyy]] (the covariance of the area).
  double angle = 0.5 * std::atan2(2 * ixy, ixx - iyy);
  if (angle <= -M_PI / 2) angle += M_PI;
  return angle;
}

Vec2 AreaMoments::principal_axis() const {
  const double angle = principal_axis_angle();
  return Vec2(std::cos(angle), std::sin(angle));
}

}  // namespace hg::polygon
