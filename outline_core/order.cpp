// The insertion orders: Hilbert curve sort and BRIO rounds (order.hpp).
#include "order.hpp"

#include "delaunay.hpp"  // NoInitAllocator

#include <algorithm>
#include <bit>
#include <cstring>
#include <utility>

namespace hg::outline {
namespace {

// Hilbert index of (x, y) on a 2^bits x 2^bits grid (bits <= 16). The classic iteration (quadrant digit, then rotate /
// reflect the rest) as a 4-state table: the accumulated transform is (swap?, invert?), a group where the
// order does not matter. Table-driven, so no unpredictable branches (they dominated the sort's time).
struct HilbertTable {
  std::uint8_t digit[16], next[16];  // index: state * 4 + bx * 2 + by; state = swap * 2 + invert
  constexpr HilbertTable() : digit{}, next{} {
    for (unsigned st = 0; st < 4; ++st)
      for (unsigned bx = 0; bx < 2; ++bx)
        for (unsigned by = 0; by < 2; ++by) {
          const unsigned sw = st >> 1, inv = st & 1;
          unsigned rx = bx ^ inv, ry = by ^ inv;
          if (sw) std::swap(rx, ry);
          unsigned nsw = sw, ninv = inv;
          if (ry == 0) {
            if (rx == 1) ninv ^= 1;
            nsw ^= 1;
          }
          digit[st * 4 + bx * 2 + by] = static_cast<std::uint8_t>((3 * rx) ^ ry);
          next[st * 4 + bx * 2 + by] = static_cast<std::uint8_t>(nsw * 2 + ninv);
        }
  }
};
constexpr HilbertTable kHilbert;

// Two levels per step: 4 states x 16 (two bits of x, two of y) -> 4-bit digit and next state.
struct HilbertTable2 {
  std::uint8_t digit[64], next[64];  // index: state * 16 + (x bits) * 4 + (y bits)
  constexpr HilbertTable2() : digit{}, next{} {
    for (unsigned st = 0; st < 4; ++st)
      for (unsigned xb = 0; xb < 4; ++xb)
        for (unsigned yb = 0; yb < 4; ++yb) {
          const unsigned i1 = st * 4 + (xb >> 1) * 2 + (yb >> 1);
          const unsigned s1 = kHilbert.next[i1];
          const unsigned i2 = s1 * 4 + (xb & 1) * 2 + (yb & 1);
          digit[st * 16 + xb * 4 + yb] = static_cast<std::uint8_t>((kHilbert.digit[i1] << 2) | kHilbert.digit[i2]);
          next[st * 16 + xb * 4 + yb] = kHilbert.next[i2];
        }
  }
};
constexpr HilbertTable2 kHilbert2;

std::uint32_t hilbert_index(std::uint32_t x, std::uint32_t y, int bits) {
  std::uint32_t d = 0, st = 0;
  int bit = bits;
  if (bit & 1) {  // odd count: one single level first
    --bit;
    const std::uint32_t i = st * 4 + ((x >> bit) & 1) * 2 + ((y >> bit) & 1);
    d = kHilbert.digit[i];
    st = kHilbert.next[i];
  }
  while (bit > 0) {
    bit -= 2;
    const std::uint32_t i = st * 16 + ((x >> bit) & 3) * 4 + ((y >> bit) & 3);
    d = (d << 4) | kHilbert2.digit[i];
    st = kHilbert2.next[i];
  }
  return d;
}

// The insertion order as positions 0..n-1 of the points at(k) (translated on the fly, fl(p - origin):
// only an ordering, so rounding is harmless; equal points get equal keys). `box` bounds the at(k): since
// rounding is monotone, the box of the translated points is the input box translated, no extra pass.
// BRIO rounds, growing 16-fold: the last round holds 15/16 of the points, the one before 15/16 of the
// rest, ... (factor 16 rather than the classic 2: the big last round keeps the Hilbert locality, and the
// sparse earlier rounds already make later points land inside the mesh; measured on a 1.59 M camera
// grid: 4.4 cavity triangles per point instead of 6.8 for plain Hilbert, 25 % less time; factor 2: 4.0
// triangles but no faster).
int brio_rounds(std::size_t n) {
  int rounds = 0;
  while (rounds < 7 && (n >> (4 * rounds)) > 256) ++rounds;
  return rounds;
}

// A point's round is a hash of its coordinates (not of its index), so equal points share a round and
// keep their input order.
std::uint8_t brio_round(Vec2 p, int rounds) {
  const double x = p.x + 0.0, y = p.y + 0.0;  // -0.0 becomes +0.0: equal values, equal bits
  std::uint64_t bx, by;
  std::memcpy(&bx, &x, 8);
  std::memcpy(&by, &y, 8);
  std::uint64_t h = bx * 0x9e3779b97f4a7c15ull ^ (by + 0x632be59bd9b4e019ull + (bx << 6) + (bx >> 2));
  h ^= h >> 31;
  h *= 0xbf58476d1ce4e5b9ull;
  h ^= h >> 27;
  h *= 0x94d049bb133111ebull;
  h ^= h >> 31;
  const int level = (h == 0 ? 64 : __builtin_ctzll(h)) / 4;  // P(level >= k) = 16^-k
  return static_cast<std::uint8_t>(rounds - std::min(rounds, level));
}

// Stable LSD radix sort of items (key << 32 | position) by the key's low key_bits bits. Passes of at most
// kDigitBits bits: each pass scatters into 2^digit buckets, one write stream each, and 512 streams of 64-byte
// lines (32 KB) stay in the level-1 cache, where the 2 x 4096 streams of two 12-bit passes over separate key and
// index arrays missed it (the scatter made 44 % of the outline's level-1 misses). The digits' counts are
// taken in one read pass.
constexpr int kDigitBits = 9;
using Items = std::vector<std::uint64_t, NoInitAllocator<std::uint64_t>>;  // each written before it is read

void radix_sort(Items& item, int key_bits) {
  const std::size_t n = item.size();
  const int passes = std::max(1, (key_bits + kDigitBits - 1) / kDigitBits);
  const int digit = (key_bits + passes - 1) / passes;
  const std::size_t buckets = std::size_t{1} << digit, mask = buckets - 1;
  std::vector<std::uint32_t> count(static_cast<std::size_t>(passes) * buckets, 0);
  for (const std::uint64_t it : item)
    for (int p = 0; p < passes; ++p) ++count[static_cast<std::size_t>(p) * buckets + ((it >> (32 + p * digit)) & mask)];
  Items to(n);
  for (int p = 0; p < passes; ++p) {
    std::uint32_t* start = count.data() + static_cast<std::size_t>(p) * buckets;
    std::uint32_t sum = 0;
    for (std::size_t b = 0; b < buckets; ++b) sum += std::exchange(start[b], sum);
    const int shift = 32 + p * digit;
    for (const std::uint64_t it : item) to[start[(it >> shift) & mask]++] = it;
    item.swap(to);
  }
}

template <class At>
std::vector<std::uint32_t> order_positions(std::size_t n, At at, const Box& box, Order order) {
  std::vector<std::uint32_t> idx(n);
  if (order == Order::AsIs || n < 3) {
    for (std::size_t i = 0; i < n; ++i) idx[i] = static_cast<std::uint32_t>(i);
    return idx;
  }
  const double minx = box.minx, maxx = box.maxx, miny = box.miny, maxy = box.maxy;
  // Grid of about 4 cells per point (at most 2^16 per side): finer gains nothing.
  int bits = 1;
  while (bits < 16 && (std::size_t{1} << (2 * bits)) < 4 * n) ++bits;
  const double extent = std::max(maxx - minx, maxy - miny);
  const double cells = static_cast<double>((1u << bits) - 1);
  const double scale = extent > 0 ? cells / extent : 0.0;
  // The sort key: BRIO's round above the Hilbert index (a stable sort by round within which the Hilbert
  // order is kept), hashed in the same pass as the Hilbert index, so the points are read once, in input order.
  const bool brio = order == Order::Brio;
  const int rounds = brio ? brio_rounds(n) : 0;
  const int key_bits = 2 * bits + std::bit_width(static_cast<unsigned>(rounds));
  Items item(n);
  for (std::size_t i = 0; i < n; ++i) {
    const Vec2 p = at(i);
    const auto gx = static_cast<std::uint32_t>(std::min(cells, (p.x - minx) * scale));
    const auto gy = static_cast<std::uint32_t>(std::min(cells, (p.y - miny) * scale));
    std::uint64_t key = hilbert_index(gx, gy, bits);
    if (brio) key |= std::uint64_t{brio_round(p, rounds)} << (2 * bits);
    item[i] = key << 32 | i;
  }
  radix_sort(item, key_bits);  // stable: equal points keep their input order
  for (std::size_t k = 0; k < n; ++k) idx[k] = static_cast<std::uint32_t>(item[k]);
  return idx;
}

}  // namespace

Box bounding_box(std::span<const Vec2> points) {
  Box b{points[0].x, points[0].x, points[0].y, points[0].y};
  for (const Vec2& p : points)
    b.minx = std::min(b.minx, p.x), b.maxx = std::max(b.maxx, p.x), b.miny = std::min(b.miny, p.y),
    b.maxy = std::max(b.maxy, p.y);
  return b;
}

std::vector<std::uint32_t> insertion_order(std::span<const Vec2> xy, Order order) {
  if (xy.empty()) return {};
  return order_positions(
      xy.size(), [&](std::size_t k) { return xy[k]; }, bounding_box(xy), order);
}

std::vector<std::uint32_t> order_translated(std::span<const Vec2> points, std::span<const std::uint32_t> finite,
                                            Vec2 origin, const Box& box, Order order) {
  if (finite.empty())
    return order_positions(
        points.size(),
        [&](std::size_t k) {
          return Vec2{points[k].x - origin.x, points[k].y - origin.y};
        },
        box, order);
  std::vector<std::uint32_t> ids = order_positions(
      finite.size(),
      [&](std::size_t k) {
        const Vec2& p = points[finite[k]];
        return Vec2{p.x - origin.x, p.y - origin.y};
      },
      box, order);
  for (std::uint32_t& i : ids) i = finite[i];
  return ids;
}

}  // namespace hg::outline
