// outline_service_realistic_area: where the part's area error of one realistic scan comes from, pose by pose
// (docs/BENCHMARKS-outline.md, "The part's area"). The same frames as outline_service_realistic_table (its
// poses and seeds), measured against the renderer's truth only: a pixel is steel when its ray meets the true
// top (the part's thickness above the table, lifted by its bow) inside the generator's polygon. Per pose:
// - the part's area the service reports (its part pose), against the true area;
// - the truth's own pixels: counted (their footprints summed), and taken through the service's outline and
//   part pose placed exactly where their rays meet the true top (what the part's area is on a perfect scan);
// - the pixels the bridge kept, placed the same way (what the set alone costs), and the pixels it lost and
//   kept off the steel, with their area by the edge they lie on (straight, arc, within 3 pixels of a corner).
// --mixed-fraction F runs the bridge with SegmentParams::mixed_fraction F (a trial). A benchmark that prints
// figures, never registered with CTest.
#include <algorithm>
#include <cstdio>
#include <cstdlib>
#include <string>
#include <vector>

#include "realistic_scan.hpp"
#include "sim/scene/effects.hpp"

using namespace hg::test;

namespace {

std::uint64_t case_seed(const std::string& text) {  // FNV-1a, as outline_service_realistic_table
  std::uint64_t h = 1469598103934665603ull;
  for (unsigned char ch : text) h = (h ^ ch) * 1099511628211ull;
  return h % 100000 + 1;
}

std::vector<Pose> table_poses(int n, std::uint64_t seed) {  // outline_service_realistic_table's
  hg::partgen::Rng rng(seed);
  std::vector<Pose> p;
  for (int i = 0; i < n; ++i)
    p.push_back({-0.12 + 0.24 * rng.uniform(), -0.08 + 0.16 * rng.uniform(), 2 * M_PI * rng.uniform(), i % 2 == 1});
  return p;
}

// Each pixel's ray on the true top: camera-frame point, table-frame x y, centre on the steel, footprint (m^2).
struct Truth {
  std::vector<Eigen::Vector3d> cam;
  std::vector<Eigen::Vector2d> xy;
  std::vector<char> steel;
  std::vector<double> foot;
};

Truth truth_of(const hg::sim::RenderedFrame& f, double bow) {
  const int W = f.depth.cols, H = f.depth.rows;
  Truth t{std::vector<Eigen::Vector3d>(W * H), std::vector<Eigen::Vector2d>(W * H), std::vector<char>(W * H, 0),
          std::vector<double>(W * H, 0)};
  const hg::sim::detail::Warp warp = hg::sim::detail::warps_of(f.part_polygons, bow).at(0);
  const Eigen::Isometry3d table_from_camera = f.camera_from_table.inverse();
  Eigen::Vector2d lo = f.part_polygons[0].outer.front(), hi = lo;
  for (const auto& q : f.part_polygons[0].outer) lo = lo.cwiseMin(q), hi = hi.cwiseMax(q);
  for (int r = 0; r < H; ++r)
    for (int c = 0; c < W; ++c) {
      const double a = (c - f.intrinsics.cx) / f.intrinsics.fx, b = (r - f.intrinsics.cy) / f.intrinsics.fy;
      const Eigen::Vector3d p =
          hg::sim::detail::top_depth(f, warp, f.part_thickness[0], a, b) * Eigen::Vector3d(a, b, 1);
      t.cam[r * W + c] = p;
      t.xy[r * W + c] = (table_from_camera * p).head<2>();
    }
  for (int r = 0; r + 1 < H; ++r)
    for (int c = 0; c + 1 < W; ++c) {
      const Eigen::Vector2d o = t.xy[r * W + c], du = t.xy[r * W + c + 1] - o, dv = t.xy[(r + 1) * W + c] - o;
      t.foot[r * W + c] = std::abs(du.x() * dv.y() - du.y() * dv.x());
      const bool near = (o.array() >= lo.array()).all() && (o.array() <= hi.array()).all();
      t.steel[r * W + c] = near && hg::partgen::contains(f.part_polygons[0], o.x(), o.y());
    }
  return t;
}

// 0 straight, 1 arc (ring pieces under 20 mm), 2 within `corner` of a straight's end: of the nearest edge.
int edge_kind(const hg::partgen::PolygonWithHoles& poly, const Eigen::Vector2d& p, double corner) {
  double best = 1e9;
  int kind = 0;
  auto ring = [&](const hg::partgen::Ring& R) {
    for (std::size_t i = 0, j = R.size() - 1; i < R.size(); j = i++) {
      const Eigen::Vector2d a = R[j], ab = R[i] - a;
      const double d = seg_dist(p, a, R[i]);
      if (d >= best) continue;
      best = d;
      kind = ab.norm() < 0.02 ? 1 : ((p - a).norm() < corner || (p - R[i]).norm() < corner) ? 2 : 0;
    }
  };
  ring(poly.outer);
  for (const auto& h : poly.holes) ring(h);
  return kind;
}

// The service's part area of these pixels placed on the true top, in the bridge's plate frame of `base`.
double part_area_on_truth(const Scan& base, const std::vector<int>& pixels, const Truth& t) {
  hg::camera_bridge::Segmentation s = base.seg;
  s.u.clear(), s.v.clear(), s.part.clear(), s.pixel.clear();
  for (int px : pixels) {
    const Eigen::Vector3d q = t.cam[px] - s.origin;
    s.u.push_back(float(q.dot(s.u_axis))), s.v.push_back(float(q.dot(s.v_axis)));
    s.part.push_back(0), s.pixel.push_back(px);
  }
  hullgrind::plate_cloud_t cloud{};
  hg::camera_bridge::fill_plate_cloud(s, cloud);
  const auto c = hg::outline_service::compute(cloud, shipped_rules());
  return c.poses.empty() ? 0 : c.poses.front().area;
}

struct Tally {
  int n = 0;
  double area[3] = {0, 0, 0};  // by edge kind
};

void one_pose(const std::string& shape, const std::string& profile, const Pose& pose, std::uint64_t seed, int i,
              double mixed_fraction) {
  const hg::sim::RenderedFrame f = realistic_frame(shape, profile, pose, seed);
  hg::camera_bridge::SegmentParams sp;
  if (mixed_fraction >= 0) sp.mixed_fraction = mixed_fraction;
  const Scan s = scan(f, sp, shipped_rules(), f.intensity);
  const Accuracy acc = measure(s, f);
  const Truth t = truth_of(f, hg::sim::realistic_effects().warp);
  std::vector<int> steel, kept(s.seg.pixel.begin(), s.seg.pixel.end());
  std::vector<char> is_kept(t.steel.size(), 0);
  for (int px : kept) is_kept[px] = 1;
  double counted = 0;
  for (std::size_t px = 0; px < t.steel.size(); ++px)
    if (t.steel[px]) steel.push_back(int(px)), counted += t.foot[px];
  const double corner = 3 * std::sqrt(counted / double(steel.size()));
  Tally lost, off;
  for (int px : steel)
    if (!is_kept[px]) ++lost.n, lost.area[edge_kind(f.part_polygons[0], t.xy[px], corner)] += t.foot[px];
  for (int px : kept)
    if (!t.steel[px]) ++off.n, off.area[edge_kind(f.part_polygons[0], t.xy[px], corner)] += t.foot[px];
  const double A = acc.truth_area;
  auto pc = [A](double x) { return 100 * (x - A) / A; };
  auto pa = [A](double x) { return 100 * x / A; };
  std::printf(
      "| %d | %.1f | %s | %+.2f %% | %+.2f %% | %+.2f %% | %+.2f %% | %d: %.2f / %.2f / %.2f %% | %d: %.2f / %.2f / %.2f %% |\n",
      i, std::fmod(pose.theta * 180 / M_PI, 360.0), pose.flipped ? "flipped" : "up", pc(acc.part_area), pc(counted),
      pc(part_area_on_truth(s, steel, t)), pc(part_area_on_truth(s, kept, t)), lost.n, pa(lost.area[0]),
      pa(lost.area[1]), pa(lost.area[2]), off.n, pa(off.area[0]), pa(off.area[1]), pa(off.area[2]));
  std::fflush(stdout);
}

}  // namespace

