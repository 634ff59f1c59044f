// The path modifiers (modifiers.hpp): leads, approach, retract, corner speeds, and their composition.
#include "path_planner/modifiers.hpp"

#include <algorithm>
#include <cmath>

namespace hg::path_planner {

std::vector<PlateWaypoint> flatten(const ToolPath& path) {
  std::vector<PlateWaypoint> out;
  for (const Pass& p : path.passes) out.insert(out.end(), p.waypoints.begin(), p.waypoints.end());
  return out;
}

LeadArcs::LeadArcs(double radius, double sweep, double step, double speed)
    : radius_(radius), sweep_(sweep), step_(step), speed_(speed) {}

void LeadArcs::apply(ToolPath& path) const {
  for (Pass& pass : path.passes) {
    std::vector<PlateWaypoint>& w = pass.waypoints;
    if (w.empty()) continue;
    const PlateWaypoint entry = w.front(), end = w.back();
    double radius = radius_;
    if (pass.hole) radius = std::min(radius, 0.3 * std::sqrt(pass.area / M_PI));
    auto at = [&](const Vec2& p, const PlateWaypoint& like, double speed, std::int8_t kind) {
      return PlateWaypoint{Vec3(p.x(), p.y(), like.position.z()), entry.orientation, speed, kind, entry.loop};
    };
    const Vec2 p0 = entry.position.head<2>();
    const std::vector<Vec2> in = lead_in_arc(p0, pass.tangent, pass.away, radius, sweep_, step_);
    const std::vector<Vec2> out = lead_out_arc(end.position.head<2>(), pass.tangent, pass.away, radius, sweep_, step_);
    std::vector<PlateWaypoint> lead;
    lead.push_back(at(in.front(), entry, entry.speed, entry.kind));  // the new entry
    // in.back() is p0 itself: the old entry, now the lead-in's end.
    for (std::size_t k = 1; k + 1 < in.size(); ++k) lead.push_back(at(in[k], entry, speed_, kLeadIn));
    w.front().kind = kLeadIn;
    w.front().speed = speed_;
    w.insert(w.begin(), lead.begin(), lead.end());
    for (std::size_t k = 1; k < out.size(); ++k) w.push_back(at(out[k], end, speed_, kLeadOut));
  }
}

Approach::Approach(double safe_height, double travel_speed) : safe_height_(safe_height), travel_speed_(travel_speed) {}

void Approach::apply(ToolPath& path) const {
  for (std::size_t e = 0; e < path.passes.size(); ++e) {
    std::vector<PlateWaypoint>& w = path.passes[e].waypoints;
    if (w.empty()) continue;
    PlateWaypoint above = w.front();
    above.position.z() += safe_height_;
    above.speed = travel_speed_;
    above.kind = e == 0 ? kApproach : kTravel;
    above.loop = -1;
    w.insert(w.begin(), above);
  }
}

Retract::Retract(double safe_height, double speed) : safe_height_(safe_height), speed_(speed) {}

void Retract::apply(ToolPath& path) const {
  for (Pass& pass : path.passes) {
    if (pass.waypoints.empty()) continue;
    PlateWaypoint above = pass.waypoints.back();
    above.position.z() += safe_height_;
    above.speed = speed_;
    above.kind = kRetract;
    pass.waypoints.push_back(above);
  }
}

CornerSpeeds::CornerSpeeds(double max_accel) : max_accel_(max_accel) {}

void CornerSpeeds::apply(ToolPath& path) const {
  std::vector<Waypoint> all = to_base(flatten(path), path.plate_to_base);
  path.speeds_lowered += limit_corner_speeds(all, path.start, max_accel_);
  std::size_t i = 0;
  for (Pass& pass : path.passes)
    for (PlateWaypoint& w : pass.waypoints) w.speed = all[i++].speed;
}

CompoundModifier::CompoundModifier(std::vector<std::unique_ptr<PathModifier>> modifiers)
    : modifiers_(std::move(modifiers)) {}

void CompoundModifier::apply(ToolPath& path) const {
  for (const auto& m : modifiers_) m->apply(path);
}

const std::vector<std::string>& modifier_names() {
  static const std::vector<std::string> names = {"leads", "approach", "retract", "corner-speeds"};
  return names;
}

std::string check_modifier_list(const std::vector<std::string>& names) {
  const std::vector<std::string>& known = modifier_names();
  std::string all;
  for (const std::string& k : known) all += (all.empty() ? "" : ", ") + k;
  std::ptrdiff_t last = -1;
  for (const std::string& n : names) {
    const auto it = std::find(known.begin(), known.end(), n);
    if (it == known.end()) return "unknown path modifier '" + n + "' (the modifiers: " + all + ")";
    const std::ptrdiff_t at = it - known.begin();
    if (at == last) return "'" + n + "' is listed twice";
    if (at < last) return "'" + n + "' after '" + known[std::size_t(last)] + "': they compose in the order " + all;
    last = at;
  }
  return "";
}

double approach_speed(const JobParams& job, const PlannerConfig& config) {
  return std::min(config.approach_speed, job.travel_speed);
}

CompoundModifier compose_modifiers(const std::vector<std::string>& names, const JobParams& job,
                                   const PlannerConfig& config) {
  std::vector<std::unique_ptr<PathModifier>> list;
  for (const std::string& n : names) {
    if (n == "leads")
      list.push_back(std::make_unique<LeadArcs>(config.lead_radius, config.lead_angle, job.step, job.grind_speed));
    else if (n == "approach")
      list.push_back(std::make_unique<Approach>(job.safe_height, job.travel_speed));
    else if (n == "retract")
      list.push_back(std::make_unique<Retract>(job.safe_height, approach_speed(job, config)));
    else if (n == "corner-speeds")
      list.push_back(std::make_unique<CornerSpeeds>(config.limits.max_accel));
  }
  return CompoundModifier(std::move(list));
}

}  // namespace hg::path_planner
