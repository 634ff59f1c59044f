// outline_service_realistic_warp: where the grind edge of a bowed part (SensorEffects::warp alone) lies
// against the true edge, over many poses and noise seeds (docs/BENCHMARKS-outline.md, "Warp alone"). For
// each sagitta: the grind edge's Hausdorff distance and where it is (at a corner tip or along an edge), and
// its signed offset from the true edge along the straight and curved runs (> 0: outside the steel), away
// from the corners, where a bow-dependent bias of the chain would show. A benchmark, not in CTest.
#include <cstdio>
#include <cstdlib>
#include <string>
#include <vector>

#include "realistic_grind.hpp"

using namespace hg::test;

namespace {

struct Stats {
  int n = 0, tip = 0, beyond = 0;  // tip: the max at a corner tip; beyond: the grind edge beyond the true edge there
  double max_sum = 0, max_max = 0, off_sum = 0, off_n = 0, far_sq = 0;
  double seen_sum = 0, seen_n = 0, hidden_sum = 0, hidden_n = 0;  // offsets where the side wall faces the camera or not
};

// Distance from p to the nearest vertex of the truth's outer ring whose interior angle is below 100 deg.
double to_sharp_corner(const Eigen::Vector2d& p, const Ring2& r) {
  double d = 1e9;
  for (std::size_t i = 0; i < r.size(); ++i) {
    const Eigen::Vector2d a = r[(i + r.size() - 1) % r.size()], b = r[i], c = r[(i + 1) % r.size()];
    const Eigen::Vector2d u = (a - b).normalized(), v = (c - b).normalized();
    if ((a - b).norm() > 5e-3 && (c - b).norm() > 5e-3 && u.dot(v) > std::cos(100 * M_PI / 180))
      d = std::min(d, (p - b).norm());
  }
  return d;
}

// Whether the true edge nearest p faces the point below the camera (the camera then sees its side wall):
// the edge's outward normal (out of the steel) points towards the nadir.
bool faces_nadir(const Eigen::Vector2d& p, const std::vector<Ring2>& rings, const hg::sim::RenderedFrame& f) {
  const Eigen::Vector2d nadir = (f.camera_from_table.inverse() * Eigen::Vector3d::Zero()).head<2>();
  double best = 1e9;
  Eigen::Vector2d a = Eigen::Vector2d::Zero(), b = a;
  for (const Ring2& r : rings)
    for (std::size_t i = 0, j = r.size() - 1; i < r.size(); j = i++)
      if (const double d = seg_dist(p, r[j], r[i]); d < best) best = d, a = r[j], b = r[i];
  const Eigen::Vector2d mid = 0.5 * (a + b), t = (b - a).normalized();
  Eigen::Vector2d out(t.y(), -t.x());
  if (!hg::partgen::contains(f.part_polygons[0], mid.x() + 1e-4 * out.x(), mid.y() + 1e-4 * out.y()))
    return out.dot(nadir - mid) > 0;
  return -out.dot(nadir - mid) > 0;
}

void add(Stats& s, const GrindAccuracy& g, const std::vector<Eigen::Vector2d>& edge, const hg::sim::RenderedFrame& f) {
  const auto& truth = f.part_polygons.at(0);
  const Ring2 outer(truth.outer.begin(), truth.outer.end());
  std::vector<Ring2> rings{outer};
  for (const auto& h : truth.holes) rings.emplace_back(h.begin(), h.end());
  ++s.n, s.max_sum += g.max, s.max_max = std::max(s.max_max, g.max);
  s.tip += to_sharp_corner(g.worst, outer) < 0.02;
  s.beyond += rings_dist(g.worst, rings) > 1e-7 && !hg::partgen::contains(truth, g.worst.x(), g.worst.y());
  for (const auto& p : edge) {
    if (to_sharp_corner(p, outer) < 0.02) continue;  // the runs only
    const double d = rings_dist(p, rings) * (hg::partgen::contains(truth, p.x(), p.y()) ? -1 : 1);
    s.off_sum += d, ++s.off_n, s.far_sq += d * d;
    if (faces_nadir(p, rings, f)) s.seen_sum += d, ++s.seen_n;
    else
      s.hidden_sum += d, ++s.hidden_n;
  }
}

void run(const std::string& shape, const std::string& profile, int n, bool verbose) {
  const hg::path_planner::PlannerConfig planner = make_run_planner();
  const Eigen::Isometry3d table_to_base = base_from_table(planner);
  std::printf("%s@%s, %d poses (random place and angle, alternately flipped), warp alone\n\n", shape.c_str(),
              profile.c_str(), n);
  std::printf(
      "| sagitta (mm/m) | grind Hausdorff mean / max (mm) | max at a corner tip | max outside the steel | runs: mean offset / RMS (mm) | runs where the wall is seen / not: mean offset (mm) |\n");
  std::printf("|---|---|---|---|---|---|\n");
  for (double sag : {0.0, 0.003, -0.003, 0.03, -0.03}) {
    Stats s;
    hg::partgen::Rng rng(7);
    for (int i = 0; i < n; ++i) {
      const Pose pose{-0.12 + 0.24 * rng.uniform(), -0.08 + 0.16 * rng.uniform(), 2 * M_PI * rng.uniform(), i % 2 == 1};
      hg::sim::SceneSpec spec = part_scene(shape, pose, 1000 + i);
      spec.effects = hg::sim::SensorEffects{};
      spec.effects.intensity = true, spec.effects.warp = sag;
      const hg::sim::RenderedFrame f = hg::sim::render(spec, hg::sim::camera_profile(profile), 0);
      const Scan sc = scan(f, hg::camera_bridge::SegmentParams{}, shipped_rules(), f.intensity);
      std::vector<Eigen::Vector2d> edge;
      const GrindAccuracy g = grind_edge(sc.outline, f, planner, table_to_base, &edge);
      add(s, g, edge, f);
      if (verbose)
        std::fprintf(
            stderr, "sagitta %+.0f pose %d: max %.2f mm at (%.1f, %.1f), %.1f mm from a sharp corner\n", 1e3 * sag, i,
            1e3 * g.max, 1e3 * g.worst.x(), 1e3 * g.worst.y(),
            1e3 * to_sharp_corner(g.worst, Ring2(f.part_polygons[0].outer.begin(), f.part_polygons[0].outer.end())));
    }
    std::printf("| %+.0f | %.2f / %.2f | %d of %d | %d of %d | %+.3f / %.3f | %+.3f / %+.3f |\n", 1e3 * sag,
                1e3 * s.max_sum / s.n, 1e3 * s.max_max, s.tip, s.n, s.beyond, s.n, 1e3 * s.off_sum / s.off_n,
                1e3 * std::sqrt(s.far_sq / s.off_n), 1e3 * s.seen_sum / s.seen_n, 1e3 * s.hidden_sum / s.hidden_n);
    std::fflush(stdout);
  }
}

}  // namespace

