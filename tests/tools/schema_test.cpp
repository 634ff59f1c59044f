// The schema-driven decoder/encoder of tools/lcm_tools against lcm-gen's generated classes, which are the
// independent reference: same fingerprints, same bytes, and garbage never decodes or crashes.
#include <gtest/gtest.h>

#include <random>
#include <set>

#include "hg_lcm_registry.inc"
#include "registry.hpp"
#include "sample.hpp"

using namespace hg::lcmtools;

namespace {

const Schema& schema() {
  static const Schema s = [] {
    Schema x = Schema::embedded();
    return x;
  }();
  return s;
}

// Encodes with the generated class of the named type from a buffer decoded by that class: lcm-gen's own
// bytes for the same message.
std::vector<uint8_t> regenerate(const std::string& name, const std::vector<uint8_t>& bytes, int* used) {
#define HG_TRY_TYPE(T)                                                      \
  if (name == "hullgrind." #T) {                                            \
    hullgrind::T m{};                                                       \
    *used = m.decode(bytes.data(), 0, static_cast<int>(bytes.size()));      \
    std::vector<uint8_t> out(static_cast<std::size_t>(m.getEncodedSize())); \
    m.encode(out.data(), 0, static_cast<int>(out.size()));                  \
    return out;                                                             \
  }
  HG_LCM_FOR_EACH_TYPE(HG_TRY_TYPE)
#undef HG_TRY_TYPE
  ADD_FAILURE() << "no generated class for " << name;
  return {};
}

}  // namespace

TEST(ToolsSchema, FingerprintsMatchLcmGen) {
  ASSERT_EQ(schema().structs().size(), generated_types().size());
  for (const GeneratedType& g : generated_types()) {
    const Struct* s = schema().find(g.full_name);
    ASSERT_NE(s, nullptr) << g.full_name;
    EXPECT_EQ(schema().fingerprint(*s), g.fingerprint) << g.full_name;
    EXPECT_EQ(schema().find_by_fingerprint(g.fingerprint), s);
  }
  EXPECT_NO_THROW(check_schema_matches_generated(schema()));
}

TEST(ToolsSchema, SamplesEncodeExactlyAsLcmGenAndDecodeBack) {
  for (const Struct& s : schema().structs()) {
    for (int64_t seq : {0, 1, 5, 12, 1000}) {
      Json sample = sample_message(schema(), s, seq, 1700000000000000 + seq);
      std::vector<uint8_t> bytes = schema().encode(s, sample);
      int used = -1;
      std::vector<uint8_t> reference = regenerate(s.full_name(), bytes, &used);
      ASSERT_EQ(used, static_cast<int>(bytes.size())) << s.full_name() << " seq " << seq;
      EXPECT_EQ(reference, bytes) << s.full_name() << " seq " << seq;

      Decoded d = decode_message(schema(), bytes.data(), bytes.size(), DecodeOptions{true, 8});
      ASSERT_EQ(d.type, &s) << d.error;
      EXPECT_EQ(d.msg, sample) << s.full_name();
      const bool nested = s.name == "outline_loop_t" || s.name == "edge_stretch_t" || s.name == "loop_coverage_t";
      EXPECT_EQ(message_seq(d.msg), nested ? -1 : seq);  // the nested types have no header
    }
  }
}

