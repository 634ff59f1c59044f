// The effects of real sensors on the rendered geometry (docs/scene.md says each effect's cause and source).
#include "sim/scene/effects.hpp"

#include <algorithm>
#include <cmath>

#include "sim/partgen/synth.hpp"

namespace hg::sim::detail {

using Vec2 = Eigen::Vector2d;
using Vec3 = Eigen::Vector3d;

std::vector<Warp> warps_of(const std::vector<partgen::PolygonWithHoles>& polys, double sagitta) {
  std::vector<Warp> out;
  for (const auto& poly : polys) {
    Warp w;
    if (sagitta != 0) {
      Vec2 lo = poly.outer.front(), hi = lo;
      for (const auto& p : poly.outer) lo = lo.cwiseMin(p), hi = hi.cwiseMax(p);
      w.s = sagitta;
      w.c = 0.5 * (lo + hi);
      double r2 = 0;
      for (const auto& p : poly.outer) r2 = std::max(r2, (p - w.c).squaredNorm());
      w.r0sq = sagitta < 0 ? r2 : 0;
      w.max_height = std::abs(4 * sagitta * r2);
    }
    out.push_back(w);
  }
  return out;
}

namespace {

inline double plane_depth(const Vec3& n, double offset, double a, double b) {
  return offset / (n.x() * a + n.y() * b + n.z());
}

}  // namespace

double top_depth(const RenderedFrame& out, const Warp& warp, double t, double a, double b) {
  const Vec3& n = out.table_normal;
  double z = plane_depth(n, out.table_offset + t, a, b);
  if (warp.s == 0) return z;
  const Eigen::Isometry3d table_from_camera = out.camera_from_table.inverse();
  for (int it = 0; it < 4; ++it) {
    const Vec3 q = table_from_camera * (z * Vec3(a, b, 1));
    z = plane_depth(n, out.table_offset + t + warp.height(q.x(), q.y()), a, b);
  }
  return z;
}

namespace {

inline double cross2(const Vec2& a, const Vec2& b) { return a.x() * b.y() - a.y() * b.x(); }

// One part's boundary edges bucketed in a uniform grid (table frame): the nearest edge to a point and
// whether a segment crosses the boundary, in time independent of the part's vertex count.
class EdgeGrid {
 public:
  explicit EdgeGrid(const partgen::PolygonWithHoles& poly, double cell = 0.01) : cell_(cell) {
    auto add_ring = [&](const partgen::Ring& r) {
      for (std::size_t i = 0; i < r.size(); ++i) edges_.push_back({r[i], r[(i + 1) % r.size()]});
    };
    add_ring(poly.outer);
    for (const auto& h : poly.holes) add_ring(h);
    lo_ = hi_ = poly.outer.front();
    for (const auto& p : poly.outer) lo_ = lo_.cwiseMin(p), hi_ = hi_.cwiseMax(p);
    lo_ -= Vec2(cell, cell);
    hi_ += Vec2(cell, cell);
    nx_ = static_cast<int>(std::ceil((hi_.x() - lo_.x()) / cell)) + 1;
    ny_ = static_cast<int>(std::ceil((hi_.y() - lo_.y()) / cell)) + 1;
    cells_.resize(static_cast<std::size_t>(nx_) * ny_);
    for (std::size_t e = 0; e < edges_.size(); ++e) {
      const auto& [a, b] = edges_[e];
      for_cells(a.cwiseMin(b), a.cwiseMax(b), [&](std::vector<int>& c) { c.push_back(static_cast<int>(e)); });
    }
  }
  // Distance to the nearest edge within `radius` and that edge's normal out of the material (the right-hand
  // normal: outer rings run counter-clockwise, holes clockwise). False when none is that close.
  bool nearest(const Vec2& p, double radius, double& dist, Vec2& normal) const {
    dist = radius;
    bool found = false;
    for_cells(p - Vec2(radius, radius), p + Vec2(radius, radius), [&](const std::vector<int>& c) {
      for (int e : c) {
        const auto& [a, b] = edges_[e];
        const Vec2 ab = b - a;
        const double s = std::clamp((p - a).dot(ab) / ab.squaredNorm(), 0.0, 1.0);
        const double d = (a + s * ab - p).norm();
        if (d < dist) dist = d, normal = Vec2(ab.y(), -ab.x()).normalized(), found = true;
      }
    });
    return found;
  }
  // Whether segment p-q meets an edge.
  bool crosses(const Vec2& p, const Vec2& q) const {
    bool hit = false;
    for_cells(p.cwiseMin(q), p.cwiseMax(q), [&](const std::vector<int>& c) {
      for (int e : c) {
        if (hit) return;
        const auto& [a, b] = edges_[e];
        const double d1 = cross2(b - a, p - a), d2 = cross2(b - a, q - a);
        const double d3 = cross2(q - p, a - p), d4 = cross2(q - p, b - p);
        hit = d1 * d2 <= 0 && d3 * d4 <= 0;
      }
    });
    return hit;
  }
  bool overlaps(const Vec2& lo, const Vec2& hi) const {
    return hi.x() >= lo_.x() && lo.x() <= hi_.x() && hi.y() >= lo_.y() && lo.y() <= hi_.y();
  }