int main(int argc, char** argv) {
  std::string shape = "knee-scallop", profile = "pm806";
  int n = 12;
  bool verbose = false;
  for (int i = 1; i < argc; ++i) {
    const std::string a = argv[i];
    if (a == "--help")
      return std::printf(
                 "usage: outline_service_realistic_warp [--part NAME] [--profile NAME] [--poses N] [--verbose]\n"
                 "The grind edge of one catalogue part (default knee-scallop) with warp alone at sagittas 0, +-3 and\n"
                 "+-30 mm per metre, N poses each (default 12; the same poses and noise seeds for every sagitta), at\n"
                 "one camera profile (default pm806), against the renderer's polygons: the Hausdorff distance and\n"
                 "where it is, and the mean signed offset along the runs away from sharp corners. --verbose: each\n"
                 "scan's worst point on stderr.\n"),
             0;
    if (a == "--part" && i + 1 < argc) shape = argv[++i];
    else if (a == "--profile" && i + 1 < argc)
      profile = argv[++i];
    else if (a == "--poses" && i + 1 < argc)
      n = std::max(1, std::atoi(argv[++i]));
    else if (a == "--verbose")
      verbose = true;
    else
      return std::fprintf(stderr, "unknown option '%s' (--help)\n", a.c_str()), 2;
  }
  run(shape, profile, n, verbose);
  return 0;
}
