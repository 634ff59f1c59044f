#include "lcm_json.hpp"

#include <bit>
#include <algorithm>
#include <array>
#include <cmath>
#include <cstring>
#include <limits>
#include <map>
#include <set>
#include <type_traits>

#include <fmt/format.h>

namespace hg::foxglove {

using lcmtools::DecodeError;
using lcmtools::Dim;
using lcmtools::Kind;
using lcmtools::Member;

namespace {

bool is_integer(Kind k) { return k == Kind::Int8 || k == Kind::Int16 || k == Kind::Int32 || k == Kind::Int64; }

std::size_t fixed_size(Kind k) {
  switch (k) {
    case Kind::Int8:
    case Kind::Boolean:
    case Kind::Byte: return 1;
    case Kind::Int16: return 2;
    case Kind::Int32:
    case Kind::Float: return 4;
    case Kind::Int64:
    case Kind::Double: return 8;
    default: return 0;  // string, struct: variable
  }
}

// ---- schema ----

template <class T>
Json integer_schema() {
  return Json{
      {"type", "integer"}, {"minimum", std::numeric_limits<T>::min()}, {"maximum", std::numeric_limits<T>::max()}};
}

Json primitive_schema(Kind k) {
  switch (k) {
    case Kind::Int8: return integer_schema<int8_t>();
    case Kind::Int16: return integer_schema<int16_t>();
    case Kind::Int32: return integer_schema<int32_t>();
    case Kind::Int64: return integer_schema<int64_t>();
    case Kind::Byte: return integer_schema<uint8_t>();
    case Kind::Float:
    case Kind::Double: return Json{{"type", "number"}};  // NaN and Inf are written as null: JSON has neither
    case Kind::Boolean: return Json{{"type", "boolean"}};
    case Kind::String: return Json{{"type", "string"}};
    default: return Json::object();
  }
}

Json object_schema(const Schema& schema, const Struct& s);

// An array of any rank is one flat JSON array in row-major order (a byte array one base64 string), and a
// nested struct is its object schema written in place: Foxglove's and Lichtblick's JSON Schema readers take
// one "type" per field, no "$ref" and no array of arrays (Lichtblick packages/mcap-support/src/
// parseJsonSchema.ts), and a channel whose schema they cannot read shows nothing.
Json member_schema(const Schema& schema, const Member& m) {
  Json item = m.kind == Kind::Struct ? object_schema(schema, *schema.find(m.type_name)) : primitive_schema(m.kind);
  if (m.dims.empty()) return item;
  if (m.kind == Kind::Byte) return Json{{"type", "string"}, {"contentEncoding", "base64"}};
  Json a{{"type", "array"}, {"items", std::move(item)}};
  bool fixed = true;
  std::int64_t count = 1;
  std::string shape;
  for (const Dim& d : m.dims) {
    fixed = fixed && !d.variable;
    count *= d.variable ? 1 : d.fixed;
    shape += (shape.empty() ? "" : " x ") + (d.variable ? d.var : std::to_string(d.fixed));
  }
  if (fixed) a["minItems"] = a["maxItems"] = count;
  if (m.dims.size() > 1) a["description"] = shape + " values, row-major";
  return a;
}

Json object_schema(const Schema& schema, const Struct& s) {
  Json props = Json::object();
  Json required = Json::array();
  for (const Member& m : s.members) {
    props[m.name] = member_schema(schema, m);
    required.push_back(m.name);
  }
  return Json{{"type", "object"},
              {"title", s.full_name()},
              {"properties", std::move(props)},
              {"required", std::move(required)},
              {"additionalProperties", false}};
}

}  // namespace

Json json_schema(const Schema& schema, const Struct& s) {
  Json out{{"$schema", "http://json-schema.org/draft-07/schema#"}};
  Json body = object_schema(schema, s);
  for (auto& [k, v] : body.items()) out[k] = v;
  return out;
}

// ---- text helpers ----

void append_base64(const std::uint8_t* d, std::size_t n, std::string& out) {
  static const char* k = "ABCDEFGHIJKLMNOPQRSTUVWXYZabcdefghijklmnopqrstuvwxyz0123456789+/";
  std::size_t start = out.size();
  out.resize(start + (n + 2) / 3 * 4);
  char* p = out.data() + start;
  std::size_t i = 0;
  for (; i + 3 <= n; i += 3) {
    uint32_t v = (uint32_t(d[i]) << 16) | (uint32_t(d[i + 1]) << 8) | d[i + 2];
    *p++ = k[v >> 18];
    *p++ = k[(v >> 12) & 63];
    *p++ = k[(v >> 6) & 63];
    *p++ = k[v & 63];
  }
  if (i < n) {
    uint32_t v = uint32_t(d[i]) << 16;
    if (i + 1 < n) v |= uint32_t(d[i + 1]) << 8;
    *p++ = k[v >> 18];
    *p++ = k[(v >> 12) & 63];
    *p++ = i + 1 < n ? k[(v >> 6) & 63] : '=';
    *p++ = '=';
  }
}

namespace {

// Length of the valid UTF-8 sequence at s[i], or 0 when it is not one.
std::size_t utf8_length(std::string_view s, std::size_t i) {
  auto b = [&](std::size_t j) { return static_cast<unsigned char>(s[j]); };
  unsigned char c = b(i);
  std::size_t n = c >= 0xF0 && c <= 0xF4 ? 4 : c >= 0xE0 && c < 0xF0 ? 3 : c >= 0xC2 && c < 0xE0 ? 2 : 0;
  if (n == 0 || i + n > s.size()) return 0;
  for (std::size_t j = 1; j < n; ++j)
    if ((b(i + j) & 0xC0) != 0x80) return 0;
  if (n == 3 && ((c == 0xE0 && b(i + 1) < 0xA0) || (c == 0xED && b(i + 1) >= 0xA0))) return 0;  // overlong, surrogate
  if (n == 4 && ((c == 0xF0 && b(i + 1) < 0x90) || (c == 0xF4 && b(i + 1) >= 0x90))) return 0;
  return n;
}

}  // namespace

void append_json_string(std::string_view s, std::string& out) {
  static const char* hex = "0123456789abcdef";
  out.push_back('"');
  for (std::size_t i = 0; i < s.size();) {
    unsigned char c = static_cast<unsigned char>(s[i]);
    if (c >= 0x80) {
      std::size_t n = utf8_length(s, i);
      if (n == 0) {
        out += "\xEF\xBF\xBD";
        ++i;
      } else {
        out.append(s.substr(i, n));
        i += n;
      }
      continue;
    }
    if (c == '"' || c == '\\') {
      out.push_back('\\');
      out.push_back(static_cast<char>(c));
    } else if (c < 0x20) {
      out += "\\u00";
      out.push_back(hex[c >> 4]);
      out.push_back(hex[c & 15]);
    } else {
      out.push_back(static_cast<char>(c));
    }
    ++i;
  }
  out.push_back('"');
}

namespace {

// "00".."99": the decimal digits of an integer are written two at a time.
constexpr auto kPairs = [] {
  std::array<char, 200> t{};
  for (int i = 0; i < 100; ++i) t[2 * i] = char('0' + i / 10), t[2 * i + 1] = char('0' + i % 10);
  return t;
}();

// The decimal digits of v, ending at `end`; returns the first. (A float's digits fit 32 bits, whose
// divisions by 100 are cheaper.)
template <class U>
char* digits_backward(char* end, U v) {
  while (v >= 100) {
    end -= 2;
    std::memcpy(end, &kPairs[2 * (v % 100)], 2);
    v /= 100;
  }
  if (v >= 10) {
    end -= 2;
    std::memcpy(end, &kPairs[2 * v], 2);
  } else {
    *--end = char('0' + v);
  }
  return end;
}

constexpr std::uint64_t kPow10[20] = {1ull,
                                      10ull,
                                      100ull,
                                      1000ull,
                                      10000ull,
                                      100000ull,
                                      1000000ull,
                                      10000000ull,
                                      100000000ull,
                                      1000000000ull,
                                      10000000000ull,
                                      100000000000ull,
                                      1000000000000ull,
                                      10000000000000ull,
                                      100000000000000ull,
                                      1000000000000000ull,
                                      10000000000000000ull,
                                      100000000000000000ull,
                                      1000000000000000000ull,
                                      10000000000000000000ull};

// Decimal digits of v (1 for 0): from its bit length (log10 2 ~ 1233 / 4096), corrected by one comparison.
// v | 1 has as many digits as v and is never 0.
int digit_count(std::uint64_t v) {
  const std::uint64_t u = v | 1;
  const int t = ((64 - __builtin_clzll(u)) * 1233) >> 12;
  return t + (u >= kPow10[t]);
}

// The fixed text of v x 10^e, e < 0, that has k digits: its last -e digits after the point (zeros in front
// when it has fewer), "0" before the point when it has none else. Written backwards from the end.
template <class U>
char* fraction_text(char* p, U v, int k, int e) {
  char* end = p + std::max(k + e, 1) + 1 - e;
  char* q = end;
  int i = -e;
  for (; i >= 2; i -= 2, v /= 100) std::memcpy(q -= 2, &kPairs[2 * (v % 100)], 2);
  if (i) {
    *--q = char('0' + v % 10);
    v /= 10;
  }
  *--q = '.';
  digits_backward(q, v);
  return end;
}

// v x 10^e (v's k digits) as JSON text: fixed notation or d[.ddd]e±XX, whichever is shorter (fixed on a
// tie): the text std::to_chars writes for the same digits. Fixed is the shorter only with at most 5 zeros
// after the digits or 3 after the point, so every text fits in 24 characters.
template <class U>
char* place_digits(char* p, U v, int k, int e) {
  const int point = k + e;  // digits before the decimal point
  const int fixed = e >= 0 ? k + e : point > 0 ? k + 1 : 2 - point + k;
  const int x = point - 1;  // the scientific exponent
  const int ax = x < 0 ? -x : x;
  const int sci = k + (k > 1) + 2 + (ax >= 100 ? 3 : 2);
  if (fixed <= sci && e < 0) return fraction_text(p, v, k, e);
  if (fixed <= sci) {
    digits_backward(p + k, v);
    std::memcpy(p + k, "00000", 5);  // e <= 5 of them are the number's
    return p + k + e;
  }
  char* end = p + k + (k > 1);
  digits_backward(end, v);  // then the first digit moves before the point
  if (k > 1) {
    p[0] = p[1];
    p[1] = '.';
  }
  p = end;
  *p++ = 'e';
  *p++ = x < 0 ? '-' : '+';
  if (ax >= 100) *p++ = char('0' + ax / 100);
  std::memcpy(p, &kPairs[2 * (ax % 100)], 2);
  return p + 2;
}

// The 8 decimal digits of v < 10^8, zero-padded, as 8 characters in one word, first digit in the lowest
// byte: split into 4-digit, 2-digit and 1-digit lanes with multiplications by reciprocals (10486 / 2^20 is
// 1/100 below 43699, 103 / 2^10 is 1/10 below 179), no chain of divisions.
std::uint64_t eight_digits(std::uint32_t v) {
  std::uint64_t x = (v / 10000) | (std::uint64_t(v % 10000) << 32);
  std::uint64_t hi = ((x * 10486) >> 20) & 0x0000007F0000007Full;
  x = hi | ((x - hi * 100) << 16);
  hi = ((x * 103) >> 10) & 0x000F000F000F000Full;
  x = hi | ((x - hi * 10) << 8);
  return x | 0x3030303030303030ull;
}

// A float's digits (at most 9) placed as place_digits does, from a right-aligned copy with fixed-size moves:
// writes up to 16 bytes past the text's end.
char* place_float_digits(char* p, std::uint32_t v, int k, int e) {
  char buf[32] = {};
  buf[0] = char('0' + v / 100000000);
  const std::uint64_t w = eight_digits(v % 100000000);
  std::memcpy(buf + 1, &w, 8);
  const char* d = buf + 9 - k;
  const int point = k + e;
  const int fixed = e >= 0 ? k + e : point > 0 ? k + 1 : 2 - point + k;
  const int x = point - 1;
  const int ax = x < 0 ? -x : x;
  const int sci = k + (k > 1) + 2 + (ax >= 100 ? 3 : 2);
  if (fixed > sci) return place_digits(p, v, k, e);  // rare for a cloud: 1e-05 and below, 1e+15 and above
  if (e >= 0) {
    std::memcpy(p, d, 16);
    std::memcpy(p + k, "00000", 5);
    return p + k + e;
  }
  if (point > 0) {
    std::memcpy(p, d, 16);
    p[point] = '.';
    std::memcpy(p + point + 1, d + point, 16);
    return p + k + 1;
  }
  std::memcpy(p, "0.000", 5);  // -point <= 3 zeros after the point
  std::memcpy(p + 2 - point, d, 16);
  return p + 2 - point + k;
}

template <class F>
char* shortest(char* p, F v) {
  if (std::signbit(v)) {
    *p++ = '-';
    v = -v;
  }
  // Dragonbox (libfmt-dev; declared in fmt/format.h, built into libfmt): the shortest digits that read back
  // as v, trailing zeros removed; 0 comes back as 0 x 10^0 (docs/BENCHMARKS.md, "hg-mcap", against
  // std::to_chars).
  const auto dec = fmt::detail::dragonbox::to_decimal(v);
  if constexpr (std::is_same_v<F, float>)
    return place_float_digits(p, dec.significand, digit_count(dec.significand), dec.exponent);
  else
    return place_digits(p, dec.significand, digit_count(dec.significand), dec.exponent);
}

}  // namespace

char* write_shortest(char* p, float v) { return shortest(p, v); }
char* write_shortest(char* p, double v) { return shortest(p, v); }

namespace {

template <class Raw>
Raw byteswap(Raw v) {
  if constexpr (sizeof(Raw) == 2) return static_cast<Raw>(__builtin_bswap16(v));
  else if constexpr (sizeof(Raw) == 4)
    return __builtin_bswap32(v);
  else
    return __builtin_bswap64(v);
}

// Integers: the digits of a decimal pair table, two at a time.
template <class T>
char* write_number(char* p, T v) {
  using U = std::make_unsigned_t<T>;
  U u = static_cast<U>(v);
  if constexpr (std::is_signed_v<T>)
    if (v < 0) {
      *p++ = '-';
      u = static_cast<U>(U(0) - u);
    }
  char buf[24];
  char* first = digits_backward(buf + sizeof buf, u);
  std::size_t n = static_cast<std::size_t>(buf + sizeof buf - first);
  std::memcpy(p, first, n);
  return p + n;
}
char* write_number(char* p, float v) { return write_shortest(p, v); }
char* write_number(char* p, double v) { return write_shortest(p, v); }

template <class T>
void append_number(T v, std::string& out) {
  char buf[48];
  out.append(buf, write_number(buf, v));
}

template <class F>
void append_real(F v, std::string& out) {
  if (!std::isfinite(v)) {
    out += "null";
    return;
  }
  append_number(v, out);
}

// ---- the encoder ----

struct Encoder {
  const Schema& schema;
  const uint8_t* d;
  std::size_t size;
  std::size_t pos;
  std::string& out;
  const std::atomic<bool>* cancel;

