// The insertion orders (outline_core/order.hpp) against properties that do not depend on how they are sorted:
// a Hilbert curve steps from a grid point to a neighbour; every order is a permutation; equal points stay
// together in input order (stable sort, one BRIO round for equal coordinates). Small and large clouds, so
// both digit splits of the radix sort are covered.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <map>
#include <random>
#include <utility>
#include <vector>

#include "clouds.hpp"
#include "outline_core/order.hpp"

using namespace hg::outline;
using namespace hg::outline::testing;

namespace {

template <class Order>
bool is_permutation_of_n(const Order& order, std::size_t n) {
  std::vector<char> seen(n, 0);
  for (std::uint32_t i : order) {
    if (i >= n || seen[i]) return false;
    seen[i] = 1;
  }
  return order.size() == n;
}

}  // namespace

// On a full square grid (about 4 cells of the curve's grid per point: one point per aligned 2 x 2 block),
// consecutive points of a Hilbert order are 4-neighbours.
TEST(OutlineOrder, HilbertOrderStepsFromGridPointToNeighbour) {
  for (int side : {64, 1024}) {
    SCOPED_TRACE(side);
    const auto pts = grid_cloud(side, side);
    const auto order = insertion_order(pts, Order::Hilbert);
    ASSERT_TRUE(is_permutation_of_n(order, pts.size()));
    for (std::size_t k = 1; k < order.size(); ++k) {
      const Vec2 a = pts[order[k - 1]], b = pts[order[k]];
      ASSERT_EQ(std::fabs(a.x - b.x) + std::fabs(a.y - b.y), 1.0) << "step " << k;
    }
  }
}

// Every point once; the copies of a point one after the other, in input order (a grid, so that no two
// distinct points share a cell of the curve's grid: there the stable sort would interleave their copies).
TEST(OutlineOrder, BrioKeepsEqualPointsTogetherInInputOrder) {
  for (int side : {64, 320}) {  // 12,288 and 307,200 points
    SCOPED_TRACE(side);
    const auto base = grid_cloud(side, side);
    std::vector<Vec2> pts;
    for (int copy = 0; copy < 3; ++copy) pts.insert(pts.end(), base.begin(), base.end());
    std::shuffle(pts.begin(), pts.end(), std::mt19937_64(5));
    const auto order = insertion_order(pts, Order::Brio);
    ASSERT_TRUE(is_permutation_of_n(order, pts.size()));
    std::map<std::pair<double, double>, std::vector<std::size_t>> at;  // point -> its positions in the order
    for (std::size_t k = 0; k < order.size(); ++k) at[{pts[order[k]].x, pts[order[k]].y}].push_back(k);
    for (const auto& [p, ks] : at) {
      ASSERT_EQ(ks.size(), 3u);
      for (std::size_t j = 1; j < ks.size(); ++j) {
        ASSERT_EQ(ks[j], ks[j - 1] + 1) << "copies apart";
        ASSERT_LT(order[ks[j - 1]], order[ks[j]]) << "copies out of input order";
      }
    }
  }
}
