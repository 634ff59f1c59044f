// Noise and pitch estimation of the smoothing step.
#include "path_planner/smooth/stages.hpp"

#include <algorithm>
#include <cmath>

namespace hg::path_planner {

double estimate_pitch(const std::vector<Loop>& loops) {
  std::vector<double> lengths;
  std::size_t edges = 0;
  double longest_loop = 0;
  const double tan10 = std::tan(10.0 * M_PI / 180.0);
  for (const Loop& l : loops) {
    const std::size_t n = l.points.size();
    edges += n;
    longest_loop = std::max(longest_loop, ring_length(l.points));
    for (std::size_t i = 0; i < n; ++i) {
      const Vec2 d = l.points[(i + 1) % n] - l.points[i];
      const double a = std::abs(d.x()), b = std::abs(d.y());
      if (std::min(a, b) <= tan10 * std::max(a, b) && std::max(a, b) > 0) lengths.push_back(d.norm());
    }
  }
  // A staircase has many short axis-parallel steps, all one pitch long; a hand-drawn polygon (few long
  // edges) has no pitch. Noise tilts the steps: then too few are axis-parallel and there is no estimate
  // (the lattice is not recoverable from a noisy boundary; see docs/path_planner.md).
  if (lengths.size() < 16 || lengths.size() * 4 < edges) return 0;
  auto mid = lengths.begin() + lengths.size() / 2;
  std::nth_element(lengths.begin(), mid, lengths.end());
  const double median = *mid;
  // Lattice steps are all one pitch long; noisy edges that happen to lie near an axis are not.
  const std::size_t exact = std::size_t(
      std::count_if(lengths.begin(), lengths.end(), [&](double l) { return std::abs(l - median) <= 0.02 * median; }));
  if (exact * 2 < lengths.size()) return 0;
  return median <= longest_loop / 200 ? median : 0;
}

double estimate_vertex_spacing(const std::vector<Loop>& loops) {
  std::vector<double> lengths;
  for (const Loop& l : loops) {
    const std::size_t n = l.points.size();
    if (n < 200) continue;
    for (std::size_t i = 0; i < n; ++i) lengths.push_back((l.points[(i + 1) % n] - l.points[i]).norm());
  }
  if (lengths.empty()) return 0;
  auto q = lengths.begin() + lengths.size() / 4;
  std::nth_element(lengths.begin(), q, lengths.end());
  return *q;
}

Spacing choose_spacing(const OutlineInput& in, const SmoothOptions& configured) {
  if (configured.pitch > 0) return {configured.pitch, "pixel-pitch"};
  if (in.point_spacing > 0 && std::isfinite(in.point_spacing)) return {in.point_spacing, "outline"};
  if (const double p = estimate_pitch(in.loops); p > 0) return {p, "staircase"};
  if (const double s = estimate_vertex_spacing(in.loops); s > 0) return {s, "vertices"};
  return {0, "none"};
}

namespace smooth {

int window_of(const SmoothOptions& o) { return std::max(5, int(std::lround(2 * o.window_pitches))); }

// Noise of a window mean (the mean of `win` consecutive vertices): from five adjacent window means M-2..M2
// around each vertex, E = 3/4 M0 - (M-1 + M1)/2 + (M-2 + M2)/8 cancels a straight or evenly curved edge
// (position, slope and curvature) and leaves noise and staircase with variance 1.094 sigma^2 for
// independent windows. It measures the noise as it is, correlated between neighbouring vertices or not.
// Appends |E| across the edge at every vertex (none for a loop shorter than the five windows).
void append_window_noise(const Unrolled& u, int win, std::vector<double>& dev) {
  const long n = u.n;
  if (n < 5 * win) return;
  auto mean_at = [&](long centre) {
    const long a = centre - win / 2 + n, b = a + win;
    return Vec2((u.mx[b] - u.mx[a]) / win, (u.my[b] - u.my[a]) / win);
  };
  for (long i = 0; i < n; ++i) {
    const Vec2 m0 = mean_at(i), m1 = mean_at(i + win), m_1 = mean_at(i - win), m2 = mean_at(i + 2 * win),
               m_2 = mean_at(i - 2 * win);
    const Vec2 e = 0.75 * m0 - 0.5 * (m_1 + m1) + 0.125 * (m_2 + m2);
    const Vec2 along = m1 - m_1;
    const double len = along.norm();
    dev.push_back(len > 0 ? std::abs(cross(along, e)) / len : e.norm());
  }
}
double sigma_of(std::vector<double>& dev) {
  if (dev.empty()) return 0;
  std::nth_element(dev.begin(), dev.begin() + dev.size() / 2, dev.end());
  return 1.4826 * dev[dev.size() / 2] / std::sqrt(1.094);
}

}  // namespace smooth

double estimate_noise(const std::vector<Loop>& loops, const SmoothOptions& o) {
  std::vector<double> dev;
  for (const Loop& l : loops)
    if (l.points.size() >= 8) smooth::append_window_noise(smooth::Unrolled(l.points), smooth::window_of(o), dev);
  return smooth::sigma_of(dev);
}

}  // namespace hg::path_planner
