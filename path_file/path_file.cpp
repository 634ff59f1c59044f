#include "path_file/path_file.hpp"

#include "runtime/quantities.hpp"

#include <fstream>
#include <sstream>
#include <stdexcept>

namespace hg::path_file {

namespace {

using waypoint::kKindCount;
// The wire constants of grind_path_t.lcm are the kinds of runtime/quantities.hpp, value for value.
static_assert(hullgrind::grind_path_t::KIND_APPROACH == waypoint::kApproach &&
              hullgrind::grind_path_t::KIND_LEAD_IN == waypoint::kLeadIn &&
              hullgrind::grind_path_t::KIND_GRIND == waypoint::kGrind &&
              hullgrind::grind_path_t::KIND_LEAD_OUT == waypoint::kLeadOut &&
              hullgrind::grind_path_t::KIND_RETRACT == waypoint::kRetract &&
              hullgrind::grind_path_t::KIND_TRAVEL == waypoint::kTravel && kKindCount == 6);

struct SchemaError : std::runtime_error {
  using std::runtime_error::runtime_error;
};

std::vector<double> numbers(const nlohmann::json& a, std::size_t n, const std::string& where) {
  if (!a.is_array() || a.size() != n) throw SchemaError(where + ": expected " + std::to_string(n) + " numbers");
  std::vector<double> out;
  for (const auto& x : a) {
    if (!x.is_number()) throw SchemaError(where + ": expected " + std::to_string(n) + " numbers");
    out.push_back(x.get<double>());
  }
  return out;
}

std::int8_t kind_of(const nlohmann::json& k, const std::string& where) {
  if (k.is_string())
    if (auto v = kind_from_name(k.get<std::string>())) return *v;
  if (k.is_number_integer() && k.get<std::int64_t>() >= 0 && k.get<std::int64_t>() < kKindCount)
    return std::int8_t(k.get<std::int64_t>());  // the KIND_* number itself
  std::string names;
  for (const char* n : waypoint::kKindNames) names += std::string(names.empty() ? "" : ", ") + n;
  throw SchemaError(where + ": unknown kind " + k.dump() + " (one of " + names + ", or its number 0..5)");
}

template <class T>
T optional_key(const nlohmann::json& j, const char* key, T fallback, bool (nlohmann::json::*is)() const noexcept,
               const std::string& where = "") {
  if (!j.contains(key)) return fallback;
  if (!(j[key].*is)()) throw SchemaError(where + std::string(key) + ": wrong type (" + j[key].dump() + ")");
  return j[key].get<T>();
}

void read_waypoint(const nlohmann::json& w, const std::string& where, hullgrind::grind_path_t& p) {
  if (!w.is_object()) throw SchemaError(where + ": expected an object");
  for (const char* k : {"position", "orientation", "speed", "kind"})
    if (!w.contains(k)) throw SchemaError(where + ": no \"" + k + "\"");
  const auto pos = numbers(w["position"], 3, where + ": position");
  const auto q = numbers(w["orientation"], 4, where + ": orientation");
  if (!w["speed"].is_number()) throw SchemaError(where + ": speed: expected a number");
  p.position.push_back({pos[0], pos[1], pos[2]});
  p.orientation.push_back({q[0], q[1], q[2], q[3]});
  p.speed.push_back(w["speed"].get<double>());
  p.kind.push_back(kind_of(w["kind"], where + ": kind"));
  const auto loop = optional_key<std::int64_t>(w, "loop", -1, &nlohmann::json::is_number_integer, where + ": ");
  if (loop < -1 || loop > INT16_MAX) throw SchemaError(where + ": loop: " + std::to_string(loop) + " is out of range");
  p.loop_index.push_back(std::int16_t(loop));
}

}  // namespace

const char* kind_name(std::int8_t kind) { return waypoint::kind_name(kind); }

std::optional<std::int8_t> kind_from_name(const std::string& name) { return waypoint::kind_from_name(name); }

nlohmann::ordered_json to_json(const hullgrind::grind_path_t& p) {
  nlohmann::ordered_json j;
  j["job_id"] = p.job_id;
  j["frame"] = p.frame;
  j["outline_seq"] = p.outline_seq;
  j["tool_radius"] = p.tool_radius;
  j["tilt"] = p.tilt;
  j["flipped"] = bool(p.flipped);
  auto wps = nlohmann::ordered_json::array();
  for (std::size_t i = 0; i < std::size_t(std::max(0, p.n)); ++i) {
    nlohmann::ordered_json w;
    w["position"] = {p.position[i][0], p.position[i][1], p.position[i][2]};
    w["orientation"] = {p.orientation[i][0], p.orientation[i][1], p.orientation[i][2], p.orientation[i][3]};
    w["speed"] = p.speed[i];
    w["kind"] = kind_name(p.kind[i]);
    w["loop"] = p.loop_index[i];
    wps.push_back(std::move(w));
  }
  j["waypoints"] = std::move(wps);
  return j;
}

std::string to_text(const hullgrind::grind_path_t& p) { return to_json(p).dump(1) + "\n"; }

hullgrind::grind_path_t from_json_text(const std::string& text, const std::string& name) {
  nlohmann::json j;
  try {
    j = nlohmann::json::parse(text);
  } catch (const nlohmann::json::parse_error& e) {
    throw std::runtime_error(name + ": not JSON (byte " + std::to_string(e.byte) + "): " + e.what());
  }
  hullgrind::grind_path_t p{};
  try {
    if (!j.is_object()) throw SchemaError("expected a JSON object at the top level");
    if (!j.contains("waypoints") || !j["waypoints"].is_array()) throw SchemaError("no \"waypoints\" array");
    p.job_id = optional_key<std::string>(j, "job_id", "", &nlohmann::json::is_string);
    p.frame = optional_key<std::string>(j, "frame", "", &nlohmann::json::is_string);
    p.header.frame_id = p.frame;
    p.outline_seq = optional_key<std::int64_t>(j, "outline_seq", -1, &nlohmann::json::is_number_integer);
    p.tool_radius = optional_key<double>(j, "tool_radius", 0.0, &nlohmann::json::is_number);
    p.tilt = optional_key<double>(j, "tilt", 0.0, &nlohmann::json::is_number);
    p.flipped = optional_key<bool>(j, "flipped", false, &nlohmann::json::is_boolean);
    const auto& wps = j["waypoints"];
    for (std::size_t i = 0; i < wps.size(); ++i) read_waypoint(wps[i], "waypoint " + std::to_string(i), p);
    p.n = std::int32_t(p.position.size());
  } catch (const SchemaError& e) {
    throw std::runtime_error(name + ": " + e.what());
  }
  return p;
}

hullgrind::grind_path_t read_file(const std::string& file) {
  std::ifstream in(file, std::ios::binary);
  if (!in) throw std::runtime_error(file + ": cannot open");
  std::stringstream ss;
  ss << in.rdbuf();
  return from_json_text(ss.str(), file);
}

}  // namespace hg::path_file