TEST(ToolsSchema, KnownValuesDecodeToTheirFields) {
  hullgrind::heartbeat_t hb{};
  hb.header.seq = 41;
  hb.header.utime = 1234567;
  hb.header.frame_id = "";
  hb.process = "hg-outline-service";
  hb.pid = -7;
  hb.state = hullgrind::heartbeat_t::STATE_DEGRADED;
  hb.state_text = "camera slow \xc3\xa9";
  hb.uptime = 12.5;
  hb.received = 1LL << 40;
  hb.published = 3;
  hb.dropped = 0;
  hb.decode_errors = 9;
  hb.last_latency = -1;
  std::vector<uint8_t> bytes(static_cast<std::size_t>(hb.getEncodedSize()));
  hb.encode(bytes.data(), 0, static_cast<int>(bytes.size()));
  Decoded d = decode_message(schema(), bytes.data(), bytes.size(), {});
  ASSERT_NE(d.type, nullptr) << d.error;
  EXPECT_EQ(d.type->full_name(), "hullgrind.heartbeat_t");
  const Json& m = d.msg;
  EXPECT_EQ(m["header"]["seq"], 41);
  EXPECT_EQ(m["header"]["utime"], 1234567);
  EXPECT_EQ(m["process"], "hg-outline-service");
  EXPECT_EQ(m["pid"], -7);
  EXPECT_EQ(m["state"], 2);
  EXPECT_EQ(m["state_text"], "camera slow \xc3\xa9");
  EXPECT_EQ(m["uptime"], 12.5);
  EXPECT_EQ(m["received"], 1LL << 40);
  EXPECT_EQ(m["decode_errors"], 9);
  EXPECT_EQ(m["last_latency"], -1.0);
}

TEST(ToolsSchema, LongArraysAreShortenedUnlessFull) {
  const Struct* s = schema().find("plate_cloud_t");
  ASSERT_NE(s, nullptr);
  Json msg = sample_message(schema(), *s, 0, 0);
  msg["n"] = 20;
  msg["u"] = Json::array();
  msg["v"] = Json::array();
  msg["part"] = Json::array();
  for (int i = 0; i < 20; ++i) {
    msg["u"].push_back(i * 0.5);
    msg["v"].push_back(-i * 0.25);
    msg["part"].push_back(i % 3);
  }
  std::vector<uint8_t> bytes = schema().encode(*s, msg);
  Decoded brief = decode_message(schema(), bytes.data(), bytes.size(), DecodeOptions{false, 8});
  ASSERT_NE(brief.type, nullptr) << brief.error;
  EXPECT_EQ(brief.msg["u"]["length"], 20);
  ASSERT_EQ(brief.msg["u"]["first"].size(), 8u);
  for (int i = 0; i < 8; ++i) EXPECT_EQ(brief.msg["u"]["first"][i], i * 0.5);
  EXPECT_EQ(brief.msg["num_parts"], msg["num_parts"]);  // fields after the shortened arrays still decode
  Decoded full = decode_message(schema(), bytes.data(), bytes.size(), DecodeOptions{true, 8});
  ASSERT_NE(full.type, nullptr);
  EXPECT_EQ(full.msg, msg);
}

TEST(ToolsSchema, EveryTruncationAndTrailingByteIsAnError) {
  for (const Struct* s : message_types(schema())) {
    std::vector<uint8_t> bytes = schema().encode(*s, sample_message(schema(), *s, 7, 99));
    for (std::size_t len = 0; len < bytes.size(); ++len) {
      Decoded d = decode_message(schema(), bytes.data(), len, {});
      EXPECT_EQ(d.type, nullptr) << s->full_name() << " cut to " << len;
      EXPECT_FALSE(d.error.empty());
    }
    std::vector<uint8_t> longer = bytes;
    longer.push_back(0);
    Decoded d = decode_message(schema(), longer.data(), longer.size(), {});
    EXPECT_EQ(d.type, nullptr);
    EXPECT_NE(d.error.find("1 trailing bytes after byte " + std::to_string(bytes.size())), std::string::npos)
        << d.error;
  }
}

