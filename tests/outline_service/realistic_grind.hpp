// The grind edge on the realistic presets (issue 23 §4): the outline of realistic_scan.hpp planned as
// `make run` plans (config/path_planner.yaml with the simulated cell: 10 mm tool, small-hole fail), and the
// planner's smoothed edge (what the tool grinds) carried into the table frame and measured against the
// renderer's polygons. Link hg_path_planner and hg_cell besides realistic_scan.hpp's libraries; needs
// HG_SOURCE_DIR.
#pragma once

#include <map>
#include <string>

#include "path_planner/io.hpp"
#include "path_planner/pipeline.hpp"
#include "realistic_scan.hpp"
#include "runtime/config.hpp"
#include "tests/common/cell_file.hpp"

namespace hg::test {

inline path_planner::PlannerConfig make_run_planner() {
  std::map<std::string, std::string> overrides{{"cell", sim_cell()}};
  return path_planner::config_from(path_planner::lookup_from(
      overrides, runtime::Config::load(std::string(HG_SOURCE_DIR) + "/config/path_planner.yaml")));
}

struct GrindAccuracy {
  bool planned = false;
  std::string reason;       // why not, when !planned
  int loops_planned = 0;    // loops ground (every loop the outline has, when every cut-out is planned)
  double unreached = 0;     // m of edge beyond the tool's reach
  double rms = 0, max = 0;  // the smoothed edge to the true edge (max: symmetric Hausdorff), metres
  Eigen::Vector2d worst = Eigen::Vector2d::Zero();  // where `max` is (table frame, on the edge it was measured from)
};

// The simulated cell's table in its robot's base frame: its camera_to_base is calibrated for the pm806
// profile's mount (1.5 m); a camera mounted elsewhere (lsr-l: 2.0 m) over the same table needs its own.
inline Eigen::Isometry3d base_from_table(const path_planner::PlannerConfig& sim_cell_config) {
  const sim::RenderedFrame pm806 = sim::render(sim::scene_preset("empty"), sim::camera_profile("pm806"), 0);
  return sim_cell_config.camera_to_base * pm806.camera_from_table;
}

// `config`: make_run_planner()'s, with camera_to_base calibrated for the frame's camera (`table_to_base`:
// base_from_table() of it). `points`: when given, the grind edge's points measured (table frame).
inline GrindAccuracy grind_edge(const hullgrind::outline_t& o, const sim::RenderedFrame& f,
                                const path_planner::PlannerConfig& config, const Eigen::Isometry3d& table_to_base,
                                std::vector<Eigen::Vector2d>* points = nullptr) {
  path_planner::PlannerConfig cfg = config;
  cfg.camera_to_base = table_to_base * f.camera_from_table.inverse();
  GrindAccuracy g;
  const path_planner::PlanResult r = path_planner::plan(path_planner::from_lcm(o), {}, cfg, std::nullopt);
  g.planned = r.ok, g.reason = r.reason, g.loops_planned = r.loops_planned, g.unreached = r.unreached_length;
  if (r.edges.empty()) return g;
  const Eigen::Isometry3d table_from_base = (cfg.camera_to_base * f.camera_from_table).inverse();
  const auto& truth = f.part_polygons.at(0);
  std::vector<Ring2> truth_rings{Ring2(truth.outer.begin(), truth.outer.end())}, got;
  for (const auto& h : truth.holes) truth_rings.emplace_back(h.begin(), h.end());
  double sq = 0;
  int n = 0;
  for (const path_planner::Ring& e : r.edges) {
    Ring2 ring;
    for (const Eigen::Vector2d& p : e)
      ring.push_back((table_from_base * (r.plate_to_base * Eigen::Vector3d(p.x(), p.y(), 0))).head<2>());
    for (const auto& p : densified(ring, 5e-4)) {
      const double d = rings_dist(p, truth_rings);
      sq += d * d, ++n;
      if (points) points->push_back(p);
      if (d > g.max) g.max = d, g.worst = p;
    }
    got.push_back(ring);
  }
  g.rms = n ? std::sqrt(sq / n) : 0;
  for (const Ring2& t : truth_rings)
    for (const auto& p : densified(t, 5e-4))
      if (const double d = rings_dist(p, got); d > g.max) g.max = d, g.worst = p;
  return g;
}

}  // namespace hg::test
