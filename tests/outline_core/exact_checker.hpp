// Independent exact checks with GMP rationals (every double is a dyadic rational, converted exactly).
#pragma once

#include <gmpxx.h>

#include <algorithm>
#include <cmath>
#include <map>
#include <set>
#include <span>
#include <string>
#include <vector>

#include "outline_core/delaunay.hpp"

namespace hg::outline::testing {

struct Q2 {
  mpq_class x, y;
};

inline Q2 exact(const Vec2& p) {
  Q2 q;
  q.x = p.x;  // mpq_class from double is exact
  q.y = p.y;
  return q;
}

inline int sgn(const mpq_class& v) { return ::sgn(v); }

inline mpq_class orient_q(const Q2& a, const Q2& b, const Q2& c) {
  return (a.x - c.x) * (b.y - c.y) - (a.y - c.y) * (b.x - c.x);
}

inline mpq_class incircle_q(const Q2& a, const Q2& b, const Q2& c, const Q2& d) {
  const mpq_class adx = a.x - d.x, ady = a.y - d.y, bdx = b.x - d.x, bdy = b.y - d.y, cdx = c.x - d.x, cdy = c.y - d.y;
  return (adx * adx + ady * ady) * (bdx * cdy - cdx * bdy) + (bdx * bdx + bdy * bdy) * (cdx * ady - adx * cdy) +
         (cdx * cdx + cdy * cdy) * (adx * bdy - bdx * ady);
}

// Circumradius squared, exactly.
inline mpq_class circumradius2_q(const Q2& a, const Q2& b, const Q2& c) {
  auto d2 = [](const Q2& u, const Q2& v) -> mpq_class { return (u.x - v.x) * (u.x - v.x) + (u.y - v.y) * (u.y - v.y); };
  const mpq_class D = orient_q(a, b, c);
  return d2(a, b) * d2(b, c) * d2(c, a) / (4 * D * D);
}

// Twice the area of the convex hull (Andrew's monotone chain with exact orientation).
inline mpq_class hull_area2_q(std::vector<Q2> p) {
  std::sort(p.begin(), p.end(), [](const Q2& a, const Q2& b) { return a.x < b.x || (a.x == b.x && a.y < b.y); });
  std::vector<Q2> h(2 * p.size());
  std::size_t k = 0;
  for (std::size_t i = 0; i < p.size(); ++i) {
    while (k >= 2 && sgn(orient_q(h[k - 2], h[k - 1], p[i])) <= 0) --k;
    h[k++] = p[i];
  }
  for (std::size_t i = p.size() - 1, t = k + 1; i-- > 0;) {
    while (k >= t && sgn(orient_q(h[k - 2], h[k - 1], p[i])) <= 0) --k;
    h[k++] = p[i];
  }
  h.resize(k - 1);
  mpq_class a2 = 0;
  for (std::size_t i = 0; i < h.size(); ++i) {
    const Q2 &u = h[i], &v = h[(i + 1) % h.size()];
    a2 += u.x * v.y - v.x * u.y;
  }
  return a2;
}

// Checks that T is exactly the Delaunay triangulation of the input points as given (the finite ones;
// non-finite points must be skipped). Returns "" when it is, else what is wrong. Independent of the
// triangulator: only T's arrays and the input are read, every geometric test in GMP rationals on the
// input coordinates, and T's coordinates must be the input exactly (xy + origin == input, rationally).
inline std::string check_delaunay(std::span<const Vec2> input, const Triangulation& T) {
  std::vector<char> finite_input(input.size());
  std::size_t n = 0;
  for (std::size_t i = 0; i < input.size(); ++i)
    n += finite_input[i] = std::isfinite(input[i].x) && std::isfinite(input[i].y);
  if (T.xy.size() != n || T.ids.size() != n || T.vrep.size() != n)
    return "array sizes (not one vertex per finite input point)";
  if (T.ghost != n) return "ghost id is not n";
  // Same coordinates: xy[v] + origin is input[ids[v]] exactly, ids one-to-one onto the finite points.
  const Q2 origin = exact(T.origin);
  std::vector<std::uint32_t> vertex_of(input.size(), 0xffffffffu);
  std::vector<Q2> q(n);
  for (std::size_t v = 0; v < n; ++v) {
    const std::uint32_t i = T.ids[v];
    if (i >= input.size() || !finite_input[i] || vertex_of[i] != 0xffffffffu)
      return "ids is not a one-to-one map onto the finite input points";
    vertex_of[i] = static_cast<std::uint32_t>(v);
    q[v] = exact(input[i]);
    const Q2 t = exact(T.xy[v]);
    if (t.x + origin.x != q[v].x || t.y + origin.y != q[v].y)
      return "xy + origin is not exactly input point " + std::to_string(i);
  }
  // Distinct points (equal as numbers: -0.0 == 0.0) and the expected first occurrence of each.
  std::map<std::pair<double, double>, std::uint32_t> first;
  for (std::size_t i = 0; i < input.size(); ++i)
    if (finite_input[i])
      first.emplace(std::make_pair(input[i].x + 0.0, input[i].y + 0.0), static_cast<std::uint32_t>(i));
  if (T.inserted != first.size())
    return "inserted " + std::to_string(T.inserted) + " != distinct " + std::to_string(first.size());
  if (T.duplicates != n - first.size()) return "duplicate count";
  for (std::size_t v = 0; v < n; ++v) {
    const Vec2 p = input[T.ids[v]];
    const std::uint32_t f = first.at({p.x + 0.0, p.y + 0.0});
    const bool is_first = T.ids[v] == f;
    if (is_first != (T.vrep[v] == v)) return "vertex " + std::to_string(v) + ": merged/kept wrongly";
    if (!is_first && T.ids[T.vrep[v]] != f) return "duplicate not mapped to its first occurrence";
  }

  const std::size_t slots = T.slots();
  if (T.twin.size() != T.tri.size() || T.tri.size() % 3) return "tri/twin sizes";
  std::vector<char> used(n, 0);
  std::size_t finite = 0, ghosts = 0, edges2 = 0;
  mpq_class area2 = 0;
  std::set<std::pair<std::uint32_t, std::uint32_t>> directed;
  for (std::size_t t = 0; t < slots; ++t) {
    const std::uint32_t* v = &T.tri[3 * t];
    int g = 0;
    for (int i = 0; i < 3; ++i) {
      if (v[i] > n) return "vertex id out of range";
      if (v[i] == n) ++g;
      else if (T.vrep[v[i]] != v[i])
        return "merged duplicate used in a triangle";
      if (!directed.insert({v[i], v[(i + 1) % 3]}).second)
        return "a directed edge occurs twice (edge shared by >2 triangles or flipped)";
    }
    if (v[0] == v[1] || v[1] == v[2] || v[0] == v[2]) return "repeated vertex in a triangle";
    for (int i = 0; i < 3; ++i) {
      const std::uint32_t h = static_cast<std::uint32_t>(3 * t + i), o = T.twin[h];
      if (o >= T.tri.size() || T.twin[o] != h || o / 3 == t) return "twin links broken";
      if (T.tri[o] != v[(i + 1) % 3] || T.tri[Triangulation::next(o)] != v[i]) return "twin is not the reversed edge";
    }
    if (g > 1) return "triangle with two ghost vertices";
    if (g == 1) {
      ++ghosts;
      continue;
    }
    ++finite;
    const mpq_class o = orient_q(q[v[0]], q[v[1]], q[v[2]]);
    if (sgn(o) <= 0) return "triangle " + std::to_string(t) + " not strictly counter-clockwise";
    area2 += o;
    for (int i = 0; i < 3; ++i) used[v[i]] = 1;
    for (int i = 0; i < 3; ++i) {
      const std::uint32_t o2 = T.twin[3 * t + i];
      const std::uint32_t t2 = o2 / 3;
      if (T.is_ghost(t2)) {
        edges2 += 2;
        continue;
      }  // hull edge counted once, by its finite side
      edges2 += 1;
      const std::uint32_t d = T.tri[Triangulation::prev(o2)];  // the neighbour's vertex opposite the edge
      if (sgn(incircle_q(q[v[0]], q[v[1]], q[v[2]], q[d])) > 0)
        return "edge not locally Delaunay in triangle " + std::to_string(t);
    }
  }
  for (std::size_t v = 0; v < n; ++v)
    if ((T.vrep[v] == v) != (used[v] != 0)) return "vertex " + std::to_string(v) + " used/unused wrongly";
  // Euler characteristic of a disk: V - E + F = 1; hull: as many ghost triangles as hull edges.
  const long V = static_cast<long>(first.size()), E = static_cast<long>(edges2 / 2), F = static_cast<long>(finite);
  if (V - E + F != 1) return "Euler characteristic " + std::to_string(V - E + F);
  if (F != 2 * V - 2 - static_cast<long>(ghosts)) return "triangle count != 2V - 2 - hull edges";
  // Coverage. Twin links make interior edges cancel, so the number of (counter-clockwise) triangles
  // covering a point is the winding number of the boundary cycle around it. The boundary (the edges
  // facing ghost triangles) must be one cycle through distinct vertices turning only left or straight,
  // once around (total turning 2 pi): a convex polygon, winding number 1 inside. Its area must then
  // equal the independently computed convex hull's: every hull point covered exactly once.
  std::map<std::uint32_t, std::uint32_t> hull_next;
  for (std::size_t t = 0; t < slots; ++t) {
    if (!T.is_ghost(t)) continue;
    const std::uint32_t* v = &T.tri[3 * t];
    int gi = 0;
    while (v[gi] != n) ++gi;
    const std::uint32_t x = v[(gi + 1) % 3], y = v[(gi + 2) % 3];  // ghost's edge x -> y; inside has y -> x
    if (!hull_next.emplace(y, x).second) return "hull vertex with two outgoing hull edges";
  }
  if (hull_next.size() != ghosts || ghosts < 3) return "hull edge count";
  {
    const std::uint32_t start = hull_next.begin()->first;
    std::uint32_t u = start, steps = 0;
    double turning = 0;
    do {
      const std::uint32_t v = hull_next.at(u), w = hull_next.at(v);
      if (sgn(orient_q(q[u], q[v], q[w])) < 0) return "boundary turns right: not convex";
      const Vec2 &pu = input[T.ids[u]], &pv = input[T.ids[v]], &pw = input[T.ids[w]];
      const double ax = pv.x - pu.x, ay = pv.y - pu.y, bx = pw.x - pv.x, by = pw.y - pv.y;
      turning += std::atan2(ax * by - ay * bx, ax * bx + ay * by);
      u = v;
      if (++steps > ghosts) return "boundary is not a cycle";
    } while (u != start);
    if (steps != ghosts) return "boundary is more than one cycle";
    if (std::fabs(turning - 2 * M_PI) > 1.0) return "boundary winds more than once";
  }
  std::vector<Q2> distinct;
  for (std::size_t v = 0; v < n; ++v)
    if (T.vrep[v] == v) distinct.push_back(q[v]);
  if (area2 != hull_area2_q(distinct))
    return "triangles do not cover the convex hull exactly once (area sum != hull area)";
  return "";
}

}  // namespace hg::outline::testing
