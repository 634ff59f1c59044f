#include "outline_service/outline_service.hpp"

#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <string>

#include "cell/cell_params.hpp"
#include "hullgrind/heartbeat_t.hpp"
#include "outline_service/part_pose.hpp"
#include "runtime/channels.hpp"

namespace hg::outline_service {

namespace {
// The core's default, as text for the parameter table.
const std::string kMinHoleDefault = [] {
  char b[32];
  std::snprintf(b, sizeof b, "%g", outline::kDefaultMinHoleSpacings);
  return std::string(b);
}();
}  // namespace

runtime::ProcessInfo process_info() {
  return {
      "hg-outline-service",
      "Plate points (HG_PLATE_CLOUD) -> outline (HG_OUTLINE) + part pose (HG_PART_POSE).",
      "Runs the DSHI outline core on every plate cloud. If clouds arrive faster than it computes, the\n"
      "newest wins: older ones are dropped and counted (heartbeat 'dropped'); the heartbeat's last_latency\n"
      "is cloud received -> outline published. A cloud that gives no valid loop is answered by an outline\n"
      "with status NO_LOOP or ERROR and the reason, never a made-up loop. One part_pose_t per part\n"
      "(largest first): area centroid and principal axis with the holes subtracted.",
      {{"alpha-radius", "0", "alpha radius R in metres (triangles with circumradius > R are outside); 0: automatic",
        false, runtime::ParamType::Number, 0},
       {"auto-factor", "0",
        "automatic R = factor x point spacing (sqrt(2 x median Delaunay triangle area)); 0: the outline core's default",
        false, runtime::ParamType::Number, 0},
       runtime::text_param(
           "alpha-mode", "global",
           "global: one automatic R for the cloud; local: R per triangle from the spacing around it (spacing varying across the cloud, tilted camera); not with alpha-radius",
           {"global", "local"}),
       runtime::text_param("mode", "dshi", "point location: ordinary|ds|dshi", {"ordinary", "ds", "dshi"}),
       runtime::text_param(
           "order", "brio",
           "insertion order: brio (default: biased randomized rounds of Hilbert order, 2-3x faster on camera clouds)|hilbert|as-is (the scan order the paper inserts in)",
           {"brio", "hilbert", "as-is"}),
       {"outer-only", "", "remove only big triangles connected to the outside (the paper's BFS): no holes", true},
       runtime::integer_param(
           "threads", "0",
           "threads of the outline core (0: all cores): vertical strips, loops identical to one thread's; one thread below 100 k points per strip",
           0, 1024),
       {"min-hole-spacings", kMinHoleDefault,
        "drop holes smaller in area than (this x point spacing)^2: dropout, not cut-outs (0: keep all); the outline core's rule, as hg-outline",
        false, runtime::ParamType::Number, 0},
       cell::cell_param()}};
}

ServiceOptions options_from(const runtime::Node& node) {
  ServiceOptions o;
  o.min_hole_spacings = node.params().number("min-hole-spacings");
  if (!(o.min_hole_spacings >= 0) || std::isinf(o.min_hole_spacings))
    throw runtime::ConfigError("min-hole-spacings must be a number >= 0");
  o.alpha_radius = node.params().number("alpha-radius");
  o.auto_factor = node.params().number("auto-factor");
  // Each key parsed on its own, so that the error names it.
  auto parsed = [&](const char* key, auto parse) {
    try {
      return parse(node.params().text(key));
    } catch (const outline::OutlineError& e) {
      throw runtime::ConfigError(std::string(key) + ": " + e.what());
    }
  };
  o.mode = parsed("mode", outline::parse_mode);
  o.order = parsed("order", outline::parse_order);
  o.alpha_mode = parsed("alpha-mode", outline::parse_alpha_mode);
  if (o.alpha_mode == outline::AlphaMode::Local && o.alpha_radius > 0)
    throw runtime::ConfigError("alpha-mode local sets the radius per triangle: alpha-radius must be 0");
  o.outer_only = node.params().flag("outer-only");
  o.threads = static_cast<int>(node.params().integer("threads"));
  const cell::LoadedCell cell = cell::load_cell(node.params());  // the smallest part, the edge-quality limits
  o.min_part_area = cell.cell.outline.min_part_area;
  o.max_edge_dropout = cell.cell.outline.max_edge_dropout;
  o.max_edge_gap = cell.cell.outline.max_edge_gap;
  o.cell_file = cell.file;
  return o;
}

namespace {

// The outline message's fields that come from the cloud and the options, before any computation.
void start_outline(const hullgrind::plate_cloud_t& cloud, const outline::Options& options, hullgrind::outline_t& out) {
  out.header.frame_id = cloud.header.frame_id;
  out.header.utime = cloud.header.utime;
  out.cloud_seq = cloud.header.seq;
  for (int i = 0; i < 3; ++i) {
    out.plane_origin[i] = cloud.plane_origin[i];
    out.plane_normal[i] = cloud.plane_normal[i];
    out.plane_u_axis[i] = cloud.plane_u_axis[i];
    out.plane_v_axis[i] = cloud.plane_v_axis[i];
  }
  out.thickness = cloud.thickness;
  out.flange_valid = cloud.flange_valid;  // eye-in-hand: where the camera was when the cloud was captured
  std::copy(cloud.flange_position, cloud.flange_position + 3, out.flange_position);
  std::copy(cloud.flange_orientation, cloud.flange_orientation + 4, out.flange_orientation);
  out.num_loops = 0;
  out.points_read = cloud.n;
  out.mode = outline::to_string(options.mode);
  out.order = outline::to_string(options.order);
  out.alpha_mode = outline::to_string(options.alpha_mode);
  out.alpha_automatic = !(options.alpha_radius > 0);
  out.holes_dropped = out.fragments_dropped = 0;  // the generated struct leaves its numbers uninitialised
  out.holes_dropped_area = out.fragments_dropped_area = out.edge_dropout_fraction = out.largest_edge_gap = 0;
  out.quality = hullgrind::outline_t::QUALITY_UNKNOWN;
}

// The core's result into the outline message (statistics and loops); true when there is an outer loop.
bool put_result(const outline::Result& r, hullgrind::outline_t& out) {
  out.alpha_radius = r.alpha_radius;
  out.points_read = int32_t(r.points_read);
  out.points_used = int32_t(r.points_used);
  out.duplicates_merged = int32_t(r.duplicates_merged);
  out.mode = outline::to_string(r.mode);
  out.order = outline::to_string(r.order);
  out.time_triangulate = r.time.triangulate_ms * 1e-3;
  out.time_alpha = r.time.alpha_ms * 1e-3;
  out.time_loops = r.time.loops_ms * 1e-3;
  out.triangles = int32_t(r.stats.triangles);
  out.search_cost = int64_t(r.stats.search_cost);
  // What the planner needs to know about the cloud (it takes no pixel pitch from anyone else).
  out.point_spacing = r.spacing;
  out.alpha_mode = outline::to_string(r.alpha_mode);
  out.alpha_automatic = r.alpha_automatic;
  bool any_outer = false;
  for (const outline::Loop& l : r.loops) {
    hullgrind::outline_loop_t m;
    m.hole = l.hole;
    any_outer |= !l.hole;
    m.n = int32_t(l.points.size());
    for (const auto& p : l.points) {
      m.u.push_back(p.x);
      m.v.push_back(p.y);
    }
    m.area = l.area;
    m.perimeter = l.perimeter;
    out.loops.push_back(std::move(m));
  }
  return any_outer;
}

bool inside(const std::vector<outline::Vec2>& ring, const outline::Vec2& p) {  // even-odd rule
  bool in = false;
  for (std::size_t i = 0, j = ring.size() - 1; i < ring.size(); j = i++)
    if ((ring[i].y > p.y) != (ring[j].y > p.y) &&
        p.x < (ring[j].x - ring[i].x) * (p.y - ring[i].y) / (ring[j].y - ring[i].y) + ring[i].x)
      in = !in;
  return in;
}

std::string number(const char* f, double v) {
  char b[64];
  std::snprintf(b, sizeof b, f, v);
  return b;
}

// Outer loops smaller than the cell's min-part-area, with the holes inside them, are fragments: taken out
// of the loops, counted and said in the outline (the holes go with the fragment that holds them).
void drop_fragments(std::vector<outline::Loop>& loops, const ServiceOptions& o, hullgrind::outline_t& out) {
  std::vector<bool> drop(loops.size(), false);
  for (std::size_t i = 0; i < loops.size(); ++i) {
    if (loops[i].hole || !(loops[i].area < o.min_part_area)) continue;
    drop[i] = true;
    ++out.fragments_dropped;
    out.fragments_dropped_area += loops[i].area;
    for (std::size_t j = 0; j < loops.size(); ++j)
      if (loops[j].hole && !loops[j].points.empty() && inside(loops[i].points, loops[j].points.front())) drop[j] = true;
  }
  std::size_t k = 0;
  std::erase_if(loops, [&](const outline::Loop&) { return drop[k++]; });
  if (out.fragments_dropped)
    out.dropped_text = std::to_string(out.fragments_dropped) + " fragment(s) of " +
                       number("%.3g", out.fragments_dropped_area * 1e6) + " mm^2 in all dropped: outer loops under " +
                       o.cell_file + (o.cell_file.empty() ? "" : " ") + "outline.min-part-area " +
                       number("%g", o.min_part_area) + " m^2";
}

// The camera bridge's filled dropout joins the core's dropped holes; one line says both.
void count_dropout(const hullgrind::plate_cloud_t& cloud, std::size_t core_dropped, hullgrind::outline_t& out) {
  out.holes_dropped = int32_t(cloud.dropout_filled + core_dropped);
  out.holes_dropped_area = cloud.dropout_filled_area;
  std::string said;
  if (cloud.dropout_filled)
    said = std::to_string(cloud.dropout_filled) + " dropout patch(es) inside the plate filled by the camera bridge (" +
           number("%.3g", cloud.dropout_filled_area * 1e6) + " mm^2: no return, no sign of a cut)";
  if (core_dropped)
    said += (said.empty() ? "" : "; ") + std::to_string(core_dropped) + " hole(s) under min-hole-spacings dropped";
  if (!said.empty()) out.dropped_text += (out.dropped_text.empty() ? "" : "; ") + said;
}

// The scan-quality verdict: the bridge's edge figures against the cell's limits. UNKNOWN when no organized
// frame was behind the cloud.
void judge_quality(const hullgrind::plate_cloud_t& cloud, const ServiceOptions& o, hullgrind::outline_t& out) {
  out.edge_dropout_fraction = cloud.edge_dropout_fraction;
  out.largest_edge_gap = cloud.largest_edge_gap;
  if (!cloud.edge_assessed) {
    out.quality = hullgrind::outline_t::QUALITY_UNKNOWN;
    out.quality_text = "the cloud's edge was not assessed (no organized frame behind it)";
    return;
  }
  const std::string cell = o.cell_file.empty() ? "" : o.cell_file + " ";
  std::string why;
  if (cloud.edge_dropout_fraction > o.max_edge_dropout)
    why = number("%.1f", 100 * cloud.edge_dropout_fraction) + " % of the edge in dropout or shadow (" + cell +
          "outline.max-edge-dropout " + number("%g", o.max_edge_dropout) + ")";
  if (cloud.largest_edge_gap > o.max_edge_gap)
    why += (why.empty() ? "" : "; ") + std::string("a gap of ") + number("%.1f", 1e3 * cloud.largest_edge_gap) +
           " mm along the edge (" + cell + "outline.max-edge-gap " + number("%g", o.max_edge_gap) + " m)";
  out.quality = why.empty() ? hullgrind::outline_t::QUALITY_OK : hullgrind::outline_t::QUALITY_POOR;
  out.quality_text = why;
}

// One part pose message per part of the loops, the centroid also in the cloud's frame.
std::vector<hullgrind::part_pose_t> pose_messages(const hullgrind::plate_cloud_t& cloud,
                                                  const std::vector<outline::Loop>& loops, double spacing) {
  std::vector<hullgrind::part_pose_t> out;
  std::vector<PartPose> poses = part_poses(loops, spacing);
  for (std::size_t k = 0; k < poses.size(); ++k) {
    const PartPose& p = poses[k];
    hullgrind::part_pose_t m{};
    m.header.frame_id = cloud.header.frame_id;
    m.header.utime = cloud.header.utime;
    m.cloud_seq = cloud.header.seq;
    m.part_index = int16_t(k);
    m.num_parts = int16_t(poses.size());
    m.centroid_uv[0] = p.centroid.x;
    m.centroid_uv[1] = p.centroid.y;
    for (int i = 0; i < 3; ++i)
      m.centroid_xyz[i] =
          cloud.plane_origin[i] + p.centroid.x * cloud.plane_u_axis[i] + p.centroid.y * cloud.plane_v_axis[i];
    m.principal_axis_angle = p.principal_axis_angle;
    m.area = p.area;
    m.bbox_min_uv[0] = p.bbox_min.x, m.bbox_min_uv[1] = p.bbox_min.y;
    m.bbox_max_uv[0] = p.bbox_max.x, m.bbox_max_uv[1] = p.bbox_max.y;
    m.obb_size[0] = p.major_extent, m.obb_size[1] = p.minor_extent;
    out.push_back(m);
  }
  return out;
}

}  // namespace

Computed compute(const hullgrind::plate_cloud_t& cloud, const ServiceOptions& service_options) {
  const outline::Options& options = service_options;  // the core's part
  Computed c;
  hullgrind::outline_t& out = c.outline;
  start_outline(cloud, options, out);
  auto fail = [&](int8_t status, std::string why) {
    out.status = status;
    out.error_text = std::move(why);
    out.loops.clear();
    out.num_loops = 0;
    return c;
  };
  if (cloud.status != hullgrind::plate_cloud_t::STATUS_OK)
    return fail(hullgrind::outline_t::STATUS_NO_LOOP,
                "the plate cloud has no part (status " + std::to_string(cloud.status) + ": " + cloud.status_text + ")");
  if (cloud.n < 3)
    return fail(hullgrind::outline_t::STATUS_NO_LOOP,
                "the plate cloud has " + std::to_string(cloud.n) + " points; 3 are needed");

  std::vector<outline::Vec2> pts(std::size_t(cloud.n));
  for (int i = 0; i < cloud.n; ++i) pts[std::size_t(i)] = {cloud.u[std::size_t(i)], cloud.v[std::size_t(i)]};
  auto t0 = std::chrono::steady_clock::now();
  outline::Result r;
  try {
    r = outline::compute_outline(pts, options);
  } catch (const outline::OutlineError& e) {
    return fail(hullgrind::outline_t::STATUS_ERROR, e.what());
  }
  out.compute_time = std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
  drop_fragments(r.loops, service_options, out);
  count_dropout(cloud, r.holes_dropped, out);
  c.holes_dropped = out.holes_dropped;
  judge_quality(cloud, service_options, out);
  if (!put_result(r, out))
    return fail(hullgrind::outline_t::STATUS_NO_LOOP,
                out.fragments_dropped ? "no outer loop left: " + out.dropped_text
                                      : "no outer loop found (alpha radius " + std::to_string(r.alpha_radius) +
                                            " m too small for the point spacing?)");
  out.num_loops = int32_t(out.loops.size());
  out.status = hullgrind::outline_t::STATUS_OK;
  c.poses = pose_messages(cloud, r.loops, r.spacing);
  return c;
}

OutlineService::OutlineService(runtime::Node& node) : node_(node), options_(options_from(node)) {
  node_.subscribe<hullgrind::plate_cloud_t>(channels::kPlateCloud,
                                            [this](const hullgrind::plate_cloud_t& cloud, const runtime::Delivery& d) {
                                              std::lock_guard lock(mutex_);
                                              if (pending_)
                                                node_.count_dropped();  // superseded before the worker took it
                                              pending_ = cloud;
                                              pending_recv_utime_ = d.recv_utime;
                                              wake_.notify_one();
                                            });
  worker_ = std::thread([this] { work(); });
}

OutlineService::~OutlineService() {
  std::unique_lock lock(mutex_);
  quit_ = true;
  wake_.notify_all();
  // A shutdown must take less than a second, but a big cloud can take longer than that to compute and
  // the core cannot be interrupted: then the result is abandoned and the process ends here.
  if (!wake_.wait_for(lock, std::chrono::milliseconds(700), [&] { return !busy_; })) {
    runtime::logf(runtime::Level::Warn, "abandoning the outline being computed to stop in time");
    std::_Exit(0);
  }
  lock.unlock();
  worker_.join();
}

void OutlineService::work() {
  while (true) {
    hullgrind::plate_cloud_t cloud;
    std::int64_t recv_utime = 0;
    {
      std::unique_lock lock(mutex_);
      wake_.wait(lock, [&] { return quit_ || pending_; });
      if (quit_) return;
      cloud = std::move(*pending_);
      pending_.reset();
      recv_utime = pending_recv_utime_;
      busy_ = true;
    }
    Computed c = compute(cloud, options_);
    {
      std::lock_guard lock(mutex_);
      busy_ = false;
      wake_.notify_all();
      if (quit_) return;
    }
    node_.publish(channels::kOutline, c.outline);
    for (auto& pose : c.poses) node_.publish(channels::kPartPose, pose);
    double latency = double(runtime::now_utime() - recv_utime) * 1e-6;
    node_.set_latency(latency);
    if (c.outline.status == hullgrind::outline_t::STATUS_OK) {
      node_.set_state(hullgrind::heartbeat_t::STATE_OK);
      runtime::logf(runtime::Level::Info, "cloud %lld: %d points -> %d loops in %.1f ms (R %.4f m)%s",
                    (long long)cloud.header.seq, cloud.n, c.outline.num_loops, c.outline.compute_time * 1e3,
                    c.outline.alpha_radius,
                    c.holes_dropped ? (", " + std::to_string(c.holes_dropped) + " tiny holes dropped").c_str() : "");
    } else {
      node_.set_state(hullgrind::heartbeat_t::STATE_DEGRADED, "last cloud: " + c.outline.error_text);
    }
  }
}

std::unique_ptr<OutlineService> attach(runtime::Node& node) { return std::make_unique<OutlineService>(node); }

}  // namespace hg::outline_service