  void need(std::size_t n, const std::string& field) const {
    if (n > size - pos)
      throw DecodeError("truncated: '" + field + "' needs " + std::to_string(n) + " bytes at byte " +
                        std::to_string(pos) + ", message has " + std::to_string(size));
  }
  uint64_t be(std::size_t n) {
    uint64_t v = 0;
    for (std::size_t i = 0; i < n; ++i) v = (v << 8) | d[pos + i];
    pos += n;
    return v;
  }

  void string_value(const std::string& field) {
    need(4, field);
    int32_t len = static_cast<int32_t>(be(4));
    if (len < 1) throw DecodeError("bad string length " + std::to_string(len) + " of '" + field + "'");
    need(static_cast<std::size_t>(len), field);
    const char* p = reinterpret_cast<const char*>(d + pos);
    if (p[len - 1] != '\0') throw DecodeError("string '" + field + "' is not NUL-terminated");
    append_json_string(std::string_view(p, static_cast<std::size_t>(len - 1)), out);
    pos += static_cast<std::size_t>(len);
  }

  // One primitive value; returns it as an integer when it is one (array sizes).
  int64_t primitive(Kind k, const std::string& field) {
    if (k == Kind::String) {
      string_value(field);
      return 0;
    }
    std::size_t n = fixed_size(k);
    need(n, field);
    uint64_t raw = be(n);
    switch (k) {
      case Kind::Int8: append_number(static_cast<int8_t>(raw), out); return static_cast<int8_t>(raw);
      case Kind::Int16: append_number(static_cast<int16_t>(raw), out); return static_cast<int16_t>(raw);
      case Kind::Int32: append_number(static_cast<int32_t>(raw), out); return static_cast<int32_t>(raw);
      case Kind::Int64: append_number(static_cast<int64_t>(raw), out); return static_cast<int64_t>(raw);
      case Kind::Byte: append_number(static_cast<unsigned>(raw), out); return 0;
      case Kind::Boolean: out += raw ? "true" : "false"; return 0;
      case Kind::Float: append_real(std::bit_cast<float>(static_cast<uint32_t>(raw)), out); return 0;
      case Kind::Double: append_real(std::bit_cast<double>(raw), out); return 0;
      default: return 0;
    }
  }

