// Alpha shape classification and loop extraction; see alpha.hpp.
#include "alpha.hpp"

#include <algorithm>
#include <cmath>
#include <limits>

#include "predicates.hpp"

namespace hg::outline {

double median_nn_spacing(const Triangulation& T) {
  std::vector<float> used;
  used.reserve(T.inserted);
  for (std::size_t v = 0; v < T.nn2.size(); ++v)
    if (T.vrep[v] == v && std::isfinite(T.nn2[v])) used.push_back(T.nn2[v]);
  if (used.empty()) return 0;
  auto mid = used.begin() + static_cast<std::ptrdiff_t>(used.size() / 2);
  std::nth_element(used.begin(), mid, used.end());
  return std::sqrt(static_cast<double>(*mid));
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

  std::vector<Loop> loops;
  auto emit = [&](const std::uint32_t* v, std::size_t m) {
    Loop L;
    std::size_t start = 0;
    for (std::size_t k = 1; k < m; ++k)
      if (T.ids[v[k]] < T.ids[v[start]]) start = k;
    // Area and length in input coordinates relative to the loop's first point: exact for integer-valued
    // inputs, and no cancellation against a far origin.
    const Vec2 o = input[T.ids[v[start]]];
    double twice_area = 0;
    for (std::size_t k = 0; k < m; ++k) {
      const std::uint32_t i = T.ids[v[(start + k) % m]], j = T.ids[v[(start + k + 1) % m]];
      L.point_index.push_back(i);
      L.points.push_back(input[i]);
      const double xi = input[i].x - o.x, yi = input[i].y - o.y, xj = input[j].x - o.x, yj = input[j].y - o.y;
      twice_area += xi * yj - xj * yi;
      L.perimeter += std::hypot(xj - xi, yj - yi);
    }
    L.hole = twice_area < 0;
    L.area = std::fabs(twice_area) / 2;
    loops.push_back(std::move(L));
  };

  std::vector<std::uint8_t> used(hcount, 0);
  std::vector<std::int32_t> pos(T.xy.size(), -1);  // position of a vertex in the chain being traced
  std::vector<std::uint32_t> path;
  for (std::uint32_t h0 = 0; h0 < hcount; ++h0) {
    if (used[h0] || !is_free(h0)) continue;
    path.clear();
    std::uint32_t h = h0;
    do {
      used[h] = 1;
      const std::uint32_t v = T.tri[h];
      if (pos[v] >= 0) {  // the chain came back to v: what lies between is a closed loop on its own
        const std::size_t p = static_cast<std::size_t>(pos[v]);
        emit(path.data() + p, path.size() - p);
        for (std::size_t k = p; k < path.size(); ++k) pos[path[k]] = -1;
        path.resize(p);
      }
      pos[v] = static_cast<std::int32_t>(path.size());
      path.push_back(v);
      h = successor(h);
    } while (h != h0);
    emit(path.data(), path.size());
    for (std::uint32_t v : path) pos[v] = -1;
  }
  std::stable_sort(loops.begin(), loops.end(), [](const Loop& a, const Loop& b) {
    if (a.hole != b.hole) return !a.hole;
    if (a.area != b.area) return a.area > b.area;
    return a.point_index[0] < b.point_index[0];
  });
  return loops;
}

}  // namespace hg::outline
