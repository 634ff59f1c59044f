// outline_service_realistic_table: the accuracy table of docs/BENCHMARKS-outline.md ("Realistic scans"):
// every catalogue part on its realistic preset, both camera profiles, N poses each (alternately face up and
// flipped, random place and angle, a seed each), through the camera bridge's segmentation and the outline
// service's computation, measured against the renderer's polygons (realistic_scan.hpp). --effects: the same
// per effect alone (one pose). A benchmark that prints figures, never registered with CTest.
#include <algorithm>
#include <cstdio>
#include <cstdlib>
#include <cstring>
#include <string>
#include <vector>

#include "realistic_grind.hpp"

using namespace hg::test;

namespace {

bool verbose = false;  // --verbose: one line per scan on stderr

struct Row {
  int scans = 0, ok = 0, outer_min = 1 << 30, outer_max = 0, truth_holes = 0, found_min = 1 << 30, extra_max = 0;
  int poor = 0, extra_total = 0, lost_total = 0, planned = 0;
  double grind_rms_sum = 0, grind_rms_max = 0, grind_max = 0;
  std::string why_not;  // the first plan's failure
  double area_err_max = 0, area_err_sum = 0, rms_sum = 0, rms_max = 0, haus_max = 0, haus_sum = 0;
  double area_min = 1e9, area_max = 0, area_sum = 0, hole_spread = 0, edge_dropout_max = 0, gap_max = 0;
  double part_min = 1e9, part_max = 0, part_sum = 0, part_err_sum = 0;  // the part pose's area
  std::vector<std::vector<double>> holes;                               // per true cut-out, its areas over the scans
};

void add(Row& w, const Accuracy& a, const GrindAccuracy& g) {
  if (g.planned) {
    ++w.planned;
    w.grind_rms_sum += g.rms, w.grind_rms_max = std::max(w.grind_rms_max, g.rms),
                              w.grind_max = std::max(w.grind_max, g.max);
  } else if (w.why_not.empty()) {
    w.why_not = g.reason;
  }
  ++w.scans;
  w.truth_holes = a.truth_holes;
  w.poor += a.quality == hullgrind::outline_t::QUALITY_POOR;
  w.edge_dropout_max = std::max(w.edge_dropout_max, a.edge_dropout);
  w.gap_max = std::max(w.gap_max, a.largest_gap);
  if (!a.ok) return;
  ++w.ok;
  w.outer_min = std::min(w.outer_min, a.outer), w.outer_max = std::max(w.outer_max, a.outer);
  w.found_min = std::min(w.found_min, a.holes_found), w.extra_max = std::max(w.extra_max, a.holes_extra);
  w.extra_total += a.holes_extra, w.lost_total += a.truth_holes - a.holes_found;
  w.area_err_max = std::max(w.area_err_max, std::abs(a.area_error())), w.area_err_sum += a.area_error();
  w.rms_sum += a.rms, w.rms_max = std::max(w.rms_max, a.rms);
  w.haus_sum += a.max, w.haus_max = std::max(w.haus_max, a.max);
  w.area_min = std::min(w.area_min, a.area), w.area_max = std::max(w.area_max, a.area), w.area_sum += a.area;
  w.part_min = std::min(w.part_min, a.part_area), w.part_max = std::max(w.part_max, a.part_area);
  w.part_sum += a.part_area, w.part_err_sum += a.part_area_error();
  w.holes.resize(a.hole_areas.size());
  for (std::size_t k = 0; k < a.hole_areas.size(); ++k)
    if (a.hole_areas[k] > 0) w.holes[k].push_back(a.hole_areas[k]);
}

// Largest deviation of a true cut-out's outline area from its mean over the scans, relative.
double hole_spread(const Row& w) {
  double s = 0;
  for (const auto& h : w.holes) {
    if (h.size() < 2) continue;
    double m = 0;
    for (double x : h) m += x;
    m /= double(h.size());
    for (double x : h) s = std::max(s, std::abs(x - m) / m);
  }
  return s;
}

void print_header() {
  std::printf(
      "| part | profile | scans | outer loops | cut-outs: true / found (min) / lost / extra (total) | plate area "
      "error: mean / max | area spread (max-min)/mean | part's area: error mean / spread | hole area spread (max dev. from mean) | edge RMS mean / max "
      "(mm) | Hausdorff mean / max (mm) | POOR | edge in dropout max / largest gap max (mm) | planned | grind edge RMS "
      "mean / max (mm) | grind edge Hausdorff max (mm) |\n");
  std::printf("|---|---|---|---|---|---|---|---|---|---|---|---|---|---|---|---|\n");
}

void print_row(const std::string& part, const std::string& profile, const Row& w) {
  const double n = std::max(1, w.ok), mean_area = w.area_sum / n;
  std::printf(
      "| %s | %s | %d%s | %d..%d | %d / %d / %d / %d | %+.2f %% / %.2f %% | %.2f %% | %+.2f %% / %.2f %% | %.2f %% | %.2f / %.2f | %.2f / "
      "%.2f | %d | %.1f %% / %.1f | %d | %.2f / %.2f | %.2f |\n",
      part.c_str(), profile.c_str(), w.scans,
      w.ok < w.scans ? (" (" + std::to_string(w.scans - w.ok) + " no loop)").c_str() : "", w.outer_min, w.outer_max,
      w.truth_holes, w.found_min, w.lost_total, w.extra_total, 100 * w.area_err_sum / n, 100 * w.area_err_max,
      100 * (w.area_max - w.area_min) / mean_area, 100 * w.part_err_sum / n,
      100 * (w.part_max - w.part_min) * n / std::max(w.part_sum, 1e-12), 100 * hole_spread(w), 1e3 * w.rms_sum / n,
      1e3 * w.rms_max, 1e3 * w.haus_sum / n, 1e3 * w.haus_max, w.poor, 100 * w.edge_dropout_max, 1e3 * w.gap_max,
      w.planned, 1e3 * w.grind_rms_sum / std::max(1, w.planned), 1e3 * w.grind_rms_max, 1e3 * w.grind_max);
  if (!w.why_not.empty())
    std::fprintf(stderr, "%s@%s: not planned: %s\n", part.c_str(), profile.c_str(), w.why_not.c_str());
  std::fflush(stdout);
}

std::uint64_t case_seed(const std::string& text) {  // FNV-1a: a fixed seed per case
  std::uint64_t h = 1469598103934665603ull;
  for (unsigned char ch : text) h = (h ^ ch) * 1099511628211ull;
  return h % 100000 + 1;
}

// Poses i = 0..n-1: alternately face up and flipped, place and angle at random from `seed`.
std::vector<Pose> poses(int n, std::uint64_t seed) {
  hg::partgen::Rng rng(seed);
  std::vector<Pose> p;
  for (int i = 0; i < n; ++i)
    p.push_back({-0.12 + 0.24 * rng.uniform(), -0.08 + 0.16 * rng.uniform(), 2 * M_PI * rng.uniform(), i % 2 == 1});
  return p;
}

void run_poses(int n, const std::vector<std::string>& profiles, const std::vector<std::string>& shapes) {
  const hg::path_planner::PlannerConfig planner = make_run_planner();
  const Eigen::Isometry3d table_to_base = base_from_table(planner);
  print_header();
  for (const auto& shape : shapes)
    for (const auto& profile : profiles) {
      Row w;
      const auto ps = poses(n, case_seed(shape + "/poses"));
      for (int i = 0; i < n; ++i) {
        const hg::sim::RenderedFrame f = realistic_frame(shape, profile, ps[i], case_seed(shape + profile) + i);
        const Scan s = scan(f, hg::camera_bridge::SegmentParams{}, shipped_rules(), f.intensity);
        const Accuracy a = measure(s, f);
        const GrindAccuracy g = grind_edge(s.outline, f, planner, table_to_base);
        add(w, a, g);
        if (verbose)
          std::fprintf(
              stderr,
              "%s@%s pose %d: area %+.2f %% (part's %+.2f %%), edge RMS %.2f mm, grind RMS %.2f max %.2f mm at table "
              "(%.1f, %.1f) mm%s, edge in dropout %.1f %%, gap %.1f mm%s\n",
              shape.c_str(), profile.c_str(), i, 100 * a.area_error(), 100 * a.part_area_error(), 1e3 * a.rms,
              1e3 * g.rms, 1e3 * g.max, 1e3 * g.worst.x(), 1e3 * g.worst.y(), g.planned ? "" : " (not planned)",
              100 * a.edge_dropout, 1e3 * a.largest_gap,
              a.quality == hullgrind::outline_t::QUALITY_POOR ? " POOR" : "");
      }
      print_row(shape, profile, w);
    }
}

// Where a scan's grind edge is farthest from the true edge: the point (table frame), its distance from the
// part's bounding-box centre (the bow's centre) and the bow's height there for sagitta `warp`.
void print_worst(const std::string& what, const Accuracy& a, const GrindAccuracy& g, const hg::sim::RenderedFrame& f,
                 double warp) {
  const auto& outer = f.part_polygons.at(0).outer;
  Eigen::Vector2d lo = outer.front(), hi = lo;
  for (const auto& q : outer) lo = lo.cwiseMin(q), hi = hi.cwiseMax(q);
  const double r = (g.worst - 0.5 * (lo + hi)).norm();
  std::fprintf(stderr,
               "%s: outline RMS %.2f max %.2f mm; grind RMS %.2f max %.2f mm at (%.1f, %.1f) mm, %.0f mm from the "
               "centre, bow %.2f mm\n",
               what.c_str(), 1e3 * a.rms, 1e3 * a.max, 1e3 * g.rms, 1e3 * g.max, 1e3 * g.worst.x(), 1e3 * g.worst.y(),
               1e3 * r, 1e3 * 4 * warp * r * r);
}

// Each effect of realistic_effects() alone, at the realistic preset's values, one pose per part.
hg::sim::SensorEffects only(const std::string& effect) {
  const hg::sim::SensorEffects all = hg::sim::realistic_effects();
  hg::sim::SensorEffects fx;  // all off
  fx.intensity = true;
  if (effect == "incidence") fx.incidence = true, fx.edge_radius = all.edge_radius;
  if (effect == "specular") fx.specular = true;
  if (effect == "mixed") fx.mixed_pixels = true;
  if (effect == "shadow") fx.shadow = true;
  if (effect == "table") fx.table = all.table;
  if (effect == "warp") fx.warp = all.warp;
  if (effect == "all") fx = all;
  return fx;
}

void run_effects(int n, const std::vector<std::string>& profiles, const std::vector<std::string>& shapes) {
  const hg::path_planner::PlannerConfig planner = make_run_planner();
  const Eigen::Isometry3d table_to_base = base_from_table(planner);
  std::printf("Effects alone (%d pose(s) per part and profile, the same poses for every effect):\n\n", n);
  print_header();
  for (const char* effect : {"none", "incidence", "specular", "mixed", "shadow", "table", "warp", "all"})
    for (const auto& profile : profiles) {
      Row w;
      for (const auto& shape : shapes) {
        const auto ps = poses(n, case_seed(shape + "/poses"));
        for (int i = 0; i < n; ++i) {
          hg::sim::SceneSpec spec = part_scene(shape, ps[i], case_seed(shape + profile) + i);
          spec.effects = only(effect);
          const hg::sim::RenderedFrame f = hg::sim::render(spec, hg::sim::camera_profile(profile), 0);
          const Scan s = scan(f, hg::camera_bridge::SegmentParams{}, shipped_rules(), f.intensity);
          Accuracy a = measure(s, f);
          a.hole_areas.clear();  // the parts differ: no hole spread over them
          const GrindAccuracy g = grind_edge(s.outline, f, planner, table_to_base);
          add(w, a, g);
          if (verbose) print_worst(shape + "@" + profile + " " + effect, a, g, f, spec.effects.warp);
        }
      }
      w.area_min = w.area_max = w.part_min = w.part_max = 0;  // nor an area spread
      w.truth_holes = 0;
      print_row(std::string("all parts, ") + effect, profile, w);
    }
}

}  // namespace

