// The path file of a planned path, with the planner's coverage.
#include "path_planner/path_json.hpp"

#include "path_planner/lcm.hpp"
#include "path_file/path_file.hpp"

namespace hg::path_planner {

const char* kind_name(std::int8_t kind) { return path_file::kind_name(kind); }

nlohmann::ordered_json path_json(const std::string& job_id, const std::string& frame, const PlanResult& r,
                                 std::int64_t outline_seq) {
  nlohmann::ordered_json j = path_file::to_json(to_lcm(r, job_id, outline_seq, frame, 0));
  j["coverage"] = coverage_json(r);
  return j;
}

nlohmann::ordered_json coverage_json(const PlanResult& r) {
  nlohmann::ordered_json c;
  c["tolerance"] = r.coverage_tolerance;
  c["unreached_length"] = r.unreached_length;
  auto loops = nlohmann::ordered_json::array();
  for (const LoopCoverage& l : r.coverage) {
    nlohmann::ordered_json jl;
    jl["loop"] = l.loop;
    jl["hole"] = l.hole;
    jl["length"] = l.length;
    jl["reached_fraction"] = l.reached_fraction();
    auto stretches = nlohmann::ordered_json::array();
    for (const UnreachedStretch& s : l.unreached) {
      nlohmann::ordered_json js;
      js["start"] = s.start;
      js["length"] = s.length;
      js["concave"] = s.concave;
      auto pts = nlohmann::ordered_json::array();
      for (const Vec2& p : s.points) {
        const Vec3 b = r.plate_to_base * Vec3(p.x(), p.y(), 0);
        pts.push_back({b.x(), b.y(), b.z()});
      }
      js["points"] = std::move(pts);
      stretches.push_back(std::move(js));
    }
    jl["unreached"] = std::move(stretches);
    loops.push_back(std::move(jl));
  }
  c["loops"] = std::move(loops);
  return c;
}

}  // namespace hg::path_planner
