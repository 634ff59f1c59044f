#include "lcm_schema.hpp"

#include <algorithm>
#include <bit>
#include <cctype>
#include <cmath>
#include <cstring>
#include <limits>
#include <set>

namespace hg::lcmtools {

namespace {

struct Token {
  std::string text;
  int line = 0;
};

bool is_ident_char(char c) { return std::isalnum(static_cast<unsigned char>(c)) || c == '_' || c == '.'; }

std::vector<Token> tokenize(std::string_view text, const std::string& source) {
  std::vector<Token> out;
  int line = 1;
  std::size_t i = 0;
  while (i < text.size()) {
    char c = text[i];
    if (c == '\n') {
      ++line;
      ++i;
    } else if (std::isspace(static_cast<unsigned char>(c))) {
      ++i;
    } else if (c == '/' && i + 1 < text.size() && text[i + 1] == '/') {
      while (i < text.size() && text[i] != '\n') ++i;
    } else if (c == '/' && i + 1 < text.size() && text[i + 1] == '*') {
      int start = line;
      i += 2;
      while (i + 1 < text.size() && !(text[i] == '*' && text[i + 1] == '/')) {
        if (text[i] == '\n') ++line;
        ++i;
      }
      if (i + 1 >= text.size()) throw SchemaError(source + ":" + std::to_string(start) + ": unterminated comment");
      i += 2;
    } else if (is_ident_char(c) || c == '-' || c == '+') {
      std::size_t j = i + 1;
      while (j < text.size() && (is_ident_char(text[j]) ||
                                 ((text[j] == '-' || text[j] == '+') && (text[j - 1] == 'e' || text[j - 1] == 'E'))))
        ++j;
      out.push_back({std::string(text.substr(i, j - i)), line});
      i = j;
    } else if (std::strchr("{}[];,=", c)) {
      out.push_back({std::string(1, c), line});
      ++i;
    } else {
      throw SchemaError(source + ":" + std::to_string(line) + ": unexpected character '" + std::string(1, c) + "'");
    }
  }
  return out;
}

const std::map<std::string, Kind, std::less<>>& primitive_names() {
  static const std::map<std::string, Kind, std::less<>> m = {
      {"int8_t", Kind::Int8},   {"int16_t", Kind::Int16},   {"int32_t", Kind::Int32},
      {"int64_t", Kind::Int64}, {"float", Kind::Float},     {"double", Kind::Double},
      {"string", Kind::String}, {"boolean", Kind::Boolean}, {"byte", Kind::Byte}};
  return m;
}

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
    default: return 0;  // variable: string, struct
  }
}

class Parser {
 public:
  Parser(std::vector<Token> t, std::string source) : tok_(std::move(t)), source_(std::move(source)) {}

  void parse(std::vector<Struct>& out) {
    std::string package;
    while (more()) {
      if (peek() == "package") {
        next();
        package = ident("package name");
        expect(";");
      } else if (peek() == "struct") {
        next();
        Struct s;
        s.package = package;
        s.name = ident("struct name");
        s.source = source_;
        expect("{");
        while (peek() != "}") {
          if (peek() == "const") {
            skip_const();
          } else {
            parse_members(s);
          }
        }
        expect("}");
        if (s.members.empty()) fail("struct " + s.name + " has no members");
        out.push_back(std::move(s));
      } else {
        fail("expected 'package' or 'struct', found '" + peek() + "'");
      }
    }
  }