 private:
  template <class F>
  void for_cells(const Vec2& lo, const Vec2& hi, F&& f) const {
    const int x0 = std::max(0, static_cast<int>((lo.x() - lo_.x()) / cell_));
    const int y0 = std::max(0, static_cast<int>((lo.y() - lo_.y()) / cell_));
    const int x1 = std::min(nx_ - 1, static_cast<int>((hi.x() - lo_.x()) / cell_));
    const int y1 = std::min(ny_ - 1, static_cast<int>((hi.y() - lo_.y()) / cell_));
    for (int y = y0; y <= y1; ++y)
      for (int x = x0; x <= x1; ++x) f(const_cast<std::vector<int>&>(cells_[static_cast<std::size_t>(y) * nx_ + x]));
  }
  double cell_;
  Vec2 lo_, hi_;
  int nx_ = 0, ny_ = 0;
  std::vector<std::pair<Vec2, Vec2>> edges_;
  std::vector<std::vector<int>> cells_;
};

// Grinding strips of one top face: parallel bands of strip_width across the part at a random direction;
// each is ground (else mill scale) with probability ground_fraction and tilted across by a random slope.
struct Strips {
  Vec2 across = Vec2::UnitX();  // unit vector across the strips
  double start = 0;
  std::vector<char> ground;
  std::vector<double> tilt;
};

Strips strips_of(const partgen::PolygonWithHoles& poly, const SensorEffects& fx, std::uint64_t seed, int k) {
  partgen::Rng rng(partgen::stream_seed(seed, 0x57121900u + k));
  Strips s;
  const double phi = M_PI * rng.uniform();
  s.across = Vec2(std::cos(phi), std::sin(phi));
  double lo = 1e300, hi = -1e300;
  for (const auto& p : poly.outer) lo = std::min(lo, p.dot(s.across)), hi = std::max(hi, p.dot(s.across));
  s.start = lo - fx.strip_width * rng.uniform();
  const int n = static_cast<int>((hi - s.start) / fx.strip_width) + 1;
  for (int j = 0; j < n; ++j) {
    s.ground.push_back(rng.uniform() < fx.ground_fraction);
    s.tilt.push_back(fx.strip_tilt_sigma * rng.normal());
  }
  return s;
}

// Spatter balls (hemispheres) and chips (flat flakes, slightly tilted) lying on the table, bucketed in
// 10 mm cells over the part of the table the camera sees.
struct Debris {
  struct Item {
    Vec2 c;
    double r, h;  // radius; chip thickness (0: a spatter hemisphere)
    Vec3 normal;  // chip's top face
  };
  std::vector<Item> items;
  Vec2 lo;
  int nx = 0, ny = 0;
  std::vector<std::vector<int>> cells;
  static constexpr double kCell = 0.01;
  // Height above the table and surface normal at p; false where no debris is.
  bool at(const Vec2& p, double& h, Vec3& n) const {
    if (items.empty()) return false;
    const int x = static_cast<int>((p.x() - lo.x()) / kCell), y = static_cast<int>((p.y() - lo.y()) / kCell);
    if (x < 0 || y < 0 || x >= nx || y >= ny) return false;
    bool found = false;
    h = 0;
    for (int i : cells[static_cast<std::size_t>(y) * nx + x]) {
      const Item& it = items[i];
      const Vec2 d = p - it.c;
      if (d.squaredNorm() >= it.r * it.r) continue;
      const double hi = it.h > 0 ? it.h : std::sqrt(it.r * it.r - d.squaredNorm());
      if (hi <= h) continue;
      h = hi;
      n = it.h > 0 ? it.normal : Vec3(d.x(), d.y(), hi).normalized();
      found = true;
    }
    return found;
  }
};

Debris debris_on(const TableSpec& table, const Vec2& lo, const Vec2& hi, std::uint64_t seed) {
  Debris d;
  partgen::Rng rng(partgen::stream_seed(seed, 0xDEB815u));
  const double area = (hi - lo).prod();
  const int spatter = static_cast<int>(std::round(table.spatter_per_m2 * area));
  const int chips = static_cast<int>(std::round(table.chips_per_m2 * area));
  for (int i = 0; i < spatter + chips; ++i) {
    Debris::Item it;
    it.c = Vec2(lo.x() + rng.uniform() * (hi.x() - lo.x()), lo.y() + rng.uniform() * (hi.y() - lo.y()));
    const bool chip = i >= spatter;
    it.r = chip ? 0.001 + 0.003 * rng.uniform() : 0.0003 + 0.0007 * rng.uniform();
    it.h = chip ? 0.0003 + 0.0007 * rng.uniform() : 0;
    const double tx = 0.15 * rng.normal(), ty = 0.15 * rng.normal();
    it.normal = Vec3(tx, ty, 1).normalized();
    d.items.push_back(it);
  }
  d.lo = lo;
  d.nx = static_cast<int>((hi.x() - lo.x()) / Debris::kCell) + 1;
  d.ny = static_cast<int>((hi.y() - lo.y()) / Debris::kCell) + 1;
  d.cells.resize(static_cast<std::size_t>(d.nx) * d.ny);
  for (std::size_t i = 0; i < d.items.size(); ++i) {
    const auto& it = d.items[i];
    const int x0 = std::max(0, static_cast<int>((it.c.x() - it.r - lo.x()) / Debris::kCell));
    const int x1 = std::min(d.nx - 1, static_cast<int>((it.c.x() + it.r - lo.x()) / Debris::kCell));
    const int y0 = std::max(0, static_cast<int>((it.c.y() - it.r - lo.y()) / Debris::kCell));
    const int y1 = std::min(d.ny - 1, static_cast<int>((it.c.y() + it.r - lo.y()) / Debris::kCell));
    for (int y = y0; y <= y1; ++y)
      for (int x = x0; x <= x1; ++x) d.cells[static_cast<std::size_t>(y) * d.nx + x].push_back(static_cast<int>(i));
  }
  return d;
}

}  // namespace

// Whether the table's top has an opening at table point (x, y): a perforation hole or a slat gap.
bool table_opening(const TableSpec& table, double x, double y) {
  if (table.kind == TableSpec::Kind::Slatted) {
    const double period = table.slat_width + table.slat_gap;
    const double f = x - period * std::floor(x / period);
    return f >= table.slat_width;
  }
  if (table.kind != TableSpec::Kind::Perforated) return false;
  const double p = table.hole_pitch, row_h = p * std::sqrt(3.0) / 2, r = table.hole_diameter / 2;
  const int row = static_cast<int>(std::floor(y / row_h + 0.5));
  for (int dr = -1; dr <= 1; ++dr) {
    const int rr = row + dr;
    const double off = (rr & 1) ? p / 2 : 0;
    const double cx = off + p * std::floor((x - off) / p + 0.5), cy = rr * row_h;
    if ((x - cx) * (x - cx) + (y - cy) * (y - cy) < r * r) return true;
  }
  return false;
}

namespace {

// Everything the per-pixel pass needs, built once per frame.
struct Context {
  const SceneSpec& spec;
  const SensorEffects& fx;
  const CameraProfile& prof;
  const RenderedFrame& out;
  const std::vector<Warp>& warps;
  Eigen::Isometry3d table_from_camera;
  Vec3 emitter, camera;  // table frame
  std::vector<EdgeGrid> grids;
  std::vector<Strips> strips;
  Debris debris;
};

// The surface a pixel's ray meets: point and normal in the table frame, material; `open` where the ray
// falls through a table opening (no return).
struct Hit {
  Vec3 p, n;
  Surface material;
  bool open = false;
  bool wall = false;
  int part = -1;
  Vec2 wall_normal = Vec2::Zero();
};

// The material and facet normal of part k's top face at table point p (strip tilt, warp slope, rounded
// edge); `drop` is how far the rounded edge lies below the top face.
void top_surface(const Context& cx, int k, const Vec3& p, Hit& h, double& drop) {
  const Warp& w = cx.warps[k];
  const Vec2 g = w.gradient(p.x(), p.y());
  h.n = w.s != 0 ? Vec3(-g.x(), -g.y(), 1).normalized() : Vec3::UnitZ();
  h.material = cx.fx.mill_scale;
  drop = 0;
  if (cx.fx.specular) {
    const Strips& s = cx.strips[k];
    const int j = static_cast<int>(std::floor((Vec2(p.x(), p.y()).dot(s.across) - s.start) / cx.fx.strip_width));
    if (j >= 0 && j < static_cast<int>(s.ground.size()) && s.ground[j]) {
      h.material = cx.fx.ground;
      h.n = (h.n + s.tilt[j] * Vec3(s.across.x(), s.across.y(), 0)).normalized();
    }
  }
  const double r = cx.fx.edge_radius;
  double e;
  Vec2 out_n;
  if (r > 0 && cx.grids[k].nearest(Vec2(p.x(), p.y()), r, e, out_n)) {
    // A quarter round of radius r: at e from the edge the surface has turned by asin((r - e) / r).
    const double sb = (r - e) / r, cb = std::sqrt(std::max(0.0, 1 - sb * sb));
    h.n = (cb * h.n + sb * Vec3(out_n.x(), out_n.y(), 0)).normalized();
    drop = r - r * cb;
    h.material = cx.fx.cut_face;
  }
}

// Classifies pixel (r, c) of noise-free depth z (table pattern and debris raise z_true in place).
Hit surface_at(const Context& cx, int r, int c, double& z) {
  const double a = (c - cx.prof.cx) / cx.prof.fx, b = (r - cx.prof.cy) / cx.prof.fy;
  Hit h;
  h.p = cx.table_from_camera * (z * Vec3(a, b, 1));
  const int label = cx.out.truth_labels.at<std::uint8_t>(r, c);
  if (label == 0) {
    h.n = Vec3::UnitZ();
    h.material = cx.fx.table_surface;
    h.open = table_opening(cx.fx.table, h.p.x(), h.p.y());
    double dh;
    Vec3 dn;
    if (!h.open && cx.debris.at(Vec2(h.p.x(), h.p.y()), dh, dn)) {
      z = plane_depth(cx.out.table_normal, cx.out.table_offset + dh, a, b);
      h.p = cx.table_from_camera * (z * Vec3(a, b, 1));
      h.n = dn;
      h.material = cx.fx.mill_scale;
    }
    return h;
  }
  const int k = label - 1;
  h.part = k;
  const double t = cx.out.part_thickness[k];
  if (std::abs(h.p.z() - t - cx.warps[k].height(h.p.x(), h.p.y())) < 1e-5) {
    double drop;
    top_surface(cx, k, h.p, h, drop);
    if (drop > 0) {
      z = top_depth(cx.out, cx.warps[k], t - drop, a, b);
      h.p = cx.table_from_camera * (z * Vec3(a, b, 1));
    }
    return h;
  }
  double e;
  h.wall = true;
  h.material = cx.fx.cut_face;
  if (!cx.grids[k].nearest(Vec2(h.p.x(), h.p.y()), 0.005, e, h.wall_normal)) h.wall_normal = Vec2::UnitX();
  h.n = Vec3(h.wall_normal.x(), h.wall_normal.y(), 0);
  return h;
}

// Whether the segment from the surface point to the emitter passes through a part (the baseline's shadow).
bool in_shadow(const Context& cx, const Hit& h) {
  const Vec3& L = cx.emitter;
  Vec3 p = h.p;
  if (h.wall) {
    if (h.n.dot(L - p) <= 0) return true;  // the wall faces away from the emitter
    p += 2e-5 * h.n;
  }
  for (std::size_t k = 0; k < cx.grids.size(); ++k) {
    const double top = cx.out.part_thickness[k] + cx.warps[k].max_height;
    if (p.z() >= top || L.z() <= top) continue;
    const Vec3 q = p + (L - p) * ((top - p.z()) / (L.z() - p.z()));
    const Vec2 a(p.x(), p.y()), b(q.x(), q.y());
    if (!cx.grids[k].overlaps(a.cwiseMin(b), a.cwiseMax(b))) continue;
    if (cx.grids[k].crosses(a, b)) return true;
  }
  return false;
}

// Mean return of a surface point (grey face met square on at the emitter's height = 1): the diffuse
// (Lambert) part and the specular (Beckmann) lobe about the half vector of light and view.
void mean_return(const Context& cx, const Hit& h, double& diffuse, double& specular) {
  const Vec3 to_l = cx.emitter - h.p, to_c = cx.camera - h.p;
  const Vec3 l = to_l.normalized(), v = to_c.normalized();
  const double cos_i = std::max(0.0, h.n.dot(l));
  const double falloff = (cx.emitter.z() * cx.emitter.z()) / to_l.squaredNorm();  // inverse square
  diffuse = h.material.albedo * cos_i * falloff;
  specular = 0;
  if (cx.fx.specular && cos_i > 0 && h.n.dot(v) > 0) {
    const double ch = std::min(1.0, h.n.dot((l + v).normalized()));
    const double tan2 = (1 - ch * ch) / (ch * ch), m = h.material.roughness;
    specular = h.material.specular * std::exp(-tan2 / (m * m)) * falloff;
  }
}

}  // namespace

// Detection probability of a mean return S with N speckle cells per pixel: P(gamma(N, S/N) > threshold) =
// Q(N, N threshold / S), the regularised upper incomplete gamma function (a finite sum for integer N).
double detection_probability(double mean_return, double threshold, int cells) {
  if (!(mean_return > 0)) return 0;
  const double x = cells * threshold / mean_return;
  double term = 1, sum = 1;
  for (int k = 1; k < cells; ++k) sum += (term *= x / k);
  return std::exp(-x) * sum;
}

namespace {

// A sub-ray's depth and weight (its diffuse return) for the mixed pixels: the surface it meets first.
void cast(const Context& cx, double u, double v, double& z, double& weight) {
  const double a = (u - cx.prof.cx) / cx.prof.fx, b = (v - cx.prof.cy) / cx.prof.fy;
  const Vec3 d(a, b, 1);
  const RenderedFrame& out = cx.out;
  z = plane_depth(out.table_normal, out.table_offset, a, b);
  Hit h;
  h.p = cx.table_from_camera * (z * d);
  h.n = Vec3::UnitZ();
  h.material = cx.fx.table_surface;
  h.open = table_opening(cx.fx.table, h.p.x(), h.p.y());
  for (std::size_t k = 0; k < out.part_polygons.size(); ++k) {
    const double t = out.part_thickness[k];
    const double zt = top_depth(out, cx.warps[k], t, a, b);
    if (zt >= z) continue;
    const Vec3 q = cx.table_from_camera * (zt * d);
    if (partgen::contains(out.part_polygons[k], q.x(), q.y())) {
      z = zt, h.p = q, h.n = Vec3::UnitZ(), h.material = cx.fx.mill_scale, h.open = false;
      continue;
    }
    const Vec3 qb = cx.table_from_camera * (z * d);
    if (!partgen::contains(out.part_polygons[k], qb.x(), qb.y())) continue;
    double z_out = zt, z_in = z;  // enters through a side wall: bisection as the renderer does
    for (int it = 0; it < 30; ++it) {
      const double zm = 0.5 * (z_out + z_in);
      const Vec3 qm = cx.table_from_camera * (zm * d);
      (partgen::contains(out.part_polygons[k], qm.x(), qm.y()) ? z_in : z_out) = zm;
    }
    z = z_in, h.p = cx.table_from_camera * (z * d), h.material = cx.fx.cut_face, h.open = false;
    double e;
    Vec2 wn = Vec2::UnitX();
    cx.grids[k].nearest(Vec2(h.p.x(), h.p.y()), 0.005, e, wn);
    h.n = Vec3(wn.x(), wn.y(), 0);
  }
  double spec;
  mean_return(cx, h, weight, spec);
  if (h.open) weight = 0;
}

// The depth a pixel at a depth jump reports: the return-weighted mean over its footprint (4 x 4 sub-rays),
// what a triangulation spot centroid or a phase average over the footprint gives.
double footprint_depth(const Context& cx, int r, int c, double z_centre) {
  const int n = 4;
  const double f = cx.prof.footprint_px;
  double sw = 0, swz = 0;
  for (int i = 0; i < n; ++i)
    for (int j = 0; j < n; ++j) {
      double z, w;
      cast(cx, c + f * ((j + 0.5) / n - 0.5), r + f * ((i + 0.5) / n - 0.5), z, w);
      sw += w, swz += w * z;
    }
  return sw > 0 ? swz / sw : z_centre;
}

bool at_depth_jump(const cv::Mat& z, int r, int c, double jump) {
  const double zc = z.at<double>(r, c);
  const int dr[4] = {-1, 1, 0, 0}, dc[4] = {0, 0, -1, 1};
  for (int i = 0; i < 4; ++i) {
    const int rr = r + dr[i], cc = c + dc[i];
    if (rr >= 0 && cc >= 0 && rr < z.rows && cc < z.cols && std::abs(z.at<double>(rr, cc) - zc) > jump) return true;
  }
  return false;
}

Context make_context(const SceneSpec& spec, const CameraProfile& prof, const RenderedFrame& out,
                     const std::vector<Warp>& warps) {
  Context cx{spec, spec.effects, prof, out, warps, out.camera_from_table.inverse(), {}, {}, {}, {}, {}};
  cx.emitter = cx.table_from_camera * prof.emitter;
  cx.camera = cx.table_from_camera * Vec3::Zero();
  for (std::size_t k = 0; k < out.part_polygons.size(); ++k) {
    cx.grids.emplace_back(out.part_polygons[k]);
    cx.strips.push_back(strips_of(out.part_polygons[k], spec.effects, spec.seed, static_cast<int>(k)));
  }
  const TableSpec& table = spec.effects.table;
  if (table.spatter_per_m2 > 0 || table.chips_per_m2 > 0) {
    // The table area in view: the image corners on the table plane.
    Vec2 lo(1e300, 1e300), hi(-1e300, -1e300);
    for (double u : {-0.5, prof.width - 0.5})
      for (double v : {-0.5, prof.height - 0.5}) {
        const double a = (u - prof.cx) / prof.fx, b = (v - prof.cy) / prof.fy;
        const Vec3 q = cx.table_from_camera * (plane_depth(out.table_normal, out.table_offset, a, b) * Vec3(a, b, 1));
        lo = lo.cwiseMin(Vec2(q.x(), q.y())), hi = hi.cwiseMax(Vec2(q.x(), q.y()));
      }
    cx.debris = debris_on(table, lo, hi, spec.seed);
  }
  return cx;
}

// One pixel's reported depth (0: none) and intensity (0..255) from its surface and the random stream.
struct PixelOut {
  double z = 0;  // metres, 0: no return
  int intensity = 0;
};

PixelOut sense(const Context& cx, const Hit& h, double z, partgen::Rng& rng) {
  // Fixed number of draws per pixel, so a change in one effect does not move the others' streams.
  double u_speckle = 1;
  for (int i = 0; i < std::max(1, cx.prof.speckle_cells); ++i) u_speckle *= std::max(1e-300, rng.uniform());
  const double gain = -std::log(u_speckle) / std::max(1, cx.prof.speckle_cells);  // gamma(N, 1/N), mean 1
  PixelOut o;
  if (h.open) return o;
  if (cx.fx.shadow && in_shadow(cx, h)) return o;
  double diffuse, specular;
  mean_return(cx, h, diffuse, specular);
  const double received = diffuse * gain + specular;  // a specular glint is not speckled
  const double sat = cx.prof.saturation > 0 ? cx.prof.saturation : 1;
  o.intensity = static_cast<int>(std::min(255.0, std::round(255 * received / sat)));
  if (cx.fx.specular && received >= sat) return o;  // saturated: the pattern cannot be decoded
  if (cx.fx.incidence && received < cx.prof.return_threshold) return o;
  o.z = z;
  return o;
}

// Noise, the profile's random dropout and (without the mixed-pixel model) its random flying pixels, then
// counts; the same rules as the renderer without effects.
std::uint16_t to_counts(const CameraProfile& prof, bool mixed_model, double z, double other, partgen::Rng& rng) {
  const double u_drop = rng.uniform(), u_fly = rng.uniform(), u_mix = rng.uniform(), noise = rng.normal();
  if (!(z > 0)) return 0;
  if (!mixed_model && other != z && u_fly < prof.flying_pixel_prob) z += u_mix * (other - z);
  z += (prof.noise_a + prof.noise_b * z * z) * noise;
  const double counts = std::round(z / prof.depth_unit);
  return (u_drop < prof.dropout || !(counts > 0)) ? 0 : static_cast<std::uint16_t>(std::min(counts, 65535.0));
}

// The neighbour across the largest depth step above `jump` (the renderer's flying-pixel partner), else z.
double partner(const cv::Mat& z_true, int r, int c, double jump) {
  const double z = z_true.at<double>(r, c);
  double other = z, step = jump;
  const int dr[4] = {0, 0, -1, 1}, dc[4] = {-1, 1, 0, 0};
  for (int i = 0; i < 4; ++i) {
    const int rr = r + dr[i], cc = c + dc[i];
    if (rr < 0 || cc < 0 || rr >= z_true.rows || cc >= z_true.cols) continue;
    const double zn = z_true.at<double>(rr, cc);
    if (std::abs(zn - z) > step) step = std::abs(zn - z), other = zn;
  }
  return other;
}

}  // namespace

void apply_effects(const SceneSpec& spec, const CameraProfile& prof, std::uint64_t frame_index,
                   const std::vector<Warp>& warps, cv::Mat& z_true, RenderedFrame& out) {
  const Context cx = make_context(spec, prof, out, warps);
  const int W = z_true.cols, H = z_true.rows;
  const double jump = 0.003;  // the renderer's depth-edge threshold
  partgen::Rng rng(partgen::stream_seed(spec.seed, frame_index));
  partgen::Rng fx_rng(partgen::stream_seed(spec.seed ^ 0xEFFEC7u, frame_index));
  out.depth = cv::Mat(H, W, CV_16UC1);
  if (spec.effects.intensity) out.intensity = cv::Mat::zeros(H, W, CV_8UC1);
  const cv::Mat z_geom = z_true.clone();  // before debris and rounded edges: where the part edges are
  for (int r = 0; r < H; ++r)
    for (int c = 0; c < W; ++c) {
      double z = z_true.at<double>(r, c);
      const Hit h = surface_at(cx, r, c, z);
      if (spec.effects.mixed_pixels && at_depth_jump(z_geom, r, c, jump)) z = footprint_depth(cx, r, c, z);
      z_true.at<double>(r, c) = z;
      const PixelOut o = sense(cx, h, z, fx_rng);
      if (spec.effects.intensity) out.intensity.at<std::uint8_t>(r, c) = static_cast<std::uint8_t>(o.intensity);
      const double other = partner(z_geom, r, c, jump);
      out.depth.at<std::uint16_t>(r, c) = to_counts(prof, spec.effects.mixed_pixels, o.z, other, rng);
    }
}

}  // namespace hg::sim::detail
