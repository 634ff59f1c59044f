// Step 7b: coverage. Before a path is published, every point of each loop's edge must lie within the tool's
// reach of the grind path (pipeline.hpp): an offset that collapsed in a slot narrower than the tool, or a
// concave corner the round tool cannot enter, leaves edge unground, and the job must not end DONE as if it
// were. Distances in doubles (point to segment); segments bucketed in a uniform grid of cells one reach wide,
// so a sample only looks at the 3 x 3 cells around it.
#include "path_planner/pipeline.hpp"

#include <algorithm>
#include <cmath>

namespace hg::path_planner {

namespace {

double segment_distance(const Vec2& p, const Segment2& s) {
  const Vec2 ab = s.b - s.a;
  const double l2 = ab.squaredNorm();
  const double t = l2 > 0 ? std::clamp((p - s.a).dot(ab) / l2, 0.0, 1.0) : 0.0;
  return (s.a + t * ab - p).norm();
}

// Segments listed per cell (CSR) over a box; a query looks at its cell and the eight around it, which holds
// every segment within one cell width of the query point.
class SegmentGrid {
 public:
  SegmentGrid(const std::vector<Segment2>& segs, Vec2 lo, Vec2 hi, double cell) : segs_(segs) {
    cell_ = std::max({cell, (hi - lo).maxCoeff() / 2048, 1e-9});
    lo_ = lo;
    gx_ = int((hi.x() - lo.x()) / cell_) + 1, gy_ = int((hi.y() - lo.y()) / cell_) + 1;
    start_.assign(std::size_t(gx_) * gy_ + 1, 0);
    for (std::size_t i = 0; i < segs.size(); ++i) each_cell(segs[i], [&](std::size_t c) { ++start_[c + 1]; });
    for (std::size_t c = 1; c < start_.size(); ++c) start_[c] += start_[c - 1];
    std::vector<std::uint32_t> fill(start_.begin(), start_.end() - 1);
    index_.resize(start_.back());
    for (std::size_t i = 0; i < segs.size(); ++i)
      each_cell(segs[i], [&](std::size_t c) { index_[fill[c]++] = std::uint32_t(i); });
  }
  // Distance to the nearest segment, or infinity when none is within one cell width.
  double nearest(const Vec2& p) const {
    const int x = cx(p.x()), y = cy(p.y());
    double best = INFINITY;
    for (int yy = std::max(0, y - 1); yy <= std::min(gy_ - 1, y + 1); ++yy)
      for (int xx = std::max(0, x - 1); xx <= std::min(gx_ - 1, x + 1); ++xx) {
        const std::size_t c = std::size_t(yy) * gx_ + xx;
        for (std::uint32_t k = start_[c]; k < start_[c + 1]; ++k)
          best = std::min(best, segment_distance(p, segs_[index_[k]]));
      }
    return best;
  }

