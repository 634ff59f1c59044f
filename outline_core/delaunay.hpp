// Bowyer-Watson Delaunay triangulation over flat arrays, with the paper's three point-location schemes
// (section 3.1): Ordinary (test every triangle), DS (directive walk from a fixed triangle), DSHI
// (directive walk from a triangle made by the previous insertion).
//
// Exactness: the triangulation is exactly Delaunay for the input coordinates as given: every orientation
// and incircle decision is exact on `xy`, and xy[v] + origin == input[ids[v]] exactly. The translation to a
// rounded centroid (kept for speed: float32 data then stays few-bit, see delaunay.cpp) is made only when
// every translated coordinate is exact; otherwise origin = 0 and xy are the input coordinates. Only points
// with equal coordinates (as numbers: 0.0 == -0.0) are merged; 1 ulp apart are two points.
// Limits (predicates.hpp): the cloud must span less than 1e60 and every coordinate be a multiple of
// 2^-170 (any double of magnitude >= 1e-35); otherwise OutlineError names the point.
// Points with a non-finite coordinate are skipped (counted in `skipped`): they get no vertex.
//
// Vertex ids are positions in the insertion order (xy is stored in that order, so points near in the
// order are near in memory: a shuffled cloud sorted along a Hilbert curve keeps its cache locality);
// ids[v] maps a vertex back to the input.
//
// The vertex at infinity: instead of a finite super triangle, every convex-hull edge (u, v) has a "ghost"
// triangle (v, u, ghost) whose third vertex is the symbolic vertex `ghost` (= number of vertices,
// so it is never a vertex id and has no coordinates). The finite triangles are then exactly the
// Delaunay triangulation of the points, hull included.
#pragma once

#include <cstddef>
#include <cstdint>
#include <functional>
#include <memory>
#include <new>
#include <span>
#include <utility>
#include <vector>

#include "order.hpp"  // insertion_order
#include "types.hpp"

