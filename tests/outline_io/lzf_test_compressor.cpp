#include "lzf_test_compressor.hpp"

#include <cstdint>
#include <vector>

namespace hg_test {

// Stream: control byte c < 32 -> literal run of c + 1 bytes follows; otherwise a back reference of
// length (c >> 5) + 2 (when c >> 5 == 7 one more byte adds to the length), distance ((c & 31) << 8 | next) + 1.
std::string lzf_compress(std::string_view in) {
  std::string out;
  std::string literal;
  auto flush = [&] {
    for (std::size_t i = 0; i < literal.size(); i += 32) {
      std::size_t n = std::min<std::size_t>(32, literal.size() - i);
      out += static_cast<char>(n - 1);
      out.append(literal, i, n);
    }
    literal.clear();
  };
  std::vector<long> last(1 << 16, -1);
  const std::size_t n = in.size();
  std::size_t i = 0;
  while (i < n) {
    std::size_t best_len = 0, best_dist = 0;
    if (i + 3 <= n) {
      unsigned h = (static_cast<unsigned char>(in[i]) * 2654435761u ^ static_cast<unsigned char>(in[i + 1]) * 40503u ^
                    static_cast<unsigned char>(in[i + 2])) &
                   0xffff;
      long cand = last[h];
      last[h] = static_cast<long>(i);
      if (cand >= 0 && i - cand <= 8192) {
        std::size_t len = 0;
        while (i + len < n && len < 264 && in[cand + len] == in[i + len]) ++len;
        if (len >= 3) best_len = len, best_dist = i - cand;
      }
    }
    if (best_len == 0) {
      literal += in[i++];
      continue;
    }
    flush();
    std::size_t l = best_len - 2, d = best_dist - 1;
    if (l < 7) {
      out += static_cast<char>((l << 5) | (d >> 8));
    } else {
      out += static_cast<char>((7 << 5) | (d >> 8));
      out += static_cast<char>(l - 7);
    }
    out += static_cast<char>(d & 0xff);
    i += best_len;
  }
  flush();
  return out;
}

}  // namespace hg_test