int main(int argc, char** argv) {
  std::string shape = "knee-scallop", profile = "pm806";
  int n = 6;
  double mixed_fraction = -1;
  for (int i = 1; i < argc; ++i) {
    const std::string a = argv[i];
    if (a == "--help") {
      std::printf(
          "usage: outline_service_realistic_area [--part NAME] [--profile NAME] [--poses N] [--mixed-fraction F]\n"
          "Where the part's area error comes from, pose by pose, on outline_service_realistic_table's frames\n"
          "(default knee-scallop at pm806, 6 poses): the service's part area; the truth's pixels counted and\n"
          "through the service; the bridge's kept pixels placed on the true top; the pixels lost and kept off the\n"
          "steel, by edge (straight / arc / corner), in %% of the true area. --mixed-fraction: the bridge's\n"
          "SegmentParams::mixed_fraction for a trial.\n");
      return 0;
    }
    if (a == "--part" && i + 1 < argc) shape = argv[++i];
    else if (a == "--profile" && i + 1 < argc)
      profile = argv[++i];
    else if (a == "--poses" && i + 1 < argc)
      n = std::max(1, std::atoi(argv[++i]));
    else if (a == "--mixed-fraction" && i + 1 < argc)
      mixed_fraction = std::atof(argv[++i]);
    else
      return std::fprintf(stderr, "unknown option '%s' (--help)\n", a.c_str()), 2;
  }
  std::printf(
      "%s@%s\n\n| pose | angle (deg) | face | part's area | truth's pixels counted | truth's pixels, part's area | "
      "kept pixels on the truth, part's area | lost: n, straight / arc / corner | kept off the steel |\n"
      "|---|---|---|---|---|---|---|---|---|\n",
      shape.c_str(), profile.c_str());
  const std::vector<Pose> poses = table_poses(n, case_seed(shape + "/poses"));
  for (int i = 0; i < n; ++i) one_pose(shape, profile, poses[i], case_seed(shape + profile) + i, i, mixed_fraction);
  return 0;
}
