// The triangle slots' blocks are kept between outlines (outline_core/delaunay.hpp): a second triangulation of
// a large cloud in the same process reuses them instead of faulting fresh memory in, and gives the same
// triangulation. Measured with the kernel's own count of minor page faults (getrusage), not our bookkeeping.
#include <gtest/gtest.h>

#include <sys/resource.h>

#include <cstddef>

#include "clouds.hpp"
#include "outline_core/delaunay.hpp"

using namespace hg::outline;
using namespace hg::outline::testing;

namespace {

long minor_faults() {
  rusage u{};
  getrusage(RUSAGE_SELF, &u);
  return u.ru_minflt;
}

// Minor page faults taken while triangulating points, and the triangulation.
std::pair<long, Triangulation> faults_of_triangulation(const std::vector<Vec2>& points) {
  const long before = minor_faults();
  Triangulation T = triangulate(points, Mode::DSHI, Order::Brio);
  return {minor_faults() - before, std::move(T)};
}

}  // namespace

TEST(OutlineKeptBlocks, ASecondLargeTriangulationFaultsNoTriangleSlotsIn) {
  const auto points = random_cloud(300000, 11);
  std::size_t slot_pages = 0;
  long first = 0;
  std::vector<std::uint32_t> first_tri;
  {
    auto [faults, T] = faults_of_triangulation(points);
    first = faults;
    slot_pages = 2 * T.tri.capacity() * sizeof(std::uint32_t) / 4096;
    first_tri.assign(T.tri.begin(), T.tri.end());
  }  // T's blocks are kept here
  auto [second, T] = faults_of_triangulation(points);
  // tri and twin are 7 MB each here: on fresh 4 KB pages the first triangulation faults each page in.
  ASSERT_GT(first, long(slot_pages) * 9 / 10) << "the first triangulation's slots were not fresh memory";
  EXPECT_LT(second, first - long(slot_pages) * 9 / 10) << "the second triangulation faulted its slots in again";
  EXPECT_TRUE(std::equal(first_tri.begin(), first_tri.end(), T.tri.begin(), T.tri.end()));
}

TEST(OutlineKeptBlocks, ASmallerCloudDoesNotHoldALargeBlock) {
  const void* big_blocks[2];
  {
    Triangulation big = triangulate(random_cloud(300000, 12), Mode::DSHI, Order::Brio);
    big_blocks[0] = big.tri.data();
    big_blocks[1] = big.twin.data();
  }
  // 100 k points need a third of those blocks: a kept block serves a request of four fifths of it or more.
  Triangulation T = triangulate(random_cloud(100000, 13), Mode::DSHI, Order::Brio);
  for (const void* b : big_blocks) {
    EXPECT_NE(static_cast<const void*>(T.tri.data()), b);
    EXPECT_NE(static_cast<const void*>(T.twin.data()), b);
  }
  // The same size again takes them back.
  Triangulation again = triangulate(random_cloud(300000, 14), Mode::DSHI, Order::Brio);
  EXPECT_TRUE(again.tri.data() == big_blocks[0] || again.tri.data() == big_blocks[1]);
}