int main(int argc, char** argv) {
  int n = 6;
  bool effects = false;
  std::vector<std::string> profiles = hg::sim::camera_profile_names(), shapes = hg::partgen::shape_names();
  for (int i = 1; i < argc; ++i) {
    const std::string a = argv[i];
    if (a == "--help") {
      std::printf(
          "usage: outline_service_realistic_table [--poses N] [--profile NAME] [--part NAME] [--effects] [--verbose]\n"
          "The accuracy table of docs/BENCHMARKS-outline.md: every catalogue part's realistic preset at N poses\n"
          "(default 6, alternately face up and flipped) per camera profile, through the bridge's segmentation and\n"
          "the outline service, against the renderer's polygons. --effects: each effect alone instead. --profile,\n"
          "--part: that camera profile or catalogue part only; --verbose: each scan's figures on stderr.\n");
      return 0;
    }
    if (a == "--version") return std::printf("outline_service_realistic_table 1\n"), 0;
    if (a == "--poses" && i + 1 < argc) n = std::max(1, std::atoi(argv[++i]));
    else if (a == "--profile" && i + 1 < argc)
      profiles = {argv[++i]};
    else if (a == "--verbose")
      verbose = true;
    else if (a == "--part" && i + 1 < argc)
      shapes = {argv[++i]};
    else if (a == "--effects")
      effects = true;
    else
      return std::fprintf(stderr, "unknown option '%s' (--help)\n", a.c_str()), 2;
  }
  effects ? run_effects(n, profiles, shapes) : run_poses(n, profiles, shapes);
  return 0;
}
