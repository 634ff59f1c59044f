// hg-radius-table: the table of docs/outline-auto-radius.md. Noisy scan grids with circular cut-outs and
// random or clustered (3x3) dropout, outlined with the automatic radius; each loop scored against the
// generator's truth (outer loops, real holes found, spurious holes) for several hole thresholds.
// Not a test (no assertions); a measurement, with its command in the doc.
//   hg-radius-table [--size 2k|17k|1.6M] [--seeds N] [--k K] [--alpha-mode global|local] [--boundary]
//   hg-radius-table --tilted POINTS   (catalogue parts seen by a tilted camera, global vs local mode)
#include <algorithm>
#include <cmath>
#include <cstdio>
#include <limits>
#include <string>
#include <vector>

#include "outline_core/alpha.hpp"
#include "tools/bench/core/synthetic_clouds.hpp"
#include "tools/bench/core/tilted_camera.hpp"
#include "sim/partgen/shapes.hpp"
#include "outline_core/outline.hpp"
#include "runtime/params.hpp"

using namespace hg::outline;

namespace {

struct Noise {
  const char* name;
  double amp, sigma;
};
struct Dropout {
  const char* name;
  double total, clustered;
};

constexpr double kThresholds[] = {0, 4, 4.25, 4.5, 5};
constexpr int kThresholdCount = 5;

struct Cell {
  int runs = 0, bad_outer = 0, holes = 0, min_clusters = 1 << 30;
  int spurious[kThresholdCount] = {}, missed[kThresholdCount] = {};
  double max_spurious_area = 0, h_min = 1e300, h_max = 0;
  double min_real_area[4] = {1e300, 1e300, 1e300, 1e300};  // d = 4, 4.5, 5, >= 6 (0 when missed)
};

int diameter_class(double d) { return d < 4.25 ? 0 : d < 4.75 ? 1 : d < 5.5 ? 2 : 3; }

// One cloud: loops kept with every hole (threshold 0), then each threshold applied as the core does.
void run_one(const synth::PlateSpec& spec, const Options& base, Cell& cell) {
  const synth::PlateCloud c = synth::make_plate(spec);
  Options o = base;
  o.min_hole_spacings = 0;
  const Result r = compute_outline(c.points, o);
  ++cell.runs;
  cell.min_clusters = std::min(cell.min_clusters, c.clusters);
  cell.h_min = std::min(cell.h_min, r.spacing);
  cell.h_max = std::max(cell.h_max, r.spacing);
  cell.holes += static_cast<int>(c.hole_centres.size());
  for (int t = 0; t < kThresholdCount; ++t) {
    const double m = kThresholds[t] * r.spacing;
    std::vector<Loop> kept;
    for (const Loop& L : r.loops)
      if (!L.hole || !(L.area < m * m)) kept.push_back(L);
    const synth::PlateScore s = synth::score_plate(c, kept);
    cell.spurious[t] += s.spurious;
    cell.missed[t] += s.missed;
    if (t == 0) {
      cell.bad_outer += s.outers != 1;
      for (const Loop& L : r.loops) {
        if (!L.hole) continue;
        bool real = false;
        const double a = L.area / (r.spacing * r.spacing);
        for (std::size_t k = 0; k < c.hole_centres.size(); ++k)
          if (synth::inside_polygon(L.points, c.hole_centres[k])) {
            real = true;
            double& m = cell.min_real_area[diameter_class(c.hole_diameters[k])];
            m = std::min(m, a);
          }
        if (!real) cell.max_spurious_area = std::max(cell.max_spurious_area, a);
      }
      // A missed hole counts as area 0 in its class.
      for (std::size_t k = 0; k < c.hole_centres.size(); ++k) {
        bool hit = false;
        for (const Loop& L : r.loops) hit |= L.hole && synth::inside_polygon(L.points, c.hole_centres[k]);
        if (!hit) cell.min_real_area[diameter_class(c.hole_diameters[k])] = 0;
      }
    }
  }
}

// Largest distance from a loop vertex to the truth boundary, and from the truth's vertices to the loops,
// in local spacings (the longer side of the pixel footprint).
double hausdorff_in_spacings(const synth::TiltedView& v, const std::vector<Loop>& loops) {
  using P = hg::partgen::Vec2;
  auto seg = [](const P& p, const P& a, const P& b) {
    const P ab = b - a;
    const double t = std::clamp((p - a).dot(ab) / ab.squaredNorm(), 0.0, 1.0);
    return (a + t * ab - p).norm();
  };
  std::vector<std::vector<P>> truth{v.truth.outer}, ours;
  for (const auto& h : v.truth.holes) truth.push_back(h);
  for (const Loop& L : loops) {
    ours.emplace_back();
    for (const Vec2& p : L.points) ours.back().push_back({p.x, p.y});
  }
  auto dist = [&](const P& p, const std::vector<std::vector<P>>& rings) {
    double d = 1e300;
    for (const auto& r : rings)
      for (std::size_t i = 0; i < r.size(); ++i) d = std::min(d, seg(p, r[i], r[(i + 1) % r.size()]));
    return d;
  };
  double worst = 0;
  for (const auto& r : ours)
    for (const P& p : r) worst = std::max(worst, dist(p, truth) / v.spacing(p, true));
  for (const auto& r : truth)
    for (const P& p : r) worst = std::max(worst, dist(p, ours) / v.spacing(p, true));
  return worst;
}

// The tilted-camera table: every catalogue part, spacing gradients 1x, 2x and 5x, both alpha modes.
int tilted_table(const Options& base, double points) {
  std::printf(
      "| part | gradient | points | truth holes | global: outer / holes / Hausdorff | local: outer / holes / Hausdorff |\n");
  std::printf("|---|---|---|---|---|---|\n");
  for (double g : {1.0, 2.0, 5.0})
    for (const hg::partgen::Shape& shape : hg::partgen::catalogue()) {
      const synth::TiltedView view = synth::tilted_view(shape, g, points, 0.2, 3);
      std::printf("| %s | %.1f | %zu | %zu |", shape.name.c_str(), view.spacing_far / view.spacing_near,
                  view.points.size(), view.truth.holes.size());
      for (AlphaMode m : {AlphaMode::Global, AlphaMode::Local}) {
        Options o = base;
        o.alpha_mode = m;
        const Result r = compute_outline(view.points, o);
        int outers = 0, holes = 0;
        for (const Loop& L : r.loops) (L.hole ? holes : outers)++;
        std::printf(" %d / %d / %.2f |", outers, holes, outers <= 50 ? hausdorff_in_spacings(view, r.loops) : -1.0);
      }
      std::printf("\n");
      std::fflush(stdout);
    }
  return 0;
}

constexpr const char* kUsageHead =
    "usage: hg-radius-table [--size 2k|17k|1.6M] [--seeds N] [--k K] [--alpha-mode M] [--boundary] | --tilted POINTS\n"
    "The automatic radius's table on generated plates (docs/outline-auto-radius.md).\n";

std::vector<hg::runtime::Param> table_params() {
  using namespace hg::runtime;
  constexpr double inf = std::numeric_limits<double>::infinity();
  std::vector<Param> params = {
      text_param("size", "17k", "plate grid: 60 x 34, 170 x 100 or 1600 x 1000 points", {"2k", "17k", "1.6M"}),
      integer_param("seeds", "4", "seeds per table cell", 1, 1e6),
      number_param("k", "", "radius factor R = k x spacing (default: the automatic one)", 0, inf, true),
      text_param("alpha-mode", "global", "one radius for the cloud, or one per triangle", {"global", "local"}),
      flag_param("boundary", "the diameter-4 holes centred on grid points (exactly 3x3 gaps)"),
      number_param("tilted", "",
                   "instead: catalogue parts of about this many points seen by a tilted camera, "
                   "global vs local mode",
                   0, inf, true)};
  set_value_names(params, {{"seeds", "N"}, {"k", "K"}, {"alpha-mode", "M"}, {"tilted", "POINTS"}});
  return params;
}

}  // namespace

