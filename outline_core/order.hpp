// The insertion order of the triangulation (Order, types.hpp): as given, along a Hilbert curve, or in
// BRIO rounds (biased randomized insertion order, each round along the Hilbert curve). Separate from the
// insertion itself (delaunay.cpp): it only permutes the points.
#pragma once

#include <cstdint>
#include <span>
#include <vector>

#include "types.hpp"

namespace hg::outline {

struct Box {
  double minx, maxx, miny, maxy;
};
Box bounding_box(std::span<const Vec2> points);  // points not empty

// The insertion order: a permutation of 0..n-1 (AsIs: identity; Hilbert: sorted along a Hilbert curve
// over the bounding box, stable, so equal points keep their input order; Brio: rounds growing 16-fold by
// a hash of the coordinates, each in Hilbert order).
std::vector<std::uint32_t> insertion_order(std::span<const Vec2> xy, Order order);

// The same order for the points points[finite[k]] - origin (finite empty: all points), computed on the
// fly as fl(p - origin) (only an ordering, so rounding is harmless; equal points get equal keys), as
// indices into `points`. `box` bounds the translated points (the input box translated: rounding is
// monotone).
std::vector<std::uint32_t> order_translated(std::span<const Vec2> points, std::span<const std::uint32_t> finite,
                                            Vec2 origin, const Box& box, Order order);

}  // namespace hg::outline