 private:
  bool more() const { return pos_ < tok_.size(); }
  const std::string& peek() const {
    static const std::string eof = "<end of file>";
    return more() ? tok_[pos_].text : eof;
  }
  const Token& next() {
    if (!more()) fail("unexpected end of file");
    return tok_[pos_++];
  }
  [[noreturn]] void fail(const std::string& what) const {
    int line = more() ? tok_[pos_].line : (tok_.empty() ? 1 : tok_.back().line);
    throw SchemaError(source_ + ":" + std::to_string(line) + ": " + what);
  }
  void expect(const char* s) {
    if (peek() != s) fail(std::string("expected '") + s + "', found '" + peek() + "'");
    ++pos_;
  }
  std::string ident(const char* what) {
    const std::string& t = peek();
    if (t.empty() || !(std::isalpha(static_cast<unsigned char>(t[0])) || t[0] == '_'))
      fail(std::string("expected ") + what + ", found '" + t + "'");
    return next().text;
  }
  void skip_const() {
    next();  // const
    ident("constant type");
    do {
      ident("constant name");
      expect("=");
      next();  // value, not needed by the tools
    } while (peek() == "," && (next(), true));
    expect(";");
  }
  void parse_members(Struct& s) {
    std::string type = ident("member type");
    do {
      Member m;
      m.type_name = type;
      auto p = primitive_names().find(type);
      m.kind = p == primitive_names().end() ? Kind::Struct : p->second;
      if (m.kind == Kind::Struct && type.find('.') == std::string::npos && !s.package.empty())
        m.type_name = s.package + "." + type;
      m.name = ident("member name");
      for (const Member& other : s.members)
        if (other.name == m.name) fail("duplicate member '" + m.name + "'");
      while (peek() == "[") {
        next();
        Dim d;
        const std::string& size = next().text;
        if (std::isdigit(static_cast<unsigned char>(size[0]))) {
          std::size_t used = 0;
          long long v = 0;
          try {
            v = std::stoll(size, &used);
          } catch (const std::exception&) {
            used = 0;
          }
          if (used != size.size() || v <= 0) fail("bad array size '" + size + "'");
          d.fixed = v;
          d.var = size;  // the text as written: it enters the fingerprint
        } else {
          d.variable = true;
          d.var = size;
          auto it = std::find_if(s.members.begin(), s.members.end(), [&](const Member& o) { return o.name == size; });
          if (it == s.members.end() || !is_integer(it->kind) || !it->dims.empty())
            fail("array size '" + size + "' of '" + m.name + "' is not an earlier integer member");
        }
        expect("]");
        m.dims.push_back(std::move(d));
      }
      s.members.push_back(std::move(m));
    } while (peek() == "," && (next(), true));
    expect(";");
  }

  std::vector<Token> tok_;
  std::string source_;
  std::size_t pos_ = 0;
};

// ---- fingerprint (the LCM type-specification hash) ----
uint64_t hash_update(uint64_t v, int64_t c) {
  // ((v << 8) ^ (v >> 55)) + c, with v a signed 64-bit value: the right shift is arithmetic.
  uint64_t shifted = static_cast<uint64_t>(static_cast<int64_t>(v) >> 55);
  return ((v << 8) ^ shifted) + static_cast<uint64_t>(c);
}
uint64_t hash_string(uint64_t v, const std::string& s) {
  v = hash_update(v, static_cast<int64_t>(s.size()));
  for (char c : s) v = hash_update(v, static_cast<signed char>(c));
  return v;
}

// ---- byte reading ----
struct Reader {
  const uint8_t* d;
  std::size_t size;
  std::size_t pos;

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
};

struct Writer {
  std::vector<uint8_t> out;
  void be(uint64_t v, std::size_t n) {
    for (std::size_t i = 0; i < n; ++i) out.push_back(static_cast<uint8_t>(v >> (8 * (n - 1 - i))));
  }
};

}  // namespace

bool is_primitive(Kind k) { return k != Kind::Struct; }

const char* kind_name(Kind k) {
  for (const auto& [name, kind] : primitive_names())
    if (kind == k) return name.c_str();
  return "struct";
}

void Schema::add(std::string_view text, const std::string& source_name) {
  Parser(tokenize(text, source_name), source_name).parse(structs_);
}

void Schema::finish() {
  std::set<std::string> names;
  for (const Struct& s : structs_)
    if (!names.insert(s.full_name()).second)
      throw SchemaError(s.source + ": struct " + s.full_name() + " defined twice");
  for (const Struct& s : structs_)
    for (const Member& m : s.members)
      if (m.kind == Kind::Struct && !find(m.type_name))
        throw SchemaError(s.source + ": member '" + m.name + "' of " + s.full_name() + " has unknown type " +
                          m.type_name);
  by_fingerprint_.clear();
  for (std::size_t i = 0; i < structs_.size(); ++i) by_fingerprint_[fingerprint(structs_[i])] = i;
}

