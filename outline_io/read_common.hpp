// Internal helpers shared by the readers: messages with file + line/byte, number parsing, line cursor,
// checked arithmetic and little-endian scalar loads.
#pragma once

#include <bit>
#include <charconv>
#include <cmath>
#include <cstdint>
#include <cstring>
#include <string>
#include <string_view>
#include <vector>

#include "outline_io/cloud.hpp"

namespace hg::outline_io::detail {

static_assert(std::endian::native == std::endian::little, "binary readers assume a little-endian host");

[[noreturn]] inline void fail_line(const std::string& name, std::size_t line, const std::string& what) {
  throw ReadError(name + ": line " + std::to_string(line) + ": " + what);
}
[[noreturn]] inline void fail_byte(const std::string& name, std::size_t byte, const std::string& what) {
  throw ReadError(name + ": byte " + std::to_string(byte) + ": " + what);
}
[[noreturn]] inline void fail_file(const std::string& name, const std::string& what) {
  throw ReadError(name + ": " + what);
}

// A token quoted for a message: control bytes escaped, long tokens cut, so garbage cannot mess up a terminal.
inline std::string quote(std::string_view s) {
  std::string out = "'";
  std::size_t n = 0;
  for (unsigned char c : s) {
    if (++n > 40) {
      out += "...";
      break;
    }
    if (c >= 0x20 && c < 0x7f) {
      out += static_cast<char>(c);
    } else {
      static const char* hex = "0123456789abcdef";
      out += "\\x";
      out += hex[c >> 4];
      out += hex[c & 15];
    }
  }
  return out + "'";
}

enum class Num { Ok, Bad, NonFinite, Range };

// Whole token must be a decimal floating-point number (an optional leading '+' is accepted).
inline Num parse_number(std::string_view tok, double& out) {
  if (tok.size() > 1 && tok[0] == '+' && (tok[1] == '.' || (tok[1] >= '0' && tok[1] <= '9'))) tok.remove_prefix(1);
  if (tok.empty()) return Num::Bad;
  const char* end = tok.data() + tok.size();
  auto [p, ec] = std::from_chars(tok.data(), end, out);
  if (ec == std::errc::result_out_of_range && p == end) return Num::Range;
  if (ec != std::errc() || p != end) return Num::Bad;
  if (!std::isfinite(out)) return Num::NonFinite;
  return Num::Ok;
}

inline bool parse_u64(std::string_view tok, std::uint64_t& out) {
  if (tok.empty()) return false;
  auto [p, ec] = std::from_chars(tok.data(), tok.data() + tok.size(), out);
  return ec == std::errc() && p == tok.data() + tok.size();
}
inline bool parse_i64(std::string_view tok, std::int64_t& out) {
  if (tok.empty()) return false;
  auto [p, ec] = std::from_chars(tok.data(), tok.data() + tok.size(), out);
  return ec == std::errc() && p == tok.data() + tok.size();
}

inline bool mul_ok(std::uint64_t a, std::uint64_t b, std::uint64_t& out) { return !__builtin_mul_overflow(a, b, &out); }
inline bool add_ok(std::uint64_t a, std::uint64_t b, std::uint64_t& out) { return !__builtin_add_overflow(a, b, &out); }

// Walks a buffer line by line; lines end with '\n', a trailing '\r' is dropped. line_no is 1-based.
struct LineCursor {
  std::string_view data;
  std::size_t pos = 0;
  std::size_t line_no = 0;

