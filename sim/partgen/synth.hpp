// Cloud synthesis: what a top-down depth camera sees of the parts of a Scene lying on a table.
// The camera's pixel grid is axis-aligned in the table frame with pixel centres on the lattice
// ((k + 0.5) pitch, (m + 0.5) pitch); a part's rotation in its Pose is its rotation against that grid.
// Points come out in SCAN-LINE order: rows from the top of the image (largest y) down, and within a
// row columns left to right (increasing x). DSHI's heritable initial relies on this order.
#pragma once

#include "sim/partgen/shapes.hpp"

#include <cstdint>
#include <random>
#include <vector>

namespace hg::partgen {

// Deterministic random numbers: mt19937_64 bits turned into uniforms and normals by formulas written
// here (not std::*_distribution, whose algorithms differ between standard libraries).
class Rng {
 public:
  explicit Rng(std::uint64_t seed) : engine_(seed) {}
  double uniform();  // [0, 1), 53 random bits
  double normal();   // standard normal, Marsaglia polar method
 private:
  std::mt19937_64 engine_;
  double spare_ = 0;
  bool has_spare_ = false;
};
// Independent seeds for the separate streams of one run (SplitMix64 of seed and stream number).
std::uint64_t stream_seed(std::uint64_t seed, std::uint64_t stream);

struct Span {
  double x0, x1;  // covers x0 <= x < x1
  int part;
};

// Even-odd spans of the scene's parts along horizontal lines, fast for many lines: edges are bucketed
// in bands of rows so a query only looks at the edges near its y. Works in any 2-D frame (the camera
// bridge can feed polygons already mapped into image coordinates).
class SpanRasterizer {
 public:
  // polys[k] is part k. Lines queried must satisfy y_bottom <= y <= y_top; bands of height band_height.
  SpanRasterizer(const std::vector<const PolygonWithHoles*>& polys, double y_top, double y_bottom, double band_height);
  // Spans of every part along the line at y, sorted by x0. Reuses `out`'s storage.
  void spans(double y, std::vector<Span>& out) const;

 private:
  int band_of(double y) const;
  struct Edge {
    Vec2 a, b;
    int part;
  };
  std::vector<Edge> edges_;
  std::vector<std::uint32_t> band_start_, band_edges_;  // CSR: edges meeting band k
  double y_top_, band_height_;
  int bands_;
  mutable std::vector<std::pair<int, double>> scratch_;  // (part, crossing x)
};

struct CloudOptions {
  double pitch = 0.002;       // pixel spacing on the table, metres
  double in_plane_sigma = 0;  // Gaussian noise added to x and y, metres
  double depth_sigma = 0;     // Gaussian noise added to z, metres
  double dropout = 0;         // fraction of pixels lost at random, [0, 1]
  bool jagged = false;        // edge pixels kept with probability = fraction of the pixel covered
  int coverage_subrows = 8;   // sub-lines per pixel row used to measure coverage (jagged only)
  std::uint64_t seed = 1;
};

struct PixelGrid {
  double pitch = 0;
  double origin_x = 0;  // x of column 0's centre
  double origin_y = 0;  // y of row 0's centre (the top row)
  int rows = 0, cols = 0;
  double x(int col) const { return origin_x + col * pitch; }
  double y(int row) const { return origin_y - row * pitch; }
};

// The grid covering the scene with one spare pixel on every side.
PixelGrid grid_for(const Scene& scene, double pitch);

struct Cloud {
  PixelGrid grid;
  std::vector<double> xyz;              // x0 y0 z0 x1 y1 z1 ... in scan-line order
  std::vector<std::int32_t> pixel_row;  // pixel each point came from
  std::vector<std::int32_t> pixel_col;
  std::vector<std::uint16_t> part;  // index of the scene part under the pixel
  std::size_t candidates = 0;       // pixels seen on the parts before dropout
  double expected_points = 0;       // sum of pixel coverage (jagged) or centre count, times (1 - dropout)
  std::size_t size() const { return pixel_row.size(); }
};

// Throws std::invalid_argument naming the bad option (non-positive pitch, negative sigma, dropout
// outside [0, 1], grid larger than 400 M pixels, empty scene).
Cloud synthesize(const Scene& scene, const CloudOptions& options);
// Number of pixel centres inside the scene's parts: the noise-free, dropout-free, non-jagged count.
std::size_t count_pixel_centres(const Scene& scene, double pitch);
// Pitch at which count_pixel_centres is as close as possible to target (secant steps on n ~ area/p^2).
double fit_pitch(const Scene& scene, std::size_t target);

// The pixel staircase of a ring: what an outline through the outermost pixel centres looks like, without
// running an outline. The ring is sampled every pitch / 8 and each sample snapped to the nearest pixel
// centre on the lattice ((k + 0.5) pitch); repeats and back-and-forth spikes are removed (a stack, O(n)).
// Every vertex is a pixel centre within pitch / sqrt(2) of the ring; no inward bias (the snapping is
// symmetric). For the path planner's tests and benchmark, which need staircases of known polygons.
Ring pixel_staircase(const Ring& ring, double pitch);

}  // namespace hg::partgen