Schema Schema::embedded() {
  Schema s;
  for (const SchemaSource& src : embedded_schema_sources()) s.add(src.text, src.name);
  s.finish();
  return s;
}

const Struct* Schema::find(std::string_view name) const {
  for (const Struct& s : structs_)
    if (s.full_name() == name || s.name == name) return &s;
  return nullptr;
}

const Struct* Schema::find_by_fingerprint(int64_t fp) const {
  auto it = by_fingerprint_.find(fp);
  return it == by_fingerprint_.end() ? nullptr : &structs_[it->second];
}

uint64_t Schema::base_hash(const Struct& s) const {
  uint64_t v = 0x12345678;
  for (const Member& m : s.members) {
    v = hash_string(v, m.name);
    if (m.kind != Kind::Struct) v = hash_string(v, m.type_name);  // a struct's content enters recursively
    v = hash_update(v, static_cast<int64_t>(m.dims.size()));
    for (const Dim& d : m.dims) {
      v = hash_update(v, d.variable ? 1 : 0);
      v = hash_string(v, d.var);
    }
  }
  return v;
}

uint64_t Schema::recursive_hash(const Struct& s, std::vector<const Struct*>& parents) const {
  if (std::find(parents.begin(), parents.end(), &s) != parents.end()) return 0;
  parents.push_back(&s);
  uint64_t v = base_hash(s);
  for (const Member& m : s.members)
    if (m.kind == Kind::Struct) v += recursive_hash(*find(m.type_name), parents);
  parents.pop_back();
  return (v << 1) + ((v >> 63) & 1);
}

int64_t Schema::fingerprint(const Struct& s) const {
  std::vector<const Struct*> parents;
  return static_cast<int64_t>(recursive_hash(s, parents));
}

// ---- decoding ----
namespace {

struct Decoder {
  const Schema& schema;
  const DecodeOptions& opt;
  Reader r;
  std::map<const Struct*, std::size_t> min_sizes;

  // Fewest bytes one value of this member's element type can take; bounds array lengths before allocating.
  std::size_t min_size(const Member& m) {
    if (m.kind == Kind::String) return 5;  // int32 length + NUL
    if (m.kind != Kind::Struct) return fixed_size(m.kind);
    const Struct* s = schema.find(m.type_name);
    auto it = min_sizes.find(s);
    if (it != min_sizes.end()) return it->second;
    min_sizes[s] = 0;  // guards recursive types
    std::size_t total = 0;
    for (const Member& c : s->members) {
      std::size_t n = 1;
      for (const Dim& d : c.dims) n = d.variable ? 0 : n * static_cast<std::size_t>(d.fixed);
      total += n * min_size(c);
    }
    return min_sizes[s] = total;
  }

  Json primitive(const Member& m, const std::string& path, bool build) {
    if (m.kind == Kind::String) {
      r.need(4, path);
      int32_t len = static_cast<int32_t>(r.be(4));
      if (len < 1)
        throw DecodeError("bad string length " + std::to_string(len) + " of '" + path + "' at byte " +
                          std::to_string(r.pos - 4));
      r.need(static_cast<std::size_t>(len), path);
      const char* p = reinterpret_cast<const char*>(r.d + r.pos);
      if (p[len - 1] != '\0')
        throw DecodeError("string '" + path + "' at byte " + std::to_string(r.pos) + " is not NUL-terminated");
      // LCM encoders write strlen() bytes, so a NUL inside means the length is wrong.
      if (std::memchr(p, '\0', static_cast<std::size_t>(len - 1)))
        throw DecodeError("string '" + path + "' at byte " + std::to_string(r.pos) + " has a NUL byte inside");
      r.pos += static_cast<std::size_t>(len);
      return build ? Json(std::string(p, static_cast<std::size_t>(len - 1))) : Json();
    }
    std::size_t n = fixed_size(m.kind);
    r.need(n, path);
    uint64_t raw = r.be(n);
    if (!build) return {};
    switch (m.kind) {
      case Kind::Int8: return static_cast<int8_t>(raw);
      case Kind::Int16: return static_cast<int16_t>(raw);
      case Kind::Int32: return static_cast<int32_t>(raw);
      case Kind::Int64: return static_cast<int64_t>(raw);
      case Kind::Byte: return static_cast<uint8_t>(raw);
      case Kind::Boolean: return raw != 0;
      case Kind::Float: return static_cast<double>(std::bit_cast<float>(static_cast<uint32_t>(raw)));
      case Kind::Double: return std::bit_cast<double>(raw);
      default: return {};
    }
  }

