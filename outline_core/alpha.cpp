// Alpha shape classification and loop extraction; see alpha.hpp.
#include "alpha.hpp"

#include <algorithm>
#include <cmath>
#include <cstring>
#include <limits>

#include "predicates.hpp"

namespace hg::outline {

double median_nn_spacing(const Triangulation& T) {
  // Selection by radix on the float bit patterns (for non-negative floats their order is that of the
  // unsigned integers): a histogram of the top 16 bits finds the bucket of the median, a second one of
  // the low 16 bits within that bucket finds it exactly. Two passes, no copy of the 1.5 M distances.
  const std::size_t n = T.nn2.size();
  auto key = [&](std::size_t v, std::uint32_t& k) {
    if (T.vrep[v] != v || !std::isfinite(T.nn2[v])) return false;
    std::memcpy(&k, &T.nn2[v], 4);
    k &= 0x7fffffffu;  // -0.0f (never produced) as +0.0f
    return true;
  };
  std::vector<std::uint32_t> hist(1u << 16, 0);
  std::size_t used = 0;
  for (std::size_t v = 0; v < n; ++v) {
    std::uint32_t k;
    if (key(v, k)) ++hist[k >> 16], ++used;
  }
  if (used == 0) return 0;
  std::size_t rank = used / 2;  // the element nth_element would put at used / 2
  std::uint32_t top = 0;
  while (rank >= hist[top]) rank -= hist[top++];
  std::fill(hist.begin(), hist.end(), 0);
  for (std::size_t v = 0; v < n; ++v) {
    std::uint32_t k;
    if (key(v, k) && (k >> 16) == top) ++hist[k & 0xffffu];
  }
  std::uint32_t low = 0;
  while (rank >= hist[low]) rank -= hist[low++];
  const std::uint32_t bits = (top << 16) | low;
  float f;
  std::memcpy(&f, &bits, 4);
  return std::sqrt(static_cast<double>(f));
}

std::vector<std::uint8_t> classify_alpha(const Triangulation& T, double R, bool outer_only) {
  const std::size_t slots = T.slots();
  std::vector<std::uint8_t> inside(slots, 0);
  // big = finite triangle with r > R (exact).
  for (std::size_t t = 0; t < slots; ++t) {
    if (T.is_ghost(t)) continue;
    const Vec2 &a = T.xy[T.tri[3 * t]], &b = T.xy[T.tri[3 * t + 1]], &c = T.xy[T.tri[3 * t + 2]];
    inside[t] = pred::circumradius_vs(a.x, a.y, b.x, b.y, c.x, c.y, R) <= 0 ? 1 : 2;  // 2 = big, for now
  }
  if (!outer_only) {
    for (auto& s : inside) s = s == 1;
    return inside;
  }
  // The paper's BFS: from every ghost triangle, through big triangles only; those reached are outside.
  std::vector<std::uint32_t> stack;
  for (std::size_t t = 0; t < slots; ++t)
    if (T.is_ghost(t)) stack.push_back(static_cast<std::uint32_t>(t));
  while (!stack.empty()) {
    const std::uint32_t t = stack.back();
    stack.pop_back();
    for (int i = 0; i < 3; ++i) {
      const std::uint32_t nb = T.twin[3 * t + i] / 3;
      if (inside[nb] == 2) {
        inside[nb] = 3;  // big and reached from outside
        stack.push_back(nb);
      }
    }
  }
  for (auto& s : inside) s = (s == 1 || s == 2);
  return inside;
}

std::vector<Loop> extract_loops(const Triangulation& T, const std::vector<std::uint8_t>& inside,
                                std::span<const Vec2> input) {
  const std::size_t hcount = T.tri.size();
  auto is_free = [&](std::uint32_t h) { return inside[h / 3] && !inside[T.twin[h] / 3]; };
  // The next free half-edge after h = a -> b: turn around b through the inside triangles of the same fan.
  auto successor = [&](std::uint32_t h) {
    std::uint32_t g = Triangulation::next(h);
    while (inside[T.twin[g] / 3]) g = Triangulation::next(T.twin[g]);
    return g;
  };

  // A vertex's input coordinates; with no input given, the translated point plus the origin (exact when
  // the caller released its points through triangulate_releasing).
  auto coord = [&](std::uint32_t v) {
    return input.empty() ? Vec2{T.xy[v].x + T.origin.x, T.xy[v].y + T.origin.y} : input[T.ids[v]];
  };
  std::vector<Loop> loops;
  auto emit = [&](const std::uint32_t* v, std::size_t m) {
    Loop L;
    std::size_t start = 0;
    for (std::size_t k = 1; k < m; ++k)
      if (T.ids[v[k]] < T.ids[v[start]]) start = k;
    // Area and length in input coordinates relative to the loop's first point: exact for integer-valued
    // inputs, and no cancellation against a far origin.
    const Vec2 o = coord(v[start]);
    double twice_area = 0;
    for (std::size_t k = 0; k < m; ++k) {
      const std::uint32_t vi = v[(start + k) % m], vj = v[(start + k + 1) % m];
      const Vec2 pi = coord(vi), pj = coord(vj);
      L.point_index.push_back(T.ids[vi]);
      L.points.push_back(pi);
      const double xi = pi.x - o.x, yi = pi.y - o.y, xj = pj.x - o.x, yj = pj.y - o.y;
      twice_area += xi * yj - xj * yi;
      L.perimeter += std::hypot(xj - xi, yj - yi);
    }
    L.hole = twice_area < 0;
    L.area = std::fabs(twice_area) / 2;
    loops.push_back(std::move(L));
  };

  // The free half-edges, in increasing order (one pass over the triangles); the tracing below then
  // works on this short list (its length is the outline's, not the cloud's): used marks per free edge,
  // found by binary search; the chain position of a boundary vertex likewise.
  std::vector<std::uint32_t> free_edges, bverts;
  for (std::uint32_t h = 0; h < hcount; ++h)
    if (is_free(h)) free_edges.push_back(h);
  bverts.reserve(free_edges.size());
  for (std::uint32_t h : free_edges) bverts.push_back(T.tri[h]);
  std::sort(bverts.begin(), bverts.end());
  bverts.erase(std::unique(bverts.begin(), bverts.end()), bverts.end());
  auto edge_slot = [&](std::uint32_t h) {
    return static_cast<std::size_t>(std::lower_bound(free_edges.begin(), free_edges.end(), h) - free_edges.begin());
  };
  auto vert_slot = [&](std::uint32_t v) {
    return static_cast<std::size_t>(std::lower_bound(bverts.begin(), bverts.end(), v) - bverts.begin());
  };
  std::vector<std::uint8_t> used(free_edges.size(), 0);
  std::vector<std::int32_t> pos(bverts.size(), -1);  // position of a vertex in the chain being traced
  std::vector<std::uint32_t> path;
  for (std::size_t e0 = 0; e0 < free_edges.size(); ++e0) {
    if (used[e0]) continue;
    const std::uint32_t h0 = free_edges[e0];
    path.clear();
    std::uint32_t h = h0;
    do {
      used[edge_slot(h)] = 1;
      const std::uint32_t v = T.tri[h];
      const std::size_t vs = vert_slot(v);
      if (pos[vs] >= 0) {  // the chain came back to v: what lies between is a closed loop on its own
        const std::size_t p = static_cast<std::size_t>(pos[vs]);
        emit(path.data() + p, path.size() - p);
        for (std::size_t k = p; k < path.size(); ++k) pos[vert_slot(path[k])] = -1;
        path.resize(p);
      }
      pos[vs] = static_cast<std::int32_t>(path.size());
      path.push_back(v);
      h = successor(h);
    } while (h != h0);
    emit(path.data(), path.size());
    for (std::uint32_t v : path) pos[vert_slot(v)] = -1;
  }
  std::stable_sort(loops.begin(), loops.end(), [](const Loop& a, const Loop& b) {
    if (a.hole != b.hole) return !a.hole;
    if (a.area != b.area) return a.area > b.area;
    return a.point_index[0] < b.point_index[0];
  });
  return loops;
}

}  // namespace hg::outline