  void element(const Member& m, const std::string& field) {
    if (m.kind == Kind::Struct) structure(*schema.find(m.type_name), field);
    else
      primitive(m.kind, field);
  }

  // The innermost dimension of a numeric array: one bounds check, then a tight loop over blocks of elements
  // into a buffer on the stack with room for the longest text of each, appended as a whole (a cloud's u, v
  // and part arrays are most of the bytes of the bus: no per-element capacity check, and no resize, which
  // would first fill the room with zeros).
  template <class T, class Raw>
  void numbers(std::size_t n) {
    // The shortest round-trip text of a float or double is at most 24 characters, of an integer its digits
    // and the sign.
    constexpr std::size_t width = std::is_floating_point_v<T> ? 24 : std::numeric_limits<T>::digits10 + 3;
    constexpr std::size_t block = 1024;
    char scratch[block * (width + 1) + 16];  // + 16: a number's text may write up to 16 bytes past its end
    out.push_back('[');
    const uint8_t* src = d + pos;
    for (std::size_t i = 0; i < n; i += block) {
      if (cancel && cancel->load(std::memory_order_relaxed)) throw Cancelled();
      std::size_t m = std::min(block, n - i);
      char* p = scratch;
      for (std::size_t k = 0; k < m; ++k, src += sizeof(Raw)) {
        if (i + k) *p++ = ',';
        Raw raw;
        std::memcpy(&raw, src, sizeof raw);
        if constexpr (std::endian::native == std::endian::little && sizeof(Raw) > 1) raw = byteswap(raw);
        if constexpr (std::is_floating_point_v<T>) {
          T v = std::bit_cast<T>(raw);
          if (!std::isfinite(v)) {
            std::memcpy(p, "null", 4);
            p += 4;
            continue;
          }
          p = write_number(p, v);
        } else {
          p = write_number(p, static_cast<T>(raw));
        }
      }
      out.append(scratch, p);
    }
    out.push_back(']');
    pos += n * sizeof(Raw);
  }
  bool fast_numbers(Kind k, std::size_t n) {
    switch (k) {
      case Kind::Float: numbers<float, uint32_t>(n); return true;
      case Kind::Double: numbers<double, uint64_t>(n); return true;
      case Kind::Int16: numbers<int16_t, uint16_t>(n); return true;
      case Kind::Int32: numbers<int32_t, uint32_t>(n); return true;
      case Kind::Int64: numbers<int64_t, uint64_t>(n); return true;
      default: return false;
    }
  }

