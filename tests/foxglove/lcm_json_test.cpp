// foxglove/lcm_json: the JSON of a message is the message. Property tests over random messages of every
// hullgrind type (random integers over each type's full range, floats including NaN, Inf, -0 and
// denormals, strings with escapes and multi-byte UTF-8, random array lengths): a random value is encoded
// to LCM bytes by lcm_tools (Schema::encode, which tools_schema_test checks against lcm-gen's classes),
// written as JSON by to_json, parsed back by nlohmann and compared with the value it came from.
// Truncated and corrupted bytes must throw DecodeError, never crash. ajv checks the schemas
// (tests/foxglove/mcap_check.js); here their shape follows the .lcm file member by member.
#include <gtest/gtest.h>

#include <charconv>
#include <cmath>
#include <cstring>
#include <limits>
#include <random>
#include <set>

#include "foxglove/lcm_json.hpp"

namespace {

using hg::foxglove::Json;
using hg::lcmtools::Kind;
using hg::lcmtools::Member;
using hg::lcmtools::Schema;
using hg::lcmtools::Struct;

std::string base64_of(const std::vector<uint8_t>& b) {
  std::string s;
  hg::foxglove::append_base64(b.data(), b.size(), s);
  return s;
}

struct Gen {
  const Schema& schema;
  std::mt19937_64 rng;
  int64_t top_level_max = 6;  // the largest array length of the message's own members (nested: 6)
  int depth = 0;