int main(int argc, char** argv) {
  hg::runtime::Params p(table_params());
  if (const int rc = hg::runtime::parse_tool(p, argc, argv, "hg-radius-table", hg::runtime::usage_with(kUsageHead));
      rc >= 0)
    return rc;
  if (!p.positional().empty()) {
    std::fprintf(stderr, "hg-radius-table: command line: unexpected argument '%s' (see --help)\n",
                 p.positional()[0].c_str());
    return 2;
  }
  const std::string size = p.text("size");
  const int seeds = int(p.integer("seeds"));
  Options base;
  if (p.given("k")) base.auto_factor = p.number("k");
  base.alpha_mode = parse_alpha_mode(p.text("alpha-mode"));
  const bool boundary = p.flag("boundary");
  const double tilted_points = p.given("tilted") ? p.number("tilted") : 0;
  if (tilted_points > 0) return tilted_table(base, tilted_points);
  synth::PlateSpec spec;
  if (size == "2k") spec.W = 60, spec.H = 34, spec.hole_diameters = {4, 5, 8};
  else if (size == "17k")
    spec.W = 170, spec.H = 100, spec.hole_diameters = {4, 4, 4.5, 5, 6, 8, 12};
  else  // 1.6M (the declaration's choices)
    spec.W = 1600, spec.H = 1000, spec.hole_diameters = {4, 4, 4, 4, 4.5, 4.5, 5, 5, 6, 8, 12, 20, 40};
  // --boundary: the diameter-4 holes centred on grid points, i.e. exactly 3x3 gaps.
  if (boundary) spec.holes_on_grid_points = true, spec.hole_diameters.assign(spec.hole_diameters.size(), 4.0);
  const Noise noises[] = {
      {"none", 0, 0},        {"uniform +-0.2", 0.2, 0}, {"uniform +-0.35", 0.35, 0}, {"uniform +-0.5", 0.5, 0},
      {"gauss 0.1", 0, 0.1}, {"gauss 0.2", 0, 0.2},     {"gauss 0.3", 0, 0.3}};
  const Dropout drops[] = {{"0", 0, 0}, {"2 %", 0.02, 0}, {"5 %", 0.05, 0}, {"5 % (2.5 % as 3x3)", 0.05, 0.025}};
  const std::string k = base.auto_factor > 0 ? std::to_string(base.auto_factor) : "automatic";
  std::printf(
      "hg-radius-table: %d x %d grid (%d points before holes/dropout), holes %zu%s, k = %s, alpha mode %s, %d seeds\n",
      spec.W, spec.H, spec.W * spec.H, spec.hole_diameters.size(), boundary ? " (d = 4 on grid points)" : "", k.c_str(),
      to_string(base.alpha_mode), seeds);
  std::printf(
      "columns: outer-loop failures / runs; spurious and missed holes summed over the seeds at hole threshold m"
      " (holes < (m h)^2 dropped); largest spurious and smallest real hole area (by diameter) in h^2 (m = 0; 0 = missed); h range\n\n");
  std::printf(
      "| noise | dropout | outer bad | m=0 sp/mi | m=4 | m=4.25 | m=4.5 | m=5 | max sp area | min d=4 | d=4.5 | d=5 | d>=6 | h |\n");
  std::printf("|---|---|---|---|---|---|---|---|---|---|---|---|---|---|\n");
  for (const Noise& n : noises)
    for (const Dropout& d : drops) {
      Cell cell;
      for (int s = 0; s < seeds; ++s) {
        synth::PlateSpec one = spec;
        one.uniform_amp = n.amp, one.gauss_sigma = n.sigma, one.dropout = d.total, one.clustered = d.clustered;
        one.seed = 1000 + s;
        run_one(one, base, cell);
      }
      std::printf("| %s | %s | %d/%d |", n.name, d.name, cell.bad_outer, cell.runs);
      for (int t = 0; t < kThresholdCount; ++t) std::printf(" %d / %d |", cell.spurious[t], cell.missed[t]);
      std::printf(" %.1f |", cell.max_spurious_area);
      for (double a : cell.min_real_area) {
        if (a > 1e299) std::printf(" - |");
        else
          std::printf(" %.1f |", a);
      }
      std::printf(" %.3f-%.3f |\n", cell.h_min, cell.h_max);
      std::fflush(stdout);
    }
  return 0;
}