  // Every element of an array of any rank, in the message's (row-major) order: one flat JSON array, a byte
  // array one base64 string (member_schema says why).
  void array(const Member& m, const std::vector<int64_t>& lens, const std::string& field) {
    std::size_t fixed = fixed_size(m.kind), least = std::max<std::size_t>(fixed, 1), n = 1;
    for (int64_t len : lens) {  // a lying length fails here, before any loop: each element takes >= 1 byte
      if (len != 0 && n > (size - pos) / least / static_cast<std::size_t>(len)) need(size, field);
      n *= static_cast<std::size_t>(len);
    }
    if (m.kind == Kind::Byte) {
      need(n, field);
      out.push_back('"');
      append_base64(d + pos, n, out);
      out.push_back('"');
      pos += n;
      return;
    }
    if (fixed != 0) {
      need(n * fixed, field);
      if (fast_numbers(m.kind, n)) return;
    }
    out.push_back('[');
    for (std::size_t i = 0; i < n; ++i) {
      if (i) out.push_back(',');
      element(m, field);
    }
    out.push_back(']');
  }

  void structure(const Struct& s, const std::string& path) {
    std::map<std::string, int64_t, std::less<>> ints;  // integer members: array sizes
    out.push_back('{');
    bool first = true;
    for (const Member& m : s.members) {
      if (!first) out.push_back(',');
      first = false;
      append_json_string(m.name, out);
      out.push_back(':');
      std::string field = path.empty() ? m.name : path + "." + m.name;
      if (m.dims.empty()) {
        if (is_integer(m.kind)) ints[m.name] = primitive(m.kind, field);
        else
          element(m, field);
        continue;
      }
      std::vector<int64_t> lens;
      for (const Dim& dim : m.dims) {
        int64_t len = dim.variable ? ints.at(dim.var) : dim.fixed;
        if (len < 0) throw DecodeError("negative array length " + std::to_string(len) + " of '" + field + "'");
        lens.push_back(len);
      }
      array(m, lens, field);
    }
    out.push_back('}');
  }
};

}  // namespace

void to_json(const Schema& schema, const Struct& s, const uint8_t* data, std::size_t size, std::string& out,
             const std::atomic<bool>* cancel) {
  Encoder enc{schema, data, size, 0, out, cancel};
  enc.need(8, "fingerprint");
  if (static_cast<int64_t>(enc.be(8)) != schema.fingerprint(s))
    throw DecodeError("fingerprint is not that of " + s.full_name());
  enc.structure(s, "");
  if (enc.pos != size)
    throw DecodeError(std::to_string(size - enc.pos) + " trailing bytes after " + s.full_name() + " at byte " +
                      std::to_string(enc.pos));
}

}  // namespace hg::foxglove