  int64_t range(int64_t lo, int64_t hi) { return std::uniform_int_distribution<int64_t>(lo, hi)(rng); }
  double real(bool single) {
    switch (range(0, 9)) {
      case 0: return std::numeric_limits<double>::quiet_NaN();
      case 1: return range(0, 1) ? INFINITY : -INFINITY;
      case 2: return -0.0;
      case 3: return single ? std::numeric_limits<float>::denorm_min() : std::numeric_limits<double>::denorm_min();
      default: {
        double v = std::ldexp(std::uniform_real_distribution<double>(-1, 1)(rng), static_cast<int>(range(-40, 40)));
        return single ? static_cast<double>(static_cast<float>(v)) : v;
      }
    }
  }
  std::string text() {
    static const std::vector<std::string> pieces = {"a",    "Z",    " ", "\"", "\\", "/",     "\n", "\t",
                                                    "\x01", "\x1f", "é", "€",  "😀",  "plate", "{}", "[]"};
    std::string s;
    for (int64_t i = range(0, 12); i > 0; --i) s += pieces[range(0, pieces.size() - 1)];
    return s;
  }
  Json primitive(Kind k) {
    switch (k) {
      case Kind::Int8: return range(-128, 127);
      case Kind::Int16: return range(-32768, 32767);
      case Kind::Int32: return range(INT32_MIN, INT32_MAX);
      case Kind::Int64: return range(INT64_MIN, INT64_MAX);
      case Kind::Byte: return range(0, 255);
      case Kind::Boolean: return range(0, 1) == 1;
      case Kind::Float: return real(true);
      case Kind::Double: return real(false);
      case Kind::String: return text();
      default: return {};
    }
  }
  Json element(const Member& m) {
    return m.kind == Kind::Struct ? object(*schema.find(m.type_name)) : primitive(m.kind);
  }
  Json array(const Member& m, const std::vector<int64_t>& lens, std::size_t level) {
    Json a = Json::array();
    for (int64_t i = 0; i < lens[level]; ++i)
      a.push_back(level + 1 == lens.size() ? element(m) : array(m, lens, level + 1));
    return a;
  }
  Json object(const Struct& s) {
    Json o = Json::object();
    std::map<std::string, int64_t> sizes;
    int64_t max_len = depth++ == 0 ? top_level_max : 6;
    for (const Member& m : s.members)  // array sizes first: they are earlier integer members
      for (const auto& d : m.dims)
        if (d.variable && !sizes.count(d.var)) sizes[d.var] = range(0, max_len);
    for (const Member& m : s.members) {
      if (sizes.count(m.name)) {
        o[m.name] = sizes[m.name];
      } else if (m.dims.empty()) {
        o[m.name] = element(m);
      } else {
        std::vector<int64_t> lens;
        for (const auto& d : m.dims) lens.push_back(d.variable ? sizes[d.var] : d.fixed);
        o[m.name] = array(m, lens, 0);
      }
    }
    --depth;
    return o;
  }
};

// What to_json must print for a value: NaN and Inf as null; an array of any rank as one flat array of its
// elements in row-major order, a byte array as one base64 string of them.
Json expected(const Schema& schema, const Member& m, const Json& v);
Json expected_object(const Schema& schema, const Struct& s, const Json& v) {
  Json o = Json::object();
  for (const Member& m : s.members) o[m.name] = expected(schema, m, v.at(m.name));
  return o;
}
void flatten(const Json& v, std::size_t rank, std::vector<Json>& out) {
  if (rank == 0) return out.push_back(v);
  for (const Json& x : v) flatten(x, rank - 1, out);
}
Json expected_scalar(const Schema& schema, const Member& m, const Json& v) {
  if (m.kind == Kind::Struct) return expected_object(schema, *schema.find(m.type_name), v);
  if ((m.kind == Kind::Float || m.kind == Kind::Double) && !std::isfinite(v.get<double>())) return nullptr;
  return v;
}
Json expected(const Schema& schema, const Member& m, const Json& v) {
  if (m.dims.empty()) return expected_scalar(schema, m, v);
  std::vector<Json> elements;
  flatten(v, m.dims.size(), elements);
  if (m.kind == Kind::Byte) {
    std::vector<uint8_t> b;
    for (const Json& x : elements) b.push_back(x.get<uint8_t>());
    return base64_of(b);
  }
  Json a = Json::array();
  for (const Json& x : elements) a.push_back(expected_scalar(schema, m, x));
  return a;
}

// Equal as the reader sees them: a float32 printed shortest ("292.35956") reads back as that float
// (Math.fround in JavaScript), -0 may print as the integer 0.
bool same(const Json& a, const Json& b, bool single) {
  if (a.is_number() && b.is_number()) {
    double x = a.get<double>(), y = b.get<double>();
    return single ? static_cast<float>(x) == static_cast<float>(y) : x == y;
  }
  if (a.is_array() && b.is_array()) {
    if (a.size() != b.size()) return false;
    for (std::size_t i = 0; i < a.size(); ++i)
      if (!same(a[i], b[i], single)) return false;
    return true;
  }
  return a == b;
}
bool same_object(const Schema& schema, const Struct& s, const Json& a, const Json& b) {
  if (!a.is_object() || a.size() != s.members.size()) return false;
  for (const Member& m : s.members) {
    if (!a.contains(m.name)) return false;
    if (m.kind == Kind::Struct) {
      const Struct& t = *schema.find(m.type_name);
      const Json &x = a[m.name], &y = b[m.name];
      if (m.dims.empty()) {
        if (!same_object(schema, t, x, y)) return false;
        continue;
      }
      if (!x.is_array() || x.size() != y.size()) return false;  // flat, whatever the rank
      for (std::size_t i = 0; i < x.size(); ++i)
        if (!same_object(schema, t, x[i], y[i])) return false;
    } else if (!same(a[m.name], b[m.name], m.kind == Kind::Float)) {
      return false;
    }
  }
  return true;
}

TEST(FoxgloveLcmJson, RandomMessagesOfEveryTypeComeBackAsTheirJson) {
  Schema schema = Schema::embedded();
  int checked = 0;
  for (uint64_t seed = 0; seed < 300; ++seed) {
    Gen gen{schema, std::mt19937_64(seed)};
    for (const Struct& s : schema.structs()) {
      Json value = gen.object(s);
      std::vector<uint8_t> bytes = schema.encode(s, value);
      std::string text;
      hg::foxglove::to_json(schema, s, bytes.data(), bytes.size(), text);
      Json back = Json::parse(text);  // throws on invalid JSON or UTF-8
      Json want = expected_object(schema, s, value);
      ASSERT_TRUE(same_object(schema, s, back, want)) << s.full_name() << " seed " << seed << "\n"
                                                      << text << "\n"
                                                      << want.dump();
      ++checked;
    }
  }
  EXPECT_GT(checked, 3000);
}

// Long numeric arrays (a cloud's u, v and part): the encoder writes them in blocks of elements into room it
// sizes ahead; every element of arrays up to several blocks long must come back, NaN and Inf as null.
TEST(FoxgloveLcmJson, LongArraysComeBackElementByElement) {
  Schema schema = Schema::embedded();
  for (const char* name : {"hullgrind.plate_cloud_t", "hullgrind.outline_t", "hullgrind.grind_path_t"}) {
    const Struct& s = *schema.find(name);
    for (uint64_t seed = 0; seed < 6; ++seed) {
      Gen gen{schema, std::mt19937_64(seed + 1000)};
      gen.top_level_max = 20000;
      Json value = gen.object(s);
      std::vector<uint8_t> bytes = schema.encode(s, value);
      std::string text;
      hg::foxglove::to_json(schema, s, bytes.data(), bytes.size(), text);
      Json back = Json::parse(text);
      ASSERT_TRUE(same_object(schema, s, back, expected_object(schema, s, value))) << name << " seed " << seed;
    }
  }
}

// The live server's stop: a set cancel flag ends the text of a long array with Cancelled; an unset one
// changes nothing.
TEST(FoxgloveLcmJson, CancelFlagStopsALongArray) {
  Schema schema = Schema::embedded();
  const Struct& s = *schema.find("hullgrind.plate_cloud_t");
  Gen gen{schema, std::mt19937_64(7)};
  gen.top_level_max = 20000;
  std::vector<uint8_t> bytes = schema.encode(s, gen.object(s));
  std::string plain, unset, cancelled;
  std::atomic<bool> no{false}, yes{true};
  hg::foxglove::to_json(schema, s, bytes.data(), bytes.size(), plain);
  hg::foxglove::to_json(schema, s, bytes.data(), bytes.size(), unset, &no);
  EXPECT_EQ(unset, plain);
  EXPECT_THROW(hg::foxglove::to_json(schema, s, bytes.data(), bytes.size(), cancelled, &yes), hg::foxglove::Cancelled);
}

TEST(FoxgloveLcmJson, CutAndCorruptedBytesThrowDecodeErrorNeverCrash) {
  Schema schema = Schema::embedded();
  std::mt19937_64 rng(7);
  for (const Struct& s : schema.structs()) {
    Gen gen{schema, std::mt19937_64(11)};
    std::vector<uint8_t> bytes = schema.encode(s, gen.object(s));
    for (std::size_t cut = 0; cut < bytes.size(); ++cut) {
      std::string text;
      EXPECT_THROW(hg::foxglove::to_json(schema, s, bytes.data(), cut, text), hg::lcmtools::DecodeError)
          << s.full_name() << " cut at " << cut;
    }
    std::vector<uint8_t> longer = bytes;
    longer.push_back(0);
    std::string text;
    EXPECT_THROW(hg::foxglove::to_json(schema, s, longer.data(), longer.size(), text), hg::lcmtools::DecodeError);
    for (int i = 0; i < 2000; ++i) {  // random bytes after the fingerprint: a decode or a DecodeError
      std::vector<uint8_t> bad = bytes;
      for (int k = 0; k < 4; ++k) bad[8 + rng() % (bad.size() - 8)] = static_cast<uint8_t>(rng());
      std::string t;
      try {
        hg::foxglove::to_json(schema, s, bad.data(), bad.size(), t);
        EXPECT_NO_THROW((void)Json::parse(t)) << s.full_name();
      } catch (const hg::lcmtools::DecodeError&) {
      }
    }
  }
}

TEST(FoxgloveLcmJson, SchemaFollowsTheLcmFileMemberByMember) {
  Schema schema = Schema::embedded();
  for (const Struct& s : schema.structs()) {
    Json js = hg::foxglove::json_schema(schema, s);
    EXPECT_EQ(js["title"], s.full_name());
    EXPECT_EQ(js["additionalProperties"], false);
    ASSERT_EQ(js["required"].size(), s.members.size());
    for (std::size_t i = 0; i < s.members.size(); ++i) {
      const Member& m = s.members[i];
      EXPECT_EQ(js["required"][i], m.name);
      const Json& p = js["properties"][m.name];
      if (m.dims.empty() && m.kind == Kind::Struct) EXPECT_EQ(p["title"], m.type_name) << m.name;  // in place
      if (m.kind == Kind::Byte && !m.dims.empty()) EXPECT_EQ(p["contentEncoding"], "base64") << m.name;
      if (m.kind != Kind::Byte && !m.dims.empty()) {
        EXPECT_EQ(p["type"], "array") << m.name;
        EXPECT_NE(p["items"]["type"], "array") << m.name << ": any rank is one flat array";
      }
    }
  }
}

// What Foxglove's and Lichtblick's JSON Schema reader takes (Lichtblick, packages/mcap-support/src/
// parseJsonSchema.ts; tests/foxglove/viewer_schema.js checks the same on the schemas a live server and an
// MCAP carry): one "type" per field, no "$ref", no array of arrays, no encoded strings in an array.
void expect_viewer_readable(const Json& object, const std::string& at) {
  ASSERT_EQ(object["type"], "object") << at;
  static const std::set<std::string> field{"boolean", "string", "number", "integer", "object", "array"};
  for (const auto& [name, f] : object["properties"].items()) {
    std::string where = at + "." + name;
    EXPECT_FALSE(f.contains("$ref")) << where;
    ASSERT_TRUE(f["type"].is_string() && field.count(f["type"].get<std::string>())) << where << ": " << f.dump();
    if (f["type"] == "object") expect_viewer_readable(f, where);
    if (f["type"] != "array") continue;
    const Json& item = f["items"];
    ASSERT_TRUE(item["type"].is_string() && item["type"] != "array") << where << "[]: " << item.dump();
    EXPECT_FALSE(item["type"] == "string" && item.contains("contentEncoding")) << where;
    if (item["type"] == "object") expect_viewer_readable(item, where + "[]");
  }
}

TEST(FoxgloveLcmJson, EverySchemaIsOneFoxgloveAndLichtblickCanRead) {
  Schema schema = Schema::embedded();
  for (const Struct& s : schema.structs()) {
    Json js = hg::foxglove::json_schema(schema, s);
    EXPECT_FALSE(js.contains("definitions")) << s.full_name();
    expect_viewer_readable(js, s.full_name());
  }
}

TEST(FoxgloveLcmJson, Base64IsRfc4648) {
  auto b = [](std::string s) { return base64_of(std::vector<uint8_t>(s.begin(), s.end())); };
  EXPECT_EQ(b(""), "");
  EXPECT_EQ(b("f"), "Zg==");
  EXPECT_EQ(b("fo"), "Zm8=");
  EXPECT_EQ(b("foo"), "Zm9v");
  EXPECT_EQ(b("foobar"), "Zm9vYmFy");
}

TEST(FoxgloveLcmJson, InvalidUtf8BecomesReplacementCharacter) {
  std::string out;
  hg::foxglove::append_json_string(
      "a\xff"
      "b\xc3",
      out);
  EXPECT_EQ(Json::parse(out),
            "a\xEF\xBF\xBD"
            "b\xEF\xBF\xBD");
}

}  // namespace

