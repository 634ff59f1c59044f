#include "sim/partgen/synth.hpp"

#include <algorithm>
#include <cmath>
#include <limits>
#include <stdexcept>
#include <string>

namespace hg::partgen {

double Rng::uniform() { return static_cast<double>(engine_() >> 11) * 0x1.0p-53; }

double Rng::normal() {
  if (has_spare_) {
    has_spare_ = false;
    return spare_;
  }
  double u, v, s;
  do {
    u = 2.0 * uniform() - 1.0;
    v = 2.0 * uniform() - 1.0;
    s = u * u + v * v;
  } while (s >= 1.0 || s == 0.0);
  const double m = std::sqrt(-2.0 * std::log(s) / s);
  spare_ = v * m;
  has_spare_ = true;
  return u * m;
}

std::uint64_t stream_seed(std::uint64_t seed, std::uint64_t stream) {
  std::uint64_t z = seed + 0x9E3779B97F4A7C15ull * (stream + 1);
  z = (z ^ (z >> 30)) * 0xBF58476D1CE4E5B9ull;
  z = (z ^ (z >> 27)) * 0x94D049BB133111EBull;
  return z ^ (z >> 31);
}

SpanRasterizer::SpanRasterizer(const std::vector<const PolygonWithHoles*>& polys, double y_top, double y_bottom,
                               double band_height)
    : y_top_(y_top), band_height_(band_height) {
  if (!(band_height > 0) || !(y_top >= y_bottom))
    throw std::invalid_argument("SpanRasterizer: need y_top >= y_bottom and a positive band height");
  bands_ = static_cast<int>(std::floor((y_top - y_bottom) / band_height)) + 1;
  auto add_ring = [&](const Ring& r, int part) {
    for (size_t i = 0, j = r.size() - 1; i < r.size(); j = i++)
      if (r[i].y() != r[j].y()) edges_.push_back({r[j], r[i], part});  // horizontal edges never cross
  };
  for (size_t k = 0; k < polys.size(); ++k) {
    add_ring(polys[k]->outer, static_cast<int>(k));
    for (const Ring& h : polys[k]->holes) add_ring(h, static_cast<int>(k));
  }
  auto band_range = [&](const Edge& e) {
    return std::pair{band_of(std::max(e.a.y(), e.b.y())), band_of(std::min(e.a.y(), e.b.y()))};
  };
  band_start_.assign(bands_ + 1, 0);
  for (const Edge& e : edges_) {
    const auto [f, l] = band_range(e);
    for (int b = f; b <= l; ++b) ++band_start_[b + 1];
  }
  for (int b = 0; b < bands_; ++b) band_start_[b + 1] += band_start_[b];
  band_edges_.resize(band_start_[bands_]);
  std::vector<std::uint32_t> fill(band_start_.begin(), band_start_.end() - 1);
  for (size_t i = 0; i < edges_.size(); ++i) {
    const auto [f, l] = band_range(edges_[i]);
    for (int b = f; b <= l; ++b) band_edges_[fill[b]++] = static_cast<std::uint32_t>(i);
  }
}

int SpanRasterizer::band_of(double y) const {
  // Clamped in double before the conversion so a far-away y cannot overflow the int.
  return static_cast<int>(std::clamp(std::floor((y_top_ - y) / band_height_), 0.0, double(bands_ - 1)));
}

void SpanRasterizer::spans(double y, std::vector<Span>& out) const {
  out.clear();
  // lo <= y < hi for a crossing edge, and band numbers are a monotone function of y (rounded subtraction,
  // division and floor are all monotone), so the one band of y lists every edge that can cross it.
  const int band = band_of(y);
  scratch_.clear();
  for (std::uint32_t k = band_start_[band]; k < band_start_[band + 1]; ++k) {
    const Edge& e = edges_[band_edges_[k]];
    if (edge_crosses(e.a, e.b, y)) scratch_.emplace_back(e.part, crossing_x(e.a, e.b, y));
  }
  std::sort(scratch_.begin(), scratch_.end());
  for (size_t i = 0; i + 1 < scratch_.size(); i += 2) {
    // Each part's crossings are even in number (closed rings), so pairs never straddle two parts.
    if (scratch_[i].second < scratch_[i + 1].second)
      out.push_back({scratch_[i].second, scratch_[i + 1].second, scratch_[i].first});
  }
  std::sort(out.begin(), out.end(), [](const Span& a, const Span& b) { return a.x0 < b.x0; });
}

PixelGrid grid_for(const Scene& scene, double pitch) {
  if (scene.parts.empty()) throw std::invalid_argument("scene has no parts");
  if (!(pitch > 0) || !std::isfinite(pitch))
    throw std::invalid_argument("pitch must be a positive finite number of metres, got " + std::to_string(pitch));
  Box b{INFINITY, INFINITY, -INFINITY, -INFINITY};
  for (const PlacedPart& p : scene.parts) {
    const Box pb = bounding_box(p.placed);
    b = {std::min(b.min_x, pb.min_x), std::min(b.min_y, pb.min_y), std::max(b.max_x, pb.max_x),
         std::max(b.max_y, pb.max_y)};
  }
  const double cols = std::ceil(b.max_x / pitch) - std::floor(b.min_x / pitch) + 3;
  const double rows = std::ceil(b.max_y / pitch) - std::floor(b.min_y / pitch) + 3;
  if (cols * rows > 400e6)
    throw std::invalid_argument("pitch " + std::to_string(pitch) + " m gives a grid of " +
                                std::to_string(cols * rows / 1e6) + " M pixels (limit 400 M)");
  PixelGrid g;
  g.pitch = pitch;
  // Pixel centres sit on the table-anchored lattice (k + 0.5) pitch, with one spare pixel each side.
  g.origin_x = (std::floor(b.min_x / pitch) - 1 + 0.5) * pitch;
  g.origin_y = (std::ceil(b.max_y / pitch) + 1 - 0.5) * pitch;
  g.cols = static_cast<int>(cols);
  g.rows = static_cast<int>(rows);
  return g;
}

namespace {
std::vector<const PolygonWithHoles*> placed_polygons(const Scene& scene) {
  std::vector<const PolygonWithHoles*> polys;
  for (const PlacedPart& p : scene.parts) polys.push_back(&p.placed);
  return polys;
}

SpanRasterizer rasterizer_for(const Scene& scene, const PixelGrid& g) {
  return SpanRasterizer(placed_polygons(scene), g.y(0) + g.pitch, g.y(g.rows - 1) - g.pitch, g.pitch);
}

// First column whose centre x satisfies x >= a (exact comparison on the same formula as PixelGrid::x).
int first_col_at_or_after(const PixelGrid& g, double a) {
  int i = static_cast<int>(std::clamp(std::ceil((a - g.origin_x) / g.pitch), 0.0, double(g.cols)));
  while (i > 0 && g.x(i - 1) >= a) --i;
  while (i < g.cols && g.x(i) < a) ++i;
  return i;
}

void validate(const CloudOptions& o) {
  auto bad = [](const std::string& what) { throw std::invalid_argument(what); };
  if (!(o.in_plane_sigma >= 0) || !std::isfinite(o.in_plane_sigma)) bad("in-plane noise sigma must be >= 0");
  if (!(o.depth_sigma >= 0) || !std::isfinite(o.depth_sigma)) bad("depth noise sigma must be >= 0");
  if (!(o.dropout >= 0 && o.dropout <= 1)) bad("dropout must be a fraction in [0, 1]");
  if (o.coverage_subrows < 1 || o.coverage_subrows > 64) bad("coverage_subrows must be in 1..64");
}
}  // namespace

Cloud synthesize(const Scene& scene, const CloudOptions& o) {
  validate(o);
  Cloud cloud;
  const PixelGrid g = grid_for(scene, o.pitch);
  cloud.grid = g;
  const SpanRasterizer raster = rasterizer_for(scene, g);
  Rng jag_rng(stream_seed(o.seed, 1)), drop_rng(stream_seed(o.seed, 2)), noise_rng(stream_seed(o.seed, 3));

  const size_t estimate = static_cast<size_t>(scene.total_area() / (o.pitch * o.pitch) * 1.02 + 64);
  cloud.xyz.reserve(3 * estimate);
  cloud.pixel_row.reserve(estimate);
  cloud.pixel_col.reserve(estimate);
  cloud.part.reserve(estimate);

  std::vector<Span> spans;
  std::vector<double> coverage(o.jagged ? g.cols : 0);
  std::vector<int> coverage_part(o.jagged ? g.cols : 0, -1);
  double coverage_sum = 0;

  auto emit = [&](int row, int col, int part) {
    ++cloud.candidates;
    if (o.dropout > 0 && drop_rng.uniform() < o.dropout) return;
    double x = g.x(col), y = g.y(row), z = scene.parts[part].shape.thickness;
    if (o.in_plane_sigma > 0) {
      x += o.in_plane_sigma * noise_rng.normal();
      y += o.in_plane_sigma * noise_rng.normal();
    }
    if (o.depth_sigma > 0) z += o.depth_sigma * noise_rng.normal();
    cloud.xyz.insert(cloud.xyz.end(), {x, y, z});
    cloud.pixel_row.push_back(row);
    cloud.pixel_col.push_back(col);
    cloud.part.push_back(static_cast<std::uint16_t>(part));
  };

  for (int row = 0; row < g.rows; ++row) {
    const double yc = g.y(row);
    if (!o.jagged) {
      raster.spans(yc, spans);
      for (const Span& s : spans)
        for (int col = first_col_at_or_after(g, s.x0); col < g.cols && g.x(col) < s.x1; ++col) emit(row, col, s.part);
      continue;
    }
    // Jagged edges: coverage of each pixel square, exact along x and sampled on sub-lines along y.
    std::fill(coverage.begin(), coverage.end(), 0.0);
    const double w = 1.0 / o.coverage_subrows;
    int lo_col = g.cols, hi_col = -1;
    for (int k = 0; k < o.coverage_subrows; ++k) {
      const double ys = yc + g.pitch * (0.5 - (k + 0.5) * w);
      raster.spans(ys, spans);
      for (const Span& s : spans) {
        const int c0 = std::max(0, static_cast<int>(std::floor((s.x0 - g.origin_x) / g.pitch + 0.5)));
        const int c1 = std::min(g.cols - 1, static_cast<int>(std::floor((s.x1 - g.origin_x) / g.pitch + 0.5)));
        for (int col = c0; col <= c1; ++col) {
          const double left = g.x(col) - g.pitch / 2, right = left + g.pitch;
          const double overlap = std::min(right, s.x1) - std::max(left, s.x0);
          if (overlap <= 0) continue;
          coverage[col] += w * std::min(1.0, overlap / g.pitch);
          coverage_part[col] = s.part;
        }
        lo_col = std::min(lo_col, c0);
        hi_col = std::max(hi_col, c1);
      }
    }
    for (int col = std::max(lo_col, 0); col <= hi_col; ++col) {
      const double c = std::min(coverage[col], 1.0);
      if (c <= 0) continue;
      coverage_sum += c;
      if (c >= 1.0 || jag_rng.uniform() < c) emit(row, col, coverage_part[col]);
    }
  }
  cloud.expected_points = (o.jagged ? coverage_sum : static_cast<double>(cloud.candidates)) * (1.0 - o.dropout);
  return cloud;
}

std::size_t count_pixel_centres(const Scene& scene, double pitch) {
  const PixelGrid g = grid_for(scene, pitch);
  const SpanRasterizer raster = rasterizer_for(scene, g);
  std::vector<Span> spans;
  std::size_t n = 0;
  for (int row = 0; row < g.rows; ++row) {
    raster.spans(g.y(row), spans);
    for (const Span& s : spans) {
      const int first = first_col_at_or_after(g, s.x0);
      const int end = first_col_at_or_after(g, s.x1);  // first centre at or after x1 is outside
      n += static_cast<std::size_t>(std::max(0, end - first));
    }
  }
  return n;
}

double fit_pitch(const Scene& scene, std::size_t target) {
  if (target == 0) throw std::invalid_argument("fit_pitch: target point count must be positive");
  double pitch = std::sqrt(scene.total_area() / static_cast<double>(target));
  double best = pitch;
  double best_err = std::numeric_limits<double>::infinity();
  for (int it = 0; it < 30; ++it) {
    const std::size_t n = count_pixel_centres(scene, pitch);
    const double err = std::abs(static_cast<double>(n) - static_cast<double>(target));
    if (err < best_err) {
      best_err = err;
      best = pitch;
    }
    if (n == target || n == 0) break;
    // n ~ A / p^2, so p scales with sqrt(n / target); damped a little to avoid cycling on the steps.
    pitch *= std::pow(static_cast<double>(n) / static_cast<double>(target), 0.5 * (it < 10 ? 1.0 : 0.5));
  }
  return best;
}

Ring pixel_staircase(const Ring& ring, double pitch) {
  Ring out;
  auto snap = [&](const Vec2& p) {
    return Vec2((std::floor(p.x() / pitch) + 0.5) * pitch, (std::floor(p.y() / pitch) + 0.5) * pitch);
  };
  for (std::size_t i = 0; i < ring.size(); ++i) {
    const Vec2 a = ring[i], b = ring[(i + 1) % ring.size()];
    const int m = int(std::ceil((b - a).norm() / (pitch / 8)));
    for (int k = 0; k < m; ++k) {
      const Vec2 q = snap(a + (b - a) * (double(k) / m));
      if (!out.empty() && (q - out.back()).norm() < 1e-12) continue;
      if (out.size() >= 2 && (q - out[out.size() - 2]).norm() < 1e-12) {
        out.pop_back();
        continue;
      }
      out.push_back(q);
    }
  }
  while (out.size() > 2 && (out.front() - out.back()).norm() < 1e-12) out.pop_back();
  return out;
}

}  // namespace hg::partgen