 private:
  int cx(double x) const { return std::clamp(int(std::floor((x - lo_.x()) / cell_)), 0, gx_ - 1); }
  int cy(double y) const { return std::clamp(int(std::floor((y - lo_.y()) / cell_)), 0, gy_ - 1); }
  template <class F>
  void each_cell(const Segment2& s, F&& fn) const {
    const Vec2 a = s.a.cwiseMin(s.b), b = s.a.cwiseMax(s.b);
    const Vec2 hi = lo_ + cell_ * Vec2(gx_, gy_);
    if ((b.array() < lo_.array()).any() || (a.array() > hi.array()).any()) return;  // outside the box
    for (int y = cy(a.y()); y <= cy(b.y()); ++y)
      for (int x = cx(a.x()); x <= cx(b.x()); ++x) fn(std::size_t(y) * gx_ + x);
  }
  const std::vector<Segment2>& segs_;
  Vec2 lo_;
  double cell_ = 1;
  int gx_ = 1, gy_ = 1;
  std::vector<std::uint32_t> start_, index_;
};

struct Sample {
  Vec2 p;
  double s;      // arc length from vertex 0
  double ahead;  // length to the next sample
};

std::vector<Sample> sample_edge(const Ring& edge, double spacing) {
  std::vector<Sample> out;
  double s = 0;
  for (std::size_t i = 0, n = edge.size(); i < n; ++i) {
    const Vec2 a = edge[i], b = edge[(i + 1) % n];
    const double len = (b - a).norm();
    const int m = std::max(1, int(std::ceil(len / spacing)));
    for (int k = 0; k < m; ++k) out.push_back({a + (b - a) * (double(k) / m), s + len * k / m, len / m});
    s += len;
  }
  return out;
}

// A concave corner (turn toward the material of 30 deg or more at one vertex) or a concave bend tighter
// than the reach (more concave turn within any `reach` of arc length than a circle of that radius makes),
// within one reach of the stretch [s0, s0 + length] along the ring (canonical: material on the left, so a
// concave turn is negative).
bool concave_near(const Ring& edge, double total, double s0, double length, double reach) {
  const std::size_t n = edge.size();
  struct Turn {
    double s, concave;
  };
  std::vector<Turn> turns;  // over three laps, so the window may run across vertex 0 either way
  double s = 0;
  std::vector<double> pos(n);
  for (std::size_t i = 0; i < n; ++i) pos[i] = s, s += (edge[(i + 1) % n] - edge[i]).norm();
  for (int lap = -1; lap <= 1; ++lap)
    for (std::size_t i = 0; i < n; ++i) {
      const Vec2 a = edge[i] - edge[(i + n - 1) % n], b = edge[(i + 1) % n] - edge[i];
      const double t = std::atan2(a.x() * b.y() - a.y() * b.x(), a.dot(b));
      if (t < 0) turns.push_back({pos[i] + lap * total, -t});
    }
  const double lo = s0 - reach, hi = std::min(s0 + length + reach, lo + total);
  const double corner = 30 * M_PI / 180, bend = 1.0;  // 1 rad per `reach` of arc: radius below the reach
  double window = 0;
  for (std::size_t a = 0, b = 0; a < turns.size(); ++a) {
    if (turns[a].s < lo || turns[a].s > hi) continue;
    if (turns[a].concave >= corner) return true;
    if (b < a) b = a, window = 0;
    while (b < turns.size() && turns[b].s <= std::min(hi, turns[a].s + reach)) window += turns[b++].concave;
    if (window >= bend) return true;
    window -= turns[a].concave;
  }
  return false;
}

}  // namespace

std::vector<Segment2> grind_segments(const std::vector<Waypoint>& path, const Eigen::Isometry3d& plate_to_base) {
  const Eigen::Isometry3d to_plate = plate_to_base.inverse();
  std::vector<Segment2> out;
  for (std::size_t i = 1; i < path.size(); ++i)
    if (path[i].kind == kGrind)
      out.push_back({(to_plate * path[i - 1].position).head<2>(), (to_plate * path[i].position).head<2>()});
  return out;
}

LoopCoverage edge_coverage(const Ring& edge, const std::vector<Segment2>& tool_path, double reach, double tolerance) {
  LoopCoverage c;
  if (edge.size() < 2) return c;
  const double spacing = tolerance / 2, limit = reach + tolerance - spacing / 2;
  const std::vector<Sample> samples = sample_edge(edge, spacing);
  c.length = samples.back().s + samples.back().ahead;
  Vec2 lo = edge[0], hi = edge[0];
  for (const Vec2& p : edge) lo = lo.cwiseMin(p), hi = hi.cwiseMax(p);
  const SegmentGrid grid(tool_path, lo - Vec2::Constant(limit), hi + Vec2::Constant(limit), limit);
  const std::size_t N = samples.size();
  std::vector<std::uint8_t> reached(N);
  std::vector<double> distance(N);
  std::size_t first_reached = N;
  for (std::size_t j = 0; j < N; ++j) {
    distance[j] = grid.nearest(samples[j].p);
    reached[j] = distance[j] <= limit;
    if (reached[j] && first_reached == N) first_reached = j;
  }
  // Stretches of unreached samples, from a reached one round the ring (or the whole ring).
  const std::size_t from = first_reached == N ? 0 : first_reached;
  for (std::size_t k = 0; k < N;) {
    const std::size_t j = (from + k) % N;
    if (reached[j]) {
      ++k;
      continue;
    }
    UnreachedStretch st;
    const std::size_t before = (j + N - 1) % N;
    st.start = first_reached == N ? 0 : std::fmod(samples[j].s - samples[before].ahead / 2 + c.length, c.length);
    while (k < N && !reached[(from + k) % N]) {
      const std::size_t i = (from + k) % N;
      st.length += (samples[i].ahead + samples[(i + N - 1) % N].ahead) / 2;
      st.points.push_back(samples[i].p);
      st.depth = std::max(st.depth, distance[i] - reach);
      ++k;
    }
    st.from = st.points.front(), st.to = st.points.back();
    st.concave = concave_near(edge, c.length, st.start, st.length, reach);
    c.unreached_length += st.length;
    c.unreached.push_back(std::move(st));
  }
  c.unreached_length = std::min(c.unreached_length, c.length);
  return c;
}

}  // namespace hg::path_planner