// write_shortest (Dragonbox's digits, our placement) against libstdc++'s std::to_chars, an independent
// shortest round-trip formatter: over random bit patterns of every exponent and the edge values, the text
// reads back (std::from_chars) as the same float or double, bit for bit, and is to_chars' text (an integer
// that needs zeros after its shortest digits: of to_chars' length).
template <class F, class Bits>
void check_shortest(uint64_t seed, int count) {
  std::mt19937_64 rng(seed);
  std::vector<F> values = {F(0),
                           -F(0),
                           F(1),
                           F(0.1),
                           F(1e-5),
                           F(123456789),
                           F(1e16),
                           F(1e21),
                           std::numeric_limits<F>::min(),
                           std::numeric_limits<F>::max(),
                           std::numeric_limits<F>::lowest(),
                           std::numeric_limits<F>::denorm_min(),
                           std::numeric_limits<F>::epsilon()};
  for (int i = 0; i < count; ++i) {
    Bits b = static_cast<Bits>(rng());
    F v;
    std::memcpy(&v, &b, sizeof v);
    if (std::isfinite(v)) values.push_back(v);
    values.push_back(static_cast<F>(std::uniform_real_distribution<double>(-1, 1)(rng)));  // a cloud's metres
  }
  for (F v : values) {
    char ours[48], theirs[32];
    char* end = hg::foxglove::write_shortest(ours, v);
    ASSERT_LE(end - ours, 24);
    char* their_end = std::to_chars(theirs, theirs + sizeof theirs, v).ptr;
    F back;
    auto r = std::from_chars(ours, end, back);
    const std::string text(ours, end), want(theirs, their_end);
    ASSERT_TRUE(r.ec == std::errc() && r.ptr == end) << text;
    ASSERT_EQ(std::memcmp(&back, &v, sizeof v), 0) << text << " does not read back as " << want;
    if (want.find_first_of(".e") != std::string::npos) {
      ASSERT_EQ(text, want);
    } else {  // an integer: libstdc++ writes the value's exact digits, we the shortest ones and zeros
      ASSERT_EQ(text.size(), want.size()) << text << " vs std::to_chars' " << want;
    }
    ASSERT_NO_THROW(Json::parse(text)) << text;  // valid JSON
  }
}

TEST(FoxgloveLcmJson, ShortestFloatTextReadsBackAndIsToCharsText) {
  for (uint64_t seed = 0; seed < 40; ++seed) {
    check_shortest<float, uint32_t>(seed, 25000);
    check_shortest<double, uint64_t>(seed + 100, 25000);
  }
}
