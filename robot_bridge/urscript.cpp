#include "robot_bridge/urscript.hpp"

#include <algorithm>
#include <cstdio>

#include "hullgrind/grind_path_t.hpp"

namespace hg::robot_bridge {

std::string ur_pose(const Vec3& p, const Quat& q) {
  Eigen::AngleAxisd aa(q.normalized());
  Vec3 r = aa.axis() * aa.angle();
  if (aa.angle() > M_PI) r = aa.axis() * (aa.angle() - 2 * M_PI);  // same rotation, angle within pi
  char buf[256];
  // 1e-9 m / rad resolution: far below the controller's repeatability, and exact enough to check.
  snprintf(buf, sizeof buf, "p[%.9f, %.9f, %.9f, %.9f, %.9f, %.9f]", p.x(), p.y(), p.z(), r.x(), r.y(), r.z());
  return buf;
}

std::string make_script(const Path& path, const ScriptOptions& o) {
  std::string s;
  char line[512];
  snprintf(line, sizeof line, "def %s():\n", o.name.c_str());
  s += line;
  snprintf(line, sizeof line, "  # hullgrind job %s: %zu waypoints, frame %s\n", path.job_id.c_str(), path.size(),
           path.frame.c_str());
  s += line;
  const std::size_t n = path.size();
  for (std::size_t i = 0; i < n; ++i) {
    const std::int8_t k = path.kind[i];
    const bool on_work = k == hullgrind::grind_path_t::KIND_LEAD_IN || k == hullgrind::grind_path_t::KIND_GRIND ||
                         k == hullgrind::grind_path_t::KIND_LEAD_OUT;
    double r = 0;
    if (i + 1 < n && i > 0) {
      const double shorter =
          std::min((path.position[i] - path.position[i - 1]).norm(), (path.position[i + 1] - path.position[i]).norm());
      r = std::min(o.blend_radius, 0.4 * shorter);
    }
    snprintf(line, sizeof line, "  write_output_integer_register(%d, %zu)\n", o.progress_register, i);
    s += line;
    snprintf(line, sizeof line, "  %s(%s, a=%.6f, v=%.6f, r=%.6f)\n", on_work ? "movep" : "movel",
             ur_pose(path.position[i], path.orientation[i]).c_str(), o.accel, path.speed[i], r);
    s += line;
  }
  snprintf(line, sizeof line, "  write_output_integer_register(%d, %d)\nend\n", o.progress_register, int(o.done_tag));
  s += line;
  return s;
}

std::string stop_script(double accel) {
  char buf[128];
  snprintf(buf, sizeof buf, "def hg_stop():\n  stopl(%.6f)\nend\n", accel);
  return buf;
}

}  // namespace hg::robot_bridge
