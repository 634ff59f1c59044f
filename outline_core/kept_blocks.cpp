// The triangle slots' large blocks, kept between outlines (delaunay.hpp says why). A block is reused for a
// request of at most its size and at least four fifths of it, so a small cloud never holds a large block;
// at most kKept blocks are kept (one thread's tri and twin, and two strips' of a cloud), the oldest go first.
#include "delaunay.hpp"

#include <algorithm>
#include <mutex>
#include <new>
#include <vector>

namespace hg::outline {
namespace {

constexpr std::size_t kSmall = std::size_t{1} << 20;  // below 1 MB (clouds under ~40 k points): plain memory
constexpr std::size_t kKept = 6;

struct Block {
  void* p;
  std::size_t capacity;
};

struct Blocks {
  std::mutex mu;
  std::vector<Block> kept;  // free, oldest first
  std::vector<Block> out;   // handed out: their capacity
};

Blocks& blocks() {
  static Blocks* b = new Blocks;  // never destroyed: vectors may free their slots during static destruction
  return *b;
}

}  // namespace

void* take_kept_block(std::size_t bytes) {
  if (bytes < kSmall) return ::operator new(bytes);
  Blocks& b = blocks();
  std::lock_guard<std::mutex> lock(b.mu);
  auto fits = [&](const Block& k) { return k.capacity >= bytes && k.capacity - k.capacity / 5 <= bytes; };
  auto best = b.kept.end();
  for (auto it = b.kept.begin(); it != b.kept.end(); ++it)
    if (fits(*it) && (best == b.kept.end() || it->capacity < best->capacity)) best = it;
  Block given = best != b.kept.end() ? *best : Block{::operator new(bytes), bytes};
  if (best != b.kept.end()) b.kept.erase(best);
  b.out.push_back(given);
  return given.p;
}

void give_kept_block(void* p, std::size_t bytes) noexcept {
  if (bytes < kSmall) return ::operator delete(p);
  Blocks& b = blocks();
  std::lock_guard<std::mutex> lock(b.mu);
  auto it = std::find_if(b.out.begin(), b.out.end(), [&](const Block& k) { return k.p == p; });
  if (it == b.out.end()) return ::operator delete(p);  // not one of ours: cannot happen, never a crash
  b.kept.push_back(*it);
  b.out.erase(it);
  if (b.kept.size() > kKept) {
    ::operator delete(b.kept.front().p);
    b.kept.erase(b.kept.begin());
  }
}

}  // namespace hg::outline