  Json element(const Member& m, const std::string& path, bool build) {
    if (m.kind == Kind::Struct) return structure(*schema.find(m.type_name), path, build);
    return primitive(m, path, build);
  }

  Json array(const Member& m, const std::vector<int64_t>& lens, std::size_t level, const std::string& path,
             bool build) {
    if (level == lens.size()) return element(m, path, build);
    std::size_t n = static_cast<std::size_t>(lens[level]);
    std::size_t fixed = m.kind == Kind::Struct || m.kind == Kind::String ? 0 : fixed_size(m.kind);
    std::size_t inner = 1;
    for (std::size_t i = level + 1; i < lens.size(); ++i) inner *= static_cast<std::size_t>(lens[i]);
    bool shorten = build && !opt.full && n > opt.max_shown;
    std::size_t shown = build ? (shorten ? opt.max_shown : n) : 0;
    Json items = Json::array();
    for (std::size_t i = 0; i < shown; ++i) items.push_back(array(m, lens, level + 1, path, true));
    if (fixed != 0) {  // the rest is skipped without reading
      std::size_t bytes = (n - shown) * inner * fixed;
      r.need(bytes, path);
      r.pos += bytes;
    } else {
      for (std::size_t i = shown; i < n; ++i) array(m, lens, level + 1, path, false);
    }
    if (!build) return {};
    if (shorten) return Json{{"length", n}, {"first", std::move(items)}};
    return items;
  }

  Json structure(const Struct& s, const std::string& path, bool build) {
    Json obj = build ? Json::object() : Json();
    std::map<std::string, int64_t, std::less<>> ints;  // values of integer members: array sizes
    for (const Member& m : s.members) {
      std::string mpath = path.empty() ? m.name : path + "." + m.name;
      if (m.dims.empty()) {
        Json v = element(m, mpath, build || is_integer(m.kind));
        if (is_integer(m.kind)) ints[m.name] = v.get<int64_t>();
        if (build) obj[m.name] = std::move(v);
        continue;
      }
      std::vector<int64_t> lens;
      // Bound the total element count by the bytes left: nothing is allocated for a lying length.
      long double total = 1;
      for (const Dim& d : m.dims) {
        int64_t len = d.variable ? ints.at(d.var) : d.fixed;
        if (len < 0)
          throw DecodeError("negative array length " + std::to_string(len) + " ('" + d.var + "') of '" + mpath +
                            "' before byte " + std::to_string(r.pos));
        lens.push_back(len);
        total *= static_cast<long double>(len);
      }
      std::size_t ms = min_size(m);
      long double left = static_cast<long double>(r.size - r.pos);
      if (total * static_cast<long double>(ms) > left || (ms == 0 && total > (1 << 20)))
        throw DecodeError("array '" + mpath + "' of " + std::to_string(static_cast<long long>(total)) +
                          " elements does not fit in the " + std::to_string(r.size - r.pos) + " bytes left at byte " +
                          std::to_string(r.pos));
      Json v = array(m, lens, 0, mpath, build);
      if (build) obj[m.name] = std::move(v);
    }
    return obj;
  }
};

}  // namespace

Json Schema::decode(const Struct& s, const uint8_t* data, std::size_t size, std::size_t& consumed,
                    const DecodeOptions& opt) const {
  Decoder dec{*this, opt, Reader{data, size, 0}, {}};
  dec.r.need(8, "fingerprint");
  int64_t fp = static_cast<int64_t>(dec.r.be(8));
  if (fp != fingerprint(s)) throw DecodeError("fingerprint is not that of " + s.full_name());
  Json v = dec.structure(s, "", true);
  consumed = dec.r.pos;
  return v;
}

// ---- encoding ----
namespace {

struct Encoder {
  const Schema& schema;
  Writer w;