namespace hg::outline {

struct DelaunayStats {
  std::uint64_t locate_visits = 0;  // triangles visited by point location (Ordinary: every live triangle)
  std::uint64_t cavity_visits = 0;  // triangles tested during the cavity search, excluding the located one
  std::uint64_t incircle_tests = 0;
  std::uint64_t orient_tests = 0;
  std::uint64_t cavity_triangles = 0;  // triangles deleted (sum of cavity sizes)
  std::uint64_t walk_fallbacks = 0;    // walks that hit the step cap and fell back to a scan (expected 0)
  std::uint64_t search_cost() const { return locate_visits + cavity_visits; }
};

// The large blocks of triangle slots, kept between outlines (kept_blocks.cpp): an outline of 1.59 M points
// takes 76 MB of them, and on fresh memory every outline faults them in again (23 k page faults, 13 % of its
// time). A process that computes one outline after another (the outline service, hg-bench) reuses them.
void* take_kept_block(std::size_t bytes);
void give_kept_block(void* p, std::size_t bytes) noexcept;

// An allocator whose vectors leave new elements uninitialised (resize would zero them): the triangle
// arrays are written slot by slot as the insertion uses them, and the kernel zeroes fresh pages anyway,
// so zeroing them first was one more pass over 24 bytes a point. Kept: the memory comes from and goes back
// to the kept blocks.
template <class E, bool Kept = false>
struct NoInitAllocator {
  using value_type = E;
  template <class U>
  struct rebind {
    using other = NoInitAllocator<U, Kept>;
  };
  NoInitAllocator() = default;
  template <class U>
  NoInitAllocator(const NoInitAllocator<U, Kept>&) noexcept {}
  E* allocate(std::size_t n) {
    if constexpr (Kept) return static_cast<E*>(take_kept_block(n * sizeof(E)));
    else
      return std::allocator<E>().allocate(n);
  }
  void deallocate(E* p, std::size_t n) noexcept {
    if constexpr (Kept) give_kept_block(p, n * sizeof(E));
    else
      std::allocator<E>().deallocate(p, n);
  }
  template <class U>
  void construct(U* p) noexcept {
    ::new (static_cast<void*>(p)) U;
  }
  template <class U, class... A>
  void construct(U* p, A&&... a) {
    ::new (static_cast<void*>(p)) U(std::forward<A>(a)...);
  }
  template <class U>
  bool operator==(const NoInitAllocator<U, Kept>&) const noexcept {
    return true;
  }
};
// Scratch arrays written before they are read.
using SlotArray = std::vector<std::uint32_t, NoInitAllocator<std::uint32_t>>;
// Triangle slots: tri and twin (only the slots in use are ever read), on kept blocks.
using TriangleSlots = std::vector<std::uint32_t, NoInitAllocator<std::uint32_t, true>>;

struct Triangulation {
  Vec2 origin;                     // the translation: xy[v] = input[ids[v]] - origin, exactly (often 0)
  std::vector<Vec2> xy;            // translated coordinates, by vertex id (insertion order), finite points only
  Vec2 xy_min, xy_max;             // bounding box of xy
  std::vector<std::uint32_t> ids;  // vertex id -> index in the input as given
  std::uint32_t ghost = 0;         // the vertex at infinity (= xy.size())
  // Triangle t has vertices tri[3t], tri[3t+1], tri[3t+2], counter-clockwise for finite triangles.
  // Half-edge h = 3t+i runs from tri[h] to tri[next(h)]; twin[h] is the same edge in the neighbour.
  TriangleSlots tri;
  TriangleSlots twin;
  // vrep[v] = v for an inserted vertex; for a merged duplicate, the vertex it was merged into (whose
  // input index is the smallest of the equal points: the order is stable).
  std::vector<std::uint32_t> vrep;
  // Squared distance from each inserted vertex to its nearest other point (kept up to date during the
  // insertion from the new Delaunay edges; infinity for merged duplicates). Float: it only feeds the
  // median spacing, and halves the memory.
  std::vector<float> nn2;
  std::size_t inserted = 0;
  std::size_t duplicates = 0;
  std::size_t skipped = 0;  // input points with a non-finite coordinate (not triangulated, no vertex)
  DelaunayStats stats;

  static std::uint32_t next(std::uint32_t h) { return h % 3 == 2 ? h - 2 : h + 1; }
  static std::uint32_t prev(std::uint32_t h) { return h % 3 == 0 ? h + 2 : h - 1; }
  std::size_t slots() const { return tri.size() / 3; }
  bool is_ghost(std::size_t t) const {
    return tri[3 * t] == ghost || tri[3 * t + 1] == ghost || tri[3 * t + 2] == ghost;
  }
  std::size_t finite_count() const;
};

// Skips non-finite points, validates (>= 3 distinct finite points, not all collinear, the limits above;
// throws OutlineError naming the index) and triangulates.
Triangulation triangulate(std::span<const Vec2> points, Mode mode, Order order);
// Same, and empties `points` (returning its memory) as soon as the triangulation holds its translated
// copy, from which every finite point is recovered exactly (points[ids[v]] == xy[v] + origin).
// Saves one copy of the cloud at the peak (25 MB for 1.59 M points).
Triangulation triangulate_releasing(std::vector<Vec2>& points, Mode mode, Order order);
// The triangulation of the points points[subset[k]] (finite, distinct indices; ids then index `points`)
// into T. `translated`, when given, runs once T holds the translated copy: `points` is not read after it,
// so the caller may release it there. If a later step throws, T keeps xy and ids (every point of the
// subset is still there: points[ids[v]] == xy[v] + origin). For the strips of the threaded outline.
void triangulate_subset(Triangulation& T, std::span<const Vec2> points, std::vector<std::uint32_t> subset, Mode mode,
                        Order order, const std::function<void()>& translated);
// Same with an explicit insertion order (a permutation of 0..n-1, non-finite points dropped from it; for
// experiments and benchmarks).
Triangulation triangulate(std::span<const Vec2> points, Mode mode, Order order, std::vector<std::uint32_t> custom);

}  // namespace hg::outline
