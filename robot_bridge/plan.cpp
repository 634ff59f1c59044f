#include "robot_bridge/plan.hpp"

#include <algorithm>
#include <cstdio>

namespace hg::robot_bridge {

using hullgrind::edge_stretch_t;
using hullgrind::grind_path_t;

namespace {

bool contains(const std::vector<std::int16_t>& v, std::int16_t x) {
  return std::find(v.begin(), v.end(), x) != v.end();
}

const char* cause_name(std::int8_t cause) {
  switch (cause) {
    case edge_stretch_t::CAUSE_UNREACHED: return "unreached";
    case edge_stretch_t::CAUSE_TOO_SMALL: return "too small";
    case edge_stretch_t::CAUSE_CORNER: return "corner";
    case edge_stretch_t::CAUSE_EXCLUDED: return "excluded";
    case edge_stretch_t::CAUSE_NOT_RUN: return "not run";
  }
  return "?";
}

}  // namespace

bool fully_reached(const grind_path_t& plan) {
  if (!plan.unreached.empty()) return false;
  return std::all_of(plan.coverage.begin(), plan.coverage.end(), [](const auto& c) { return c.planned; });
}

std::string check_exclusions(const grind_path_t& plan, const std::vector<std::int16_t>& excluded) {
  for (std::int16_t loop : excluded) {
    const bool in_coverage =
        std::any_of(plan.coverage.begin(), plan.coverage.end(), [&](const auto& c) { return c.loop_index == loop; });
    if (!in_coverage && !contains(plan.loop_index, loop))
      return "loop " + std::to_string(loop) + " is not a loop of plan revision " + std::to_string(plan.revision);
  }
  return "";
}

grind_path_t without_loops(const grind_path_t& plan, const std::vector<std::int16_t>& excluded) {
  grind_path_t out = plan;
  out.position.clear(), out.orientation.clear(), out.speed.clear(), out.kind.clear(), out.loop_index.clear();
  for (int i = 0; i < plan.n; ++i) {
    if (contains(excluded, plan.loop_index[i])) continue;
    // The air move into an excluded loop goes: the one after it joins the neighbours.
    if (plan.loop_index[i] < 0 && i + 1 < plan.n && contains(excluded, plan.loop_index[i + 1])) continue;
    out.position.push_back(plan.position[i]);
    out.orientation.push_back(plan.orientation[i]);
    out.speed.push_back(plan.speed[i]);
    // The first waypoint kept is where the robot comes from its start pose: an approach, whatever it was.
    out.kind.push_back(out.kind.empty() && plan.kind[i] == grind_path_t::KIND_TRAVEL ? +grind_path_t::KIND_APPROACH
                                                                                     : plan.kind[i]);
    out.loop_index.push_back(plan.loop_index[i]);
  }
  out.n = std::int32_t(out.position.size());
  return out;
}

int grind_waypoints(const grind_path_t& plan) {
  return int(std::count(plan.kind.begin(), plan.kind.end(), +grind_path_t::KIND_GRIND));
}

std::vector<edge_stretch_t> unground(const grind_path_t& plan, const std::vector<std::int16_t>& excluded,
                                     const std::string& actor) {
  std::vector<edge_stretch_t> out;
  for (const edge_stretch_t& s : plan.unreached)
    if (!contains(excluded, s.loop_index)) out.push_back(s);
  for (std::int16_t loop : excluded) {
    edge_stretch_t s{};
    s.loop_index = loop;
    for (const auto& c : plan.coverage)
      if (c.loop_index == loop) s.hole = c.hole, s.length = c.edge_length;
    s.cause = edge_stretch_t::CAUSE_EXCLUDED;
    s.reason = "excluded at approval by " + (actor.empty() ? std::string("(nobody named)") : actor);
    out.push_back(s);
  }
  return out;
}

bool is_excluded(const edge_stretch_t& s) { return s.cause == edge_stretch_t::CAUSE_EXCLUDED; }

std::string describe(const std::vector<edge_stretch_t>& stretches) {
  std::string out;
  for (const edge_stretch_t& s : stretches) {
    char buf[96];
    std::snprintf(buf, sizeof buf, "%s %d: %.1f mm at %.1f mm (%s", s.hole ? "hole" : "outer loop", int(s.loop_index),
                  s.length * 1e3, s.start * 1e3, cause_name(s.cause));
    out += (out.empty() ? "" : "; ") + std::string(buf) + (s.reason.empty() ? "" : ": " + s.reason) + ")";
  }
  return out;
}

std::string loop_list(const std::vector<std::int16_t>& loops) {
  std::string out;
  for (std::int16_t l : loops) out += (out.empty() ? "" : ", ") + std::to_string(l);
  return out;
}

}  // namespace hg::robot_bridge