  [[noreturn]] static void bad(const std::string& path, const std::string& what) {
    throw std::invalid_argument("field '" + path + "': " + what);
  }

  template <typename T>
  static T integer(const Json& v, const std::string& path) {
    if (!v.is_number_integer()) bad(path, "expected an integer, got " + v.dump());
    if (v.is_number_unsigned()) {
      auto u = v.get<uint64_t>();
      if (u > static_cast<uint64_t>(std::numeric_limits<T>::max())) bad(path, "out of range: " + v.dump());
      return static_cast<T>(u);
    }
    auto x = v.get<int64_t>();
    if (x < std::numeric_limits<T>::min() || x > std::numeric_limits<T>::max()) bad(path, "out of range: " + v.dump());
    return static_cast<T>(x);
  }
  static double real(const Json& v, const std::string& path) {
    if (v.is_null()) return std::numeric_limits<double>::quiet_NaN();  // NaN prints as null
    if (!v.is_number()) bad(path, "expected a number, got " + v.dump());
    return v.get<double>();
  }

  void element(const Member& m, const Json& v, const std::string& path) {
    switch (m.kind) {
      case Kind::Int8: w.be(static_cast<uint8_t>(integer<int8_t>(v, path)), 1); break;
      case Kind::Int16: w.be(static_cast<uint16_t>(integer<int16_t>(v, path)), 2); break;
      case Kind::Int32: w.be(static_cast<uint32_t>(integer<int32_t>(v, path)), 4); break;
      case Kind::Int64: w.be(static_cast<uint64_t>(integer<int64_t>(v, path)), 8); break;
      case Kind::Byte: w.be(integer<uint8_t>(v, path), 1); break;
      case Kind::Boolean:
        if (!v.is_boolean()) bad(path, "expected true or false, got " + v.dump());
        w.be(v.get<bool>() ? 1 : 0, 1);
        break;
      case Kind::Float: w.be(std::bit_cast<uint32_t>(static_cast<float>(real(v, path))), 4); break;
      case Kind::Double: w.be(std::bit_cast<uint64_t>(real(v, path)), 8); break;
      case Kind::String: {
        if (!v.is_string()) bad(path, "expected a string, got " + v.dump());
        const std::string& s = v.get_ref<const std::string&>();
        if (s.find('\0') != std::string::npos) bad(path, "string contains a NUL byte");
        w.be(static_cast<uint32_t>(s.size() + 1), 4);
        w.out.insert(w.out.end(), s.begin(), s.end());
        w.out.push_back(0);
        break;
      }
      case Kind::Struct: structure(*schema.find(m.type_name), v, path); break;
    }
  }

  void array(const Member& m, const std::vector<int64_t>& lens, std::size_t level, const Json& v,
             const std::string& path) {
    if (level == lens.size()) return element(m, v, path);
    if (!v.is_array() || static_cast<int64_t>(v.size()) != lens[level])
      bad(path, "expected an array of " + std::to_string(lens[level]) + " elements");
    for (const Json& item : v) array(m, lens, level + 1, item, path);
  }

  void structure(const Struct& s, const Json& v, const std::string& path) {
    if (!v.is_object()) bad(path, "expected an object of type " + s.full_name());
    std::map<std::string, int64_t, std::less<>> ints;
    for (const Member& m : s.members) {
      std::string mpath = path.empty() ? m.name : path + "." + m.name;
      auto it = v.find(m.name);
      if (it == v.end()) bad(mpath, "missing");
      if (m.dims.empty()) {
        element(m, *it, mpath);
        if (is_integer(m.kind)) ints[m.name] = it->get<int64_t>();
        continue;
      }
      std::vector<int64_t> lens;
      for (const Dim& d : m.dims) lens.push_back(d.variable ? ints.at(d.var) : d.fixed);
      array(m, lens, 0, *it, mpath);
    }
  }
};

}  // namespace

std::vector<uint8_t> Schema::encode(const Struct& s, const Json& value) const {
  Encoder enc{*this, {}};
  enc.w.be(static_cast<uint64_t>(fingerprint(s)), 8);
  enc.structure(s, value, "");
  return std::move(enc.w.out);
}

}  // namespace hg::lcmtools
