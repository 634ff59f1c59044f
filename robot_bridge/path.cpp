#include "robot_bridge/path.hpp"

#include <algorithm>
#include <cmath>
#include <stdexcept>

#include "hullgrind/grind_path_t.hpp"
#include "path_file/path_file.hpp"

namespace hg::robot_bridge {

Path from_lcm(const hullgrind::grind_path_t& msg) {
  Path p;
  p.job_id = msg.job_id;
  p.frame = msg.frame;
  const std::size_t n = std::size_t(std::max(0, msg.n));
  p.position.reserve(n);
  for (std::size_t i = 0; i < n; ++i) {
    p.position.emplace_back(msg.position[i][0], msg.position[i][1], msg.position[i][2]);
    p.orientation.emplace_back(msg.orientation[i][0], msg.orientation[i][1], msg.orientation[i][2],
                               msg.orientation[i][3]);
    p.speed.push_back(msg.speed[i]);
    p.kind.push_back(msg.kind[i]);
  }
  return p;
}

const char* kind_name(std::int8_t kind) { return path_file::kind_name(kind); }

Path read_path_json(const std::string& file) { return from_lcm(path_file::read_file(file)); }

namespace {

std::string fmt_vec(const Vec3& v) {
  char buf[96];
  snprintf(buf, sizeof buf, "(%.4f, %.4f, %.4f)", v.x(), v.y(), v.z());
  return buf;
}

std::string check_point(const Vec3& p, const Limits& lim, const std::string& what) {
  if (!motion::inside_workspace(p, lim))
    return what + " " + fmt_vec(p) + " is outside the workspace box " + fmt_vec(lim.workspace_min) + " .. " +
           fmt_vec(lim.workspace_max);
  if (!motion::above_table(p, lim))
    return what + " " + fmt_vec(p) + " is not above the table (z " + std::to_string(lim.table_z) + ")";
  return "";
}

}  // namespace

std::string check_frame(const Path& path, const std::string& base_frame) {
  if (path.frame == base_frame) return "";
  return "the path is in frame '" + path.frame + "', not the cell's base frame '" + base_frame + "' (frames.base)";
}

std::string check_path(const Path& path, const Pose& start, const Limits& lim) {
  const std::size_t n = path.size();
  if (n == 0) return "the path has no waypoints";
  if (path.orientation.size() != n || path.speed.size() != n || path.kind.size() != n)
    return "the path's arrays differ in length";
  if (auto r = check_point(start.position, lim, "the robot's current TCP"); !r.empty()) return r;
  for (std::size_t i = 0; i < n; ++i) {
    const std::string wp = "waypoint " + std::to_string(i) + " (" + kind_name(path.kind[i]) + ")";
    const Vec3& p = path.position[i];
    const Quat& q = path.orientation[i];
    if (!p.allFinite() || !q.coeffs().allFinite() || !std::isfinite(path.speed[i]))
      return wp + " has a non-finite number";
    if (std::abs(q.norm() - 1) > 1e-6)
      return wp + " has a quaternion that is not unit (norm " + std::to_string(q.norm()) + ")";
    if (auto r = check_point(p, lim, wp); !r.empty()) return r;
    if (!(path.speed[i] > 0)) return wp + ": speed " + std::to_string(path.speed[i]) + " m/s is not positive";
    if (path.speed[i] > lim.max_speed)
      return wp + ": speed " + std::to_string(path.speed[i]) + " m/s exceeds the limit " +
             std::to_string(lim.max_speed) + " m/s";
  }
  // Corners: the point before waypoint i is the start pose for i == 0.
  if (const auto f = motion::first_corner_fault(path.position, path.speed, start.position, lim.max_accel))
    return "waypoint " + std::to_string(f->waypoint) + " (" + kind_name(path.kind[f->waypoint]) +
           "): the corner (radius " + std::to_string(f->radius * 1000) + " mm) at " + std::to_string(f->speed) +
           " m/s needs " + std::to_string(f->lateral) + " m/s^2, more than the acceleration limit " +
           std::to_string(lim.max_accel) + " m/s^2";
  return "";
}

Profile::Profile(const Pose& start, const Path& path, double accel) : accel_(accel) {
  p_.push_back(start.position);
  q_.push_back(start.orientation.normalized());
  for (std::size_t i = 0; i < path.size(); ++i) {
    p_.push_back(path.position[i]);
    Quat q = path.orientation[i].normalized();
    if (q.dot(q_.back()) < 0) q.coeffs() = -q.coeffs();  // shortest slerp
    q_.push_back(q);
  }
  const std::size_t m = path.size();  // segments
  len_.resize(m);
  for (std::size_t i = 0; i < m; ++i) len_[i] = (p_[i + 1] - p_[i]).norm();
  // Speeds at the points: rest at both ends, the lower segment speed between, then what braking allows.
  std::vector<double> vj(m + 1, 0.0);
  for (std::size_t i = 1; i < m; ++i) vj[i] = std::min(path.speed[i - 1], path.speed[i]);
  for (std::size_t i = 1; i <= m; ++i)
    vj[i] = std::min(vj[i], std::sqrt(vj[i - 1] * vj[i - 1] + 2 * accel * len_[i - 1]));
  for (std::size_t i = m; i-- > 0;) vj[i] = std::min(vj[i], std::sqrt(vj[i + 1] * vj[i + 1] + 2 * accel * len_[i]));
  v_in_.resize(m);
  v_out_.resize(m);
  v_peak_.resize(m);
  s0_.assign(1, 0.0);
  t0_.assign(1, 0.0);
  for (std::size_t i = 0; i < m; ++i) {
    const double a = accel, L = len_[i], vi = vj[i], vo = vj[i + 1];
    const double vp = std::max({std::min(path.speed[i], std::sqrt((2 * a * L + vi * vi + vo * vo) / 2)), vi, vo});
    v_in_[i] = vi;
    v_out_[i] = vo;
    v_peak_[i] = vp;
    const double d_acc = (vp * vp - vi * vi) / (2 * a), d_dec = (vp * vp - vo * vo) / (2 * a);
    const double d_cruise = std::max(0.0, L - d_acc - d_dec);
    const double t = (vp - vi) / a + (vp - vo) / a + (vp > 0 ? d_cruise / vp : 0);
    s0_.push_back(s0_.back() + L);
    t0_.push_back(t0_.back() + t);
  }
}

Profile::Sample Profile::at(double t) const {
  Sample s;
  if (p_.empty()) return s;
  const std::size_t m = len_.size();
  if (m == 0 || t >= duration()) {
    s.pose = {p_.back(), q_.back()};
    s.waypoint = int(m);
    s.distance = length();
    return s;
  }
  t = std::max(0.0, t);
  std::size_t i = std::size_t(std::upper_bound(t0_.begin(), t0_.end(), t) - t0_.begin()) - 1;
  i = std::min(i, m - 1);
  const double a = accel_, vi = v_in_[i], vo = v_out_[i], vp = v_peak_[i], L = len_[i];
  const double tau = t - t0_[i];
  const double t_acc = (vp - vi) / a, t_dec = (vp - vo) / a;
  const double d_acc = (vp * vp - vi * vi) / (2 * a), d_dec = (vp * vp - vo * vo) / (2 * a);
  const double t_cruise = vp > 0 ? std::max(0.0, L - d_acc - d_dec) / vp : 0;
  double d, v;
  if (tau < t_acc) {
    d = vi * tau + a * tau * tau / 2;
    v = vi + a * tau;
  } else if (tau < t_acc + t_cruise) {
    d = d_acc + vp * (tau - t_acc);
    v = vp;
  } else {
    const double u = std::min(tau - t_acc - t_cruise, t_dec);
    d = d_acc + vp * t_cruise + vp * u - a * u * u / 2;
    v = vp - a * u;
  }
  d = std::clamp(d, 0.0, L);
  const double f = L > 0 ? d / L : 1.0;
  s.pose.position = p_[i] + f * (p_[i + 1] - p_[i]);
  s.pose.orientation = q_[i].slerp(f, q_[i + 1]);
  s.waypoint = int(i);
  s.distance = s0_[i] + d;
  s.speed = v;
  return s;
}

}  // namespace hg::robot_bridge
