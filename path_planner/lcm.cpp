// The planner's messages: outline_t in, grind_path_t out.
#include "path_planner/lcm.hpp"

#include <cmath>
#include <cstdio>

namespace hg::path_planner {

OutlineInput from_lcm(const hullgrind::outline_t& m) {
  OutlineInput in;
  in.seq = m.header.seq;
  in.point_spacing = std::isfinite(m.point_spacing) && m.point_spacing > 0 ? m.point_spacing : 0;
  in.plane = {Vec3(m.plane_origin[0], m.plane_origin[1], m.plane_origin[2]),
              Vec3(m.plane_u_axis[0], m.plane_u_axis[1], m.plane_u_axis[2]),
              Vec3(m.plane_v_axis[0], m.plane_v_axis[1], m.plane_v_axis[2]),
              Vec3(m.plane_normal[0], m.plane_normal[1], m.plane_normal[2])};
  in.loops.reserve(m.loops.size());
  for (const auto& l : m.loops) {
    Loop loop;
    loop.hole = l.hole;
    const std::size_t n = std::min(l.u.size(), l.v.size());
    loop.points.reserve(n);
    for (std::size_t i = 0; i < n; ++i) loop.points.emplace_back(l.u[i], l.v[i]);
    in.loops.push_back(std::move(loop));
  }
  return in;
}

std::vector<hullgrind::edge_stretch_t> unground_stretches(const PlanResult& r) {
  using hullgrind::edge_stretch_t;
  std::vector<edge_stretch_t> out;
  char buf[160];
  for (const LoopCoverage& c : r.coverage) {
    edge_stretch_t s{};
    s.loop_index = std::int16_t(c.loop);
    s.hole = c.hole;
    if (!c.planned) {
      s.length = c.length;
      s.cause = edge_stretch_t::CAUSE_TOO_SMALL;
      s.reason = "not planned: " + c.skipped;
      out.push_back(s);
      continue;
    }
    for (const UnreachedStretch& u : c.unreached) {
      s.start = u.start;
      s.length = u.length;
      s.cause = u.concave ? edge_stretch_t::CAUSE_CORNER : edge_stretch_t::CAUSE_UNREACHED;
      std::snprintf(buf, sizeof buf, "farther than %.1f + %.1f mm from the tool path%s", r.params.tool_radius * 1e3,
                    r.coverage_tolerance * 1e3, u.concave ? ", at a concave corner or bend tighter than the tool" : "");
      s.reason = buf;
      out.push_back(s);
    }
  }
  return out;
}

hullgrind::grind_path_t to_lcm(const PlanResult& r, const std::string& job_id, std::int64_t outline_seq,
                               const std::string& frame, std::int64_t utime, std::int32_t revision) {
  hullgrind::grind_path_t g{};  // every count zero until filled: a message that encodes
  g.header.utime = utime;
  g.header.frame_id = frame;
  g.job_id = job_id;
  g.outline_seq = outline_seq;
  g.frame = frame;
  g.n = std::int32_t(r.path.size());
  g.position.resize(r.path.size());
  g.orientation.resize(r.path.size());
  g.speed.resize(r.path.size());
  g.kind.resize(r.path.size());
  g.loop_index.resize(r.path.size());
  for (std::size_t i = 0; i < r.path.size(); ++i) {
    const Waypoint& w = r.path[i];
    g.position[i] = {w.position.x(), w.position.y(), w.position.z()};
    g.orientation[i] = {w.orientation.w(), w.orientation.x(), w.orientation.y(), w.orientation.z()};
    g.speed[i] = w.speed;
    g.kind[i] = w.kind;
    g.loop_index[i] = w.loop;
  }
  g.tool_radius = r.params.tool_radius;
  g.tilt = r.params.tilt;
  g.flipped = r.params.flipped;
  g.revision = revision;
  g.compute_time = r.seconds;
  for (const LoopCoverage& c : r.coverage) {
    hullgrind::loop_coverage_t lc{};
    lc.loop_index = std::int16_t(c.loop);
    lc.hole = c.hole;
    lc.planned = c.planned;
    lc.edge_length = c.length;
    lc.reached_length = c.planned ? c.length - c.unreached_length : 0;
    char buf[96];
    std::snprintf(buf, sizeof buf, "%.1f mm of its %.1f mm edge not reached", c.unreached_length * 1e3, c.length * 1e3);
    lc.reason = !c.planned ? c.skipped : c.unreached.empty() ? std::string() : std::string(buf);
    g.coverage.push_back(lc);
  }
  g.num_loops = std::int32_t(g.coverage.size());
  g.unreached = unground_stretches(r);
  g.num_unreached = std::int32_t(g.unreached.size());
  for (std::size_t k = 0; k < r.edges.size(); ++k)
    for (const Vec2& p : r.edges[k]) {
      const Vec3 b = r.plate_to_base * Vec3(p.x(), p.y(), 0);
      g.edge.push_back({b.x(), b.y(), b.z()});
      g.edge_loop.push_back(std::int16_t(k));
    }
  g.num_edge_points = std::int32_t(g.edge.size());
  return g;
}

}  // namespace hg::path_planner