  bool next(std::string_view& line) {
    if (pos >= data.size()) return false;
    std::size_t nl = data.find('\n', pos);
    std::size_t end = nl == std::string_view::npos ? data.size() : nl;
    line = data.substr(pos, end - pos);
    if (!line.empty() && line.back() == '\r') line.remove_suffix(1);
    pos = nl == std::string_view::npos ? data.size() : nl + 1;
    ++line_no;
    return true;
  }
};

inline bool is_space(char c) { return c == ' ' || c == '\t' || c == '\r' || c == '\v' || c == '\f'; }

// Splits on blanks (space, tab, ...). Appends to `out` (cleared first).
inline void split_blanks(std::string_view line, std::vector<std::string_view>& out) {
  out.clear();
  std::size_t i = 0, n = line.size();
  while (i < n) {
    while (i < n && is_space(line[i])) ++i;
    if (i >= n) break;
    std::size_t s = i;
    while (i < n && !is_space(line[i])) ++i;
    out.push_back(line.substr(s, i - s));
  }
}

inline std::string_view trim(std::string_view s) {
  while (!s.empty() && is_space(s.front())) s.remove_prefix(1);
  while (!s.empty() && is_space(s.back())) s.remove_suffix(1);
  return s;
}

// Binary scalar types of PCD (I/U/F + size) and PLY (char..double), as one enum.
enum class Scalar : std::uint8_t { I8, U8, I16, U16, I32, U32, I64, U64, F32, F64 };

inline std::size_t scalar_size(Scalar s) {
  switch (s) {
    case Scalar::I8:
    case Scalar::U8: return 1;
    case Scalar::I16:
    case Scalar::U16: return 2;
    case Scalar::I32:
    case Scalar::U32:
    case Scalar::F32: return 4;
    default: return 8;
  }
}
inline bool scalar_is_float(Scalar s) { return s == Scalar::F32 || s == Scalar::F64; }

template <class T>
inline T load(const char* p) {
  T v;
  std::memcpy(&v, p, sizeof v);
  return v;
}

// Loads one little-endian scalar as double (the caller has checked the bytes are there).
inline double load_scalar(Scalar s, const char* p) {
  switch (s) {
    case Scalar::I8: return load<std::int8_t>(p);
    case Scalar::U8: return load<std::uint8_t>(p);
    case Scalar::I16: return load<std::int16_t>(p);
    case Scalar::U16: return load<std::uint16_t>(p);
    case Scalar::I32: return load<std::int32_t>(p);
    case Scalar::U32: return load<std::uint32_t>(p);
    case Scalar::I64: return static_cast<double>(load<std::int64_t>(p));
    case Scalar::U64: return static_cast<double>(load<std::uint64_t>(p));
    case Scalar::F32: return load<float>(p);
    case Scalar::F64: return load<double>(p);
  }
  return 0;
}

// Integer list counts (PLY); `ok` false when the value is negative.
inline std::uint64_t load_count(Scalar s, const char* p, bool& ok) {
  ok = true;
  switch (s) {
    case Scalar::I8: {
      auto v = load<std::int8_t>(p);
      ok = v >= 0;
      return ok ? v : 0;
    }
    case Scalar::U8: return load<std::uint8_t>(p);
    case Scalar::I16: {
      auto v = load<std::int16_t>(p);
      ok = v >= 0;
      return ok ? v : 0;
    }
    case Scalar::U16: return load<std::uint16_t>(p);
    case Scalar::I32: {
      auto v = load<std::int32_t>(p);
      ok = v >= 0;
      return ok ? v : 0;
    }
    case Scalar::U32: return load<std::uint32_t>(p);
    case Scalar::I64: {
      auto v = load<std::int64_t>(p);
      ok = v >= 0;
      return ok ? static_cast<std::uint64_t>(v) : 0;
    }
    case Scalar::U64: return load<std::uint64_t>(p);
    default: ok = false; return 0;
  }
}

// Counts the points with a non-finite coordinate (Cloud::nonfinite); every reader ends with it.
inline Cloud& count_nonfinite(Cloud& c) {
  c.nonfinite = 0;
  for (std::size_t i = 0; i < c.size(); ++i)
    c.nonfinite += !(std::isfinite(c.xyz[3 * i]) && std::isfinite(c.xyz[3 * i + 1]) && std::isfinite(c.xyz[3 * i + 2]));
  return c;
}

inline const char* axis_name(int k) { return k == 0 ? "x" : k == 1 ? "y" : "z"; }

}  // namespace hg::outline_io::detail
