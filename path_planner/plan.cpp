// The composition of the steps: one pure function from an outline + job parameters to a validated path.
#include "path_planner/modifiers.hpp"
#include "path_planner/pipeline.hpp"

#include <chrono>
#include <cmath>
#include <cstdint>
#include <cstdio>

namespace hg::path_planner {

std::string resolve_params(const JobParams& req, const JobParams& def, JobParams& out) {
  // Zero takes the default; the ranges are the job quantities' (runtime/quantities.hpp), which every reader
  // checks. The first quantity out of range is the reason.
  std::string why;
  quantity::for_each_job_quantity(
      [&why](const quantity::Quantity& q, double& o, double r, double d) {
        o = r == 0 ? d : r;
        if (why.empty()) why = quantity::out_of_range(q, o);
      },
      out, req, def);
  out.direction = req.direction;
  out.flipped = req.flipped;
  if (!why.empty()) return why;
  if (!job::direction_from_wire(std::int8_t(out.direction))) return "direction must be 0 (climb) or 1 (conventional)";
  return "";
}

std::string check_job_within_cell(const JobParams& p, const PlannerConfig& cfg) {
  const std::string cell = cfg.cell_file.empty() ? std::string("the cell's") : cfg.cell_file;
  auto num = [](double v) {
    char buf[32];
    std::snprintf(buf, sizeof buf, "%g", v);
    return std::string(buf);
  };
  if (p.grind_speed > cfg.limits.max_speed)
    return "grind_speed " + num(p.grind_speed) + " m/s exceeds " + cell + " max-speed " + num(cfg.limits.max_speed);
  if (p.travel_speed > cfg.limits.max_speed)
    return "travel_speed " + num(p.travel_speed) + " m/s exceeds " + cell + " max-speed " + num(cfg.limits.max_speed);
  if (!cfg.cell_file.empty() && p.tool_radius > cfg.defaults.tool_radius)  // the mounted tool (a worn one is smaller)
    return "tool_radius " + num(p.tool_radius) + " m exceeds " + cell + " tool.radius " +
           num(cfg.defaults.tool_radius) + " (the mounted tool)";
  return "";
}

std::vector<Ring> edges_to_grind(OutlineInput& in, bool flipped, const PlannerConfig& cfg, double& pitch) {
  normalize_up(in, cfg.camera_to_base);
  make_canonical(in.loops);
  if (flipped) in.loops = mirror_for_flip(in.loops);
  const Spacing spacing = choose_spacing(in, cfg.smooth);
  pitch = spacing.value;
  // A spacing estimated from the vertices alone is no pixel lattice: the smoothing takes its unit from the
  // vertices as well and moves no edge (the compensation needs the pitch of a known grid).
  const double lattice = spacing.source == "vertices" ? 0 : pitch;
  SmoothOptions smooth = cfg.smooth;
  smooth.noise = estimate_noise(in.loops, smooth);
  std::vector<Ring> edges;
  for (const Loop& l : in.loops) edges.push_back(smooth_ring(l.points, lattice, smooth).points);
  return edges;
}

double coverage_tolerance(const PlannerConfig& cfg, double pitch) { return cfg.coverage_tolerance + 0.5 * pitch; }

std::vector<LoopCoverage> loops_coverage(const std::vector<Loop>& loops, const std::vector<Ring>& edges,
                                         const std::vector<Segment2>& tool_path, double reach, double tolerance) {
  std::vector<LoopCoverage> out;
  for (std::size_t k = 0; k < loops.size(); ++k) {
    LoopCoverage c = edge_coverage(edges[k], tool_path, reach, tolerance);
    c.loop = int(k);
    c.hole = loops[k].hole;
    out.push_back(std::move(c));
  }
  return out;
}

PathCoverage path_coverage(OutlineInput in, const std::vector<Waypoint>& path, double tool_radius, bool flipped,
                           const PlannerConfig& cfg) {
  PathCoverage pc;
  double pitch = 0;
  const std::vector<Ring> edges = edges_to_grind(in, flipped, cfg, pitch);
  pc.plate_to_base = plate_to_base(in.plane, cfg.camera_to_base);
  pc.loops = loops_coverage(in.loops, edges, grind_segments(path, pc.plate_to_base), tool_radius,
                            coverage_tolerance(cfg, pitch));
  return pc;
}

std::string describe_unreached(const LoopCoverage& c, const Eigen::Isometry3d& plate_to_base, double reach,
                               double tolerance, const std::string& frame) {
  const UnreachedStretch* longest = &c.unreached.front();
  bool concave = false;
  for (const UnreachedStretch& s : c.unreached) {
    if (s.length > longest->length) longest = &s;
    concave |= s.concave;
  }
  auto where = [&](const Vec2& p) {
    const Vec3 b = plate_to_base * Vec3(p.x(), p.y(), 0);
    char buf[96];
    std::snprintf(buf, sizeof buf, "(%.1f, %.1f, %.1f)", b.x() * 1e3, b.y() * 1e3, b.z() * 1e3);
    return std::string(buf);
  };
  double depth = 0;
  for (const UnreachedStretch& s : c.unreached) depth = std::max(depth, s.depth);
  char beyond[64];
  if (std::isfinite(depth)) std::snprintf(beyond, sizeof beyond, "up to %.1f mm", depth * 1e3);
  else
    std::snprintf(beyond, sizeof beyond, "more than %.1f mm", (reach + tolerance) * 1e3);
  // Rounded down, so that an edge with any stretch unreached never reads as 100.0 %.
  const double percent = std::floor(1000 * c.reached_fraction()) / 10;
  char buf[400];
  std::snprintf(buf, sizeof buf,
                "%s %d: %.1f mm of its %.1f mm edge (%.1f %% reached) is farther than %.1f + %.1f mm from the tool "
                "path (%s beyond), in %zu stretch%s; the longest %.1f mm from %s to %s mm (%s)",
                c.hole ? "hole" : "outer loop", c.loop, c.unreached_length * 1e3, c.length * 1e3, percent, reach * 1e3,
                tolerance * 1e3, beyond, c.unreached.size(), c.unreached.size() == 1 ? "" : "es", longest->length * 1e3,
                where(longest->from).c_str(), where(longest->to).c_str(), frame.c_str());
  std::string text = buf;
  if (concave) {
    std::snprintf(buf, sizeof buf, "; at a concave corner or bend tighter than the tool's %.1f mm radius", reach * 1e3);
    text += buf;
  }
  return text;
}

namespace {

// The sequencing step's options: the job's parameters and the cell's configuration.
SequenceOptions sequence_options(const JobParams& P, const PlannerConfig& cfg) {
  SequenceOptions so;
  so.tilt = P.tilt;
  so.grind_speed = P.grind_speed;
  so.approach_speed = approach_speed(P, cfg);
  so.z = cfg.z_offset;
  so.direction = P.direction;
  so.spindle_clockwise = cfg.spindle_clockwise;
  return so;
}

}  // namespace

double inscribed_width(const Ring& edge, bool hole, double arc_tolerance) {
  if (!hole) return INFINITY;  // an outer loop's tool runs outside it
  Vec2 lo = edge.front(), hi = edge.front();
  for (const Vec2& p : edge) lo = lo.cwiseMin(p), hi = hi.cwiseMax(p);
  double in = 0, out = 0.5 * (hi - lo).maxCoeff();  // the offset by `in` is not empty, by `out` it is
  for (int i = 0; i < 40 && out - in > 1e-6; ++i) {
    const double mid = 0.5 * (in + out);
    (offset_ring(edge, true, mid, arc_tolerance).empty() ? out : in) = mid;
  }
  return 2 * in;
}

namespace {

std::string too_small_text(std::size_t k, bool hole, const Ring& edge, double tool_radius, double arc_tolerance) {
  char buf[200];
  if (!hole) {
    std::snprintf(buf, sizeof buf, "outer loop %zu gives no path at a tool of radius %.1f mm", k, tool_radius * 1e3);
    return buf;
  }
  std::snprintf(buf, sizeof buf,
                "hole %zu is too small for a tool of radius %.1f mm: the widest circle inside its edge is %.1f mm "
                "across, the tool is %.1f mm",
                k, tool_radius * 1e3, inscribed_width(edge, true, arc_tolerance) * 1e3, 2 * tool_radius * 1e3);
  return buf;
}

}  // namespace

namespace {

// Step 0: the job's parameters resolved into res.params and checked against the cell, the outline checked.
std::string check_job(const OutlineInput& in, const JobParams& requested, const PlannerConfig& cfg, PlanResult& res) {
  if (std::string why = resolve_params(requested, cfg.defaults, res.params); !why.empty()) return why;
  if (std::string why = check_job_within_cell(res.params, cfg); !why.empty()) return "refused by the cell: " + why;
  if (std::string why = check_outline(in); !why.empty()) return "bad outline: " + why;
  return "";
}

// Steps 2 and 3: every edge offset by the tool radius and resampled. A loop with no offset is skipped (its
// reason in skipped[k], its warning's index in skipped_warning[k]) when the small-hole policy allows.
std::string offset_loops(const std::vector<Loop>& loops, const std::vector<Ring>& edges, const PlannerConfig& cfg,
                         PlanResult& res, std::vector<GrindLoop>& grind, std::vector<std::string>& skipped,
                         std::vector<std::size_t>& skipped_warning) {
  const JobParams& P = res.params;
  for (std::size_t k = 0; k < loops.size(); ++k) {
    const Loop& l = loops[k];
    const std::vector<Ring> off = offset_ring(edges[k], l.hole, P.tool_radius, cfg.arc_tolerance);
    if (off.empty()) {
      const std::string why = too_small_text(k, l.hole, edges[k], P.tool_radius, cfg.arc_tolerance);
      if (cfg.small_hole == SmallHolePolicy::Fail || !l.hole) return "not grindable: " + why;
      skipped_warning[k] = res.warnings.size();
      skipped[k] = why;
      res.warnings.push_back("skipped: " + why);
      continue;
    }
    if (off.size() > 1)
      res.warnings.push_back("loop " + std::to_string(k) + " splits into " + std::to_string(off.size()) +
                             " pieces at this tool radius; each is ground, the narrow parts between are not");
    for (const Ring& r : off)
      grind.push_back({resample_ring(r, P.step, cfg.resample_corner_angle, cfg.resample_chord_error), l.hole, int(k)});
  }
  res.loops_planned = int(grind.size());
  return "";
}

// Steps 5 to 6: the passes, the configured modifiers over them, the path in the base frame.
std::vector<Waypoint> tool_path(const std::vector<GrindLoop>& grind, const Eigen::Isometry3d& T, const Vec3& start_base,
                                const PlannerConfig& cfg, PlanResult& res) {
  const Vec3 start_plate = T.inverse() * start_base;
  ToolPath path{sequence(grind, start_plate.head<2>(), sequence_options(res.params, cfg)), T, start_base};
  compose_modifiers(cfg.modifiers, res.params, cfg).apply(path);
  res.slowed = path.speeds_lowered;
  return to_base(flatten(path), T);
}

// Step 7b: the coverage of every loop's edge by the path as published (skipped holes included: none of their
// edge is); warnings for what is not reached, and the reason to fail when the small-hole policy says so.
std::string check_coverage(const OutlineInput& in, const std::vector<Ring>& edges,
                           const std::vector<std::string>& skipped, const std::vector<std::size_t>& skipped_warning,
                           const PlannerConfig& cfg, PlanResult& res) {
  const JobParams& P = res.params;
  const Eigen::Isometry3d& T = res.plate_to_base;
  res.edges = edges;
  res.coverage_tolerance = coverage_tolerance(cfg, res.pitch);
  res.coverage = loops_coverage(in.loops, edges, grind_segments(res.path, T), P.tool_radius, res.coverage_tolerance);
  std::string unreached;
  for (std::size_t k = 0; k < in.loops.size(); ++k) {
    LoopCoverage& c = res.coverage[k];
    c.planned = skipped[k].empty();
    c.skipped = skipped[k];
    res.unreached_length += c.unreached_length;
    if (c.unreached.empty()) continue;
    const std::string text = describe_unreached(c, T, P.tool_radius, res.coverage_tolerance, cfg.base_frame);
    if (skipped_warning[k] != SIZE_MAX) res.warnings[skipped_warning[k]] += ": " + text;
    else if (cfg.small_hole == SmallHolePolicy::Skip)
      res.warnings.push_back("not reached: " + text);
    unreached += (unreached.empty() ? "" : "; ") + text;
  }
  if (!unreached.empty() && cfg.small_hole == SmallHolePolicy::Fail)
    return "not grindable: edge out of the tool's reach: " + unreached;
  return "";
}

}  // namespace

PlanResult plan(OutlineInput in, const JobParams& requested, const PlannerConfig& cfg,
                const std::optional<Vec3>& robot_position_base) {
  const auto t0 = std::chrono::steady_clock::now();
  PlanResult res;
  std::vector<std::string> skipped(in.loops.size());
  std::vector<std::size_t> skipped_warning(in.loops.size(), SIZE_MAX);
  std::string why = check_job(in, requested, cfg, res);
  std::vector<Ring> edges;
  std::vector<GrindLoop> grind;
  if (why.empty()) {
    res.pitch_source = choose_spacing(in, cfg.smooth).source;
    // No spacing at all only for a drawn polygon (no loop of 200 vertices): it is left as it is.
    edges = edges_to_grind(in, res.params.flipped, cfg, res.pitch);
    why = offset_loops(in.loops, edges, cfg, res, grind, skipped, skipped_warning);
  }
  const Vec3 start_base = robot_position_base ? *robot_position_base : cfg.home;
  if (why.empty()) {
    res.plate_to_base = plate_to_base(in.plane, cfg.camera_to_base);
    res.path = tool_path(grind, res.plate_to_base, start_base, cfg, res);
    why = validate(res.path, cfg.limits, res.plate_to_base.linear().col(2), start_base);
    if (!why.empty()) why = "validation: " + why;
  }
  if (why.empty()) why = check_coverage(in, edges, skipped, skipped_warning, cfg, res);
  res.ok = why.empty();
  res.reason = why;
  if (!res.ok) res.path.clear();
  res.seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
  return res;
}

}  // namespace hg::path_planner
