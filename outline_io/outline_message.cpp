#include "outline_io/outline_message.hpp"

#include <algorithm>
#include <string>

#include "outline_io/outline_writers.hpp"

namespace hg::outline_io {
namespace {

Result result_of(const hullgrind::outline_t& o) {
  Result r;
  r.points_read = std::size_t(o.points_read);
  r.points_used = std::size_t(o.points_used);
  r.duplicates_merged = std::size_t(o.duplicates_merged);
  r.alpha_radius = o.alpha_radius;
  r.alpha_automatic = o.alpha_automatic;
  r.alpha_mode = o.alpha_mode == "local" ? AlphaMode::Local : AlphaMode::Global;
  r.spacing = o.point_spacing;
  r.holes_dropped = std::size_t(std::max(0, o.holes_dropped));
  r.mode = outline::parse_mode(o.mode.empty() ? "dshi" : o.mode);
  r.order = outline::parse_order(o.order.empty() ? "as-is" : o.order);
  r.stats.triangles = std::size_t(o.triangles);
  r.stats.search_cost = std::uint64_t(o.search_cost);
  r.time = {o.time_triangulate * 1e3, o.time_alpha * 1e3, o.time_loops * 1e3, o.compute_time * 1e3};
  for (const auto& l : o.loops) {
    Loop loop;
    loop.hole = l.hole;
    loop.area = l.area;
    loop.perimeter = l.perimeter;
    for (int i = 0; i < l.n; ++i) loop.points.push_back({l.u[std::size_t(i)], l.v[std::size_t(i)]});
    r.loops.push_back(std::move(loop));
  }
  return r;
}

}  // namespace

nlohmann::ordered_json outline_message_json(const hullgrind::outline_t& o, const hullgrind::plate_cloud_t* cloud) {
  PlanarPoints planar;
  planar.projected = true;
  for (int i = 0; i < 3; ++i) {
    planar.plane.origin[i] = o.plane_origin[i];
    planar.plane.normal[i] = o.plane_normal[i];
    planar.plane.u[i] = o.plane_u_axis[i];
    planar.plane.v[i] = o.plane_v_axis[i];
  }
  if (cloud)
    for (int i = 0; i < cloud->n; ++i) planar.points.push_back({cloud->u[std::size_t(i)], cloud->v[std::size_t(i)]});
  RunInfo info;
  info.input = "HG_PLATE_CLOUD seq " + std::to_string(o.cloud_seq);
  info.format = "lcm";
  info.has_z = true;
  info.frame = "camera";
  nlohmann::ordered_json j = outline_json(result_of(o), planar, info);
  j["status"] = o.status;
  if (!o.error_text.empty()) j["error"] = o.error_text;
  // What the outline service computed beyond hg-outline's keys (outline_t; docs/CHANNELS.md).
  j["holes_dropped_area"] = o.holes_dropped_area;
  j["fragments_dropped"] = o.fragments_dropped;
  j["fragments_dropped_area"] = o.fragments_dropped_area;
  if (!o.dropped_text.empty()) j["dropped_text"] = o.dropped_text;
  j["edge_dropout_fraction"] = o.edge_dropout_fraction;
  j["largest_edge_gap"] = o.largest_edge_gap;
  j["quality"] = o.quality == hullgrind::outline_t::QUALITY_OK     ? "ok"
                 : o.quality == hullgrind::outline_t::QUALITY_POOR ? "poor"
                                                                   : "unknown";
  if (!o.quality_text.empty()) j["quality_text"] = o.quality_text;
  return j;
}

}  // namespace hg::outline_io
