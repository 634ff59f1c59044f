// reserve_huge: large arrays of the core on transparent huge pages.
#pragma once

#include <sys/mman.h>

#include <cstddef>
#include <cstdint>
#include <vector>

namespace hg::outline {

// Room for n elements in v, the large arrays on transparent huge pages where the kernel gives them on
// request (THP "madvise" mode, Debian's default): the insertion's scattered accesses to tri, twin and xy
// then miss the TLB far less, and the first touch takes one fault per 2 MB instead of per 4 kB. Before
// the first touch of the memory (reserve maps it, only the later assign/resize writes it); advice only.
template <class T>
void reserve_huge(std::vector<T>& v, std::size_t n) {
  v.reserve(n);
  const std::size_t bytes = n * sizeof(T);
  if (bytes < (std::size_t{4} << 20)) return;
  constexpr std::uintptr_t kPage = 4096;
  const auto p = reinterpret_cast<std::uintptr_t>(v.data());
  const std::uintptr_t begin = (p + kPage - 1) & ~(kPage - 1), end = (p + bytes) & ~(kPage - 1);
  if (end > begin) madvise(reinterpret_cast<void*>(begin), end - begin, MADV_HUGEPAGE);
}

}  // namespace hg::outline