TEST(ToolsSchema, LyingLengthsAreRejectedBeforeAllocating) {
  // plate_cloud_t ends with: int32 n, float u[n], float v[n], int16 part[n], int16 num_parts, then the flange
  // pose (boolean, 3 + 4 doubles: 57 bytes) and the frame's evidence (int32, double, boolean, 2 doubles: 29
  // bytes). With n = 0 the 6 bytes before the flange pose are n and num_parts; n is then set to values the
  // bytes cannot hold.
  const Struct* s = schema().find("plate_cloud_t");
  Json msg = sample_message(schema(), *s, 0, 0);
  msg["n"] = 0;
  msg["u"] = msg["v"] = msg["part"] = Json::array();
  std::vector<uint8_t> bytes = schema().encode(*s, msg);
  std::size_t n_at = bytes.size() - 29 - 57 - 6;
  for (uint32_t lie : {0x7fffffffu, 0x80000000u, 0xffffffffu, 23u}) {  // 23 floats: 4 bytes more than the 88 left
    std::vector<uint8_t> b = bytes;
    for (int k = 0; k < 4; ++k) b[n_at + k] = static_cast<uint8_t>(lie >> (24 - 8 * k));
    Decoded d = decode_message(schema(), b.data(), b.size(), {});
    EXPECT_EQ(d.type, nullptr) << lie;
    bool says_why = d.error.find("does not fit") != std::string::npos || d.error.find("negative") != std::string::npos;
    EXPECT_TRUE(says_why) << d.error;
  }
}

TEST(ToolsSchema, RandomBytesNeverCrashAndOnlyExactMessagesDecode) {
  std::mt19937_64 rng(12345);
  std::vector<const Struct*> types = message_types(schema());
  int decoded = 0;
  for (int i = 0; i < 20000; ++i) {
    const Struct* t = types[static_cast<std::size_t>(i) % types.size()];
    std::vector<uint8_t> b = schema().encode(*t, sample_message(schema(), *t, i, i));
    // Flip a few random bytes of a valid message (the fingerprint too, sometimes).
    int flips = 1 + static_cast<int>(rng() % 4);
    for (int f = 0; f < flips; ++f) b[rng() % b.size()] = static_cast<uint8_t>(rng());
    if (rng() % 3 == 0) b.resize(rng() % (b.size() + 1));
    Decoded d = decode_message(schema(), b.data(), b.size(), DecodeOptions{true, 8});
    if (d.type) {
      // Whatever decodes must be exactly a message: re-encoding gives the same bytes (booleans other
      // than 0/1 and NaN payloads are the exceptions LCM allows, so compare through the decoder again).
      std::vector<uint8_t> again = schema().encode(*d.type, d.msg);
      Decoded d2 = decode_message(schema(), again.data(), again.size(), DecodeOptions{true, 8});
      ASSERT_EQ(d2.type, d.type);
      EXPECT_EQ(again.size(), b.size());
      ++decoded;
    } else {
      EXPECT_FALSE(d.error.empty());
    }
  }
  // Flips in numeric fields keep most messages valid; flips in lengths do not: both paths ran.
  EXPECT_GT(decoded, 0);
  EXPECT_LT(decoded, 20000);
}

TEST(ToolsSchema, SchemaErrorsNameFileAndLine) {
  Schema bad;
  try {
    bad.add("package p;\nstruct a_t {\n  int32_t x;\n  double y[n];\n}\n", "bad.lcm");
    FAIL() << "accepted an array sized by an unknown member";
  } catch (const SchemaError& e) {
    EXPECT_NE(std::string(e.what()).find("bad.lcm:4"), std::string::npos) << e.what();
  }
  Schema unknown;
  unknown.add("package p;\nstruct b_t { other_t o; }\n", "b.lcm");
  EXPECT_THROW(unknown.finish(), SchemaError);
  Schema syntax;
  EXPECT_THROW(syntax.add("package p;\nstruct c_t { int32_t x }\n", "c.lcm"), SchemaError);
}

TEST(ToolsSchema, EveryTypeWithAHeaderHasItsOwnChannel) {
  std::set<std::string> channels;
  for (const Struct& s : schema().structs()) {
    bool has_header = !s.members.empty() && s.members[0].type_name == "hullgrind.header_t";
    EXPECT_EQ(!default_channel(s).empty(), has_header) << s.full_name();
    if (has_header) {
      EXPECT_TRUE(channels.insert(default_channel(s)).second) << default_channel(s);
    }
  }
  EXPECT_EQ(channels.size(), message_types(schema()).size());
}
