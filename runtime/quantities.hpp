// The quantities of a grinding job, each with one name and one range, declared here once and used by every
// reader: the cell file (cell.cpp), the planner's parameters and its check of a job (path_planner/io.cpp,
// plan.cpp), the DDS gateway's check of a plant's request (dds_gateway/convert.cpp), hg-lcm-send, and the
// station's job options. The name is the field's name in job_request_t, grind_path_t, the DDS IDL, the path
// file and the job record (snake_case); as a parameter or YAML key it is kebab-case (key()). The cell may
// narrow a range further for its installation (the tool mounted, max-speed): that is the cell's limit, said
// where it is checked (docs/cell.md), never a second range here.
// Also the waypoint kinds and the travel directions, whose wire values the .lcm files repeat as constants
// (checked against these where both are seen: path_file/path_file.cpp, path_planner/path_planner.cpp).
// Header only, no LCM and no other dependency: the cell library and the command-line tools include it.
#pragma once

#include <cmath>
#include <cstdint>
#include <cstdio>
#include <cstdlib>
#include <optional>
#include <string>
#include <vector>

namespace hg::quantity {

struct Quantity {
  const char* name;  // field name (snake_case); key() gives the parameter's kebab-case spelling
  const char* unit;
  double min, max;  // the range, both ends included
  const char* what;
  // NaN and the infinities are outside every range.
  constexpr bool contains(double v) const { return v >= min && v <= max; }
};

// The effective tool radius: the radius of the disc at the contact, offset of the path from the edge. The
// cell's tool.radius is the tool mounted; a job may ask for a smaller one (a worn disc), never a larger.
inline constexpr Quantity kToolRadius{"tool_radius", "m", 0.001, 0.2, "effective tool radius at the contact"};
// The tool's tilt away from the vertical, leaning out over the air side toward the edge normal. 80 deg at
// most: the disc must still touch the edge with its rim, not its face.
inline constexpr Quantity kTilt{"tilt", "rad", 0, 1.3962634015954636,
                                "tool tilt toward the edge normal (at most 80 deg)"};
inline constexpr Quantity kGrindSpeed{"grind_speed", "m/s", 1e-4, 0.5, "TCP speed along the edge"};
inline constexpr Quantity kTravelSpeed{"travel_speed", "m/s", 1e-4, 2.0, "air-move speed"};
inline constexpr Quantity kStep{"step", "m", 1e-4, 0.05, "resampling step along the path"};
inline constexpr Quantity kSafeHeight{"safe_height", "m", 1e-3, 0.5, "approach/retract height above the plate"};

// Every quantity above, in the order of job_request_t.
inline constexpr const Quantity* kJobQuantities[] = {&kToolRadius,  &kTilt, &kGrindSpeed,
                                                     &kTravelSpeed, &kStep, &kSafeHeight};

// Calls f(quantity, field of each job...) for each job quantity, on objects of any type whose fields carry
// the quantities' names (job_request_t, the DDS JobRequest, the planner's JobParams): the one mapping of a
// name to its field, so a reader checks or copies every quantity without listing them again.
//   for_each_job_quantity([](const Quantity& q, double v) { ... }, request);
//   for_each_job_quantity([](const Quantity&, double& to, double from) { to = from; }, params, request);
template <class F, class... Jobs>
void for_each_job_quantity(F&& f, Jobs&... jobs) {
  f(kToolRadius, jobs.tool_radius...);
  f(kTilt, jobs.tilt...);
  f(kGrindSpeed, jobs.grind_speed...);
  f(kTravelSpeed, jobs.travel_speed...);
  f(kStep, jobs.step...);
  f(kSafeHeight, jobs.safe_height...);
}

// "tool-radius": the parameter and YAML key of a quantity.
inline std::string key(const Quantity& q) {
  std::string k = q.name;
  for (char& c : k)
    if (c == '_') c = '-';
  return k;
}

// The shortest of %g and %.17g that reads back exactly: 0.001, 1.3962634015954636.
inline std::string number_text(double v) {
  char buf[32];
  std::snprintf(buf, sizeof buf, "%g", v);
  if (std::strtod(buf, nullptr) != v) std::snprintf(buf, sizeof buf, "%.17g", v);
  return buf;
}

// "[0.001, 0.2] m": the range as every message states it.
inline std::string range_text(const Quantity& q) {
  std::string s = "[";
  s += number_text(q.min);
  s += ", ";
  s += number_text(q.max);
  s += "] ";
  s += q.unit;
  return s;
}

// Empty when v is in q's range; else "tilt 1.5 rad is outside [0, 1.3962634015954636] rad".
inline std::string out_of_range(const Quantity& q, double v) {
  if (q.contains(v)) return "";
  std::string s = q.name;
  s += " ";
  s += number_text(v);
  s += " ";
  s += q.unit;
  s += " is outside ";
  s += range_text(q);
  return s;
}

}  // namespace hg::quantity

namespace hg::waypoint {

// What a waypoint of a grind path is (grind_path_t.kind; the path file's "kind" names).
enum Kind : std::int8_t { kApproach = 0, kLeadIn = 1, kGrind = 2, kLeadOut = 3, kRetract = 4, kTravel = 5 };
inline constexpr int kKindCount = 6;
inline constexpr const char* kKindNames[kKindCount] = {"approach", "lead_in", "grind", "lead_out", "retract", "travel"};

// Name of a kind ("unknown" outside 0..5).
inline const char* kind_name(std::int8_t kind) { return kind >= 0 && kind < kKindCount ? kKindNames[kind] : "unknown"; }
inline std::optional<std::int8_t> kind_from_name(const std::string& name) {
  for (std::int8_t k = 0; k < kKindCount; ++k)
    if (name == kKindNames[k]) return k;
  return std::nullopt;
}

}  // namespace hg::waypoint

namespace hg::job {

// Which way the tool travels along the edge (job_request_t.direction, DIRECTION_*; the `direction` option of
// the planner, hg-lcm-send and the station, by name).
enum class Direction : std::int8_t { Climb = 0, Conventional = 1 };
inline constexpr const char* kDirectionNames[] = {"climb", "conventional"};  // by wire value

inline const char* direction_name(Direction d) { return kDirectionNames[d == Direction::Conventional ? 1 : 0]; }
// The direction of a wire value, or nothing when it is none (a request is checked, never cast).
inline std::optional<Direction> direction_from_wire(std::int8_t v) {
  if (v == std::int8_t(Direction::Climb)) return Direction::Climb;
  if (v == std::int8_t(Direction::Conventional)) return Direction::Conventional;
  return std::nullopt;
}
// The names, for a parameter's choices.
inline std::vector<std::string> direction_names() { return {kDirectionNames[0], kDirectionNames[1]}; }
inline std::optional<Direction> direction_from_name(const std::string& name) {
  for (std::int8_t v = 0; v < 2; ++v)
    if (name == kDirectionNames[v]) return direction_from_wire(v);
  return std::nullopt;
}

}  // namespace hg::job
