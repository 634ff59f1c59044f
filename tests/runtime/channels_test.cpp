// The one channel table (runtime/channels.hpp): docs/CHANNELS.md's table is generated from it, every type it
// names is a message type of lcmtypes/, and every channel constant has exactly one row. After changing the
// table:  HG_WRITE_DOC=1 build/tests/runtime_channels_test  rewrites the doc's table.
#include <gtest/gtest.h>

#include <cstdlib>
#include <fstream>
#include <regex>
#include <set>
#include <sstream>
#include <string>

#include "runtime/channels.hpp"

namespace ch = hg::channels;

namespace {

const std::string kDoc = std::string(HG_SOURCE_DIR) + "/docs/CHANNELS.md";
const std::string kBegin =
    "<!-- The table below is generated from runtime/channels.hpp (tests/runtime/channels_test.cpp; "
    "HG_WRITE_DOC=1 build/tests/runtime_channels_test rewrites it). -->\n";
const std::string kEnd = "<!-- end of the generated channel table -->\n";

std::string read(const std::string& path) {
  std::ifstream f(path);
  std::stringstream s;
  s << f.rdbuf();
  return s.str();
}

std::string table_markdown() {
  std::string md = "| channel | type | publishers | subscribers | what |\n|---|---|---|---|---|\n";
  for (const ch::Channel& c : ch::kTable)
    md += std::string("| `") + c.name + "` | `" + c.type + "` | " + c.publishers + " | " + c.subscribers + " | " +
          c.what + " |\n";
  return md;
}

}  // namespace

TEST(Channels, DocTableIsTheCodeTable) {
  std::string doc = read(kDoc);
  const std::size_t b = doc.find(kBegin), e = doc.find(kEnd);
  ASSERT_NE(b, std::string::npos) << kDoc << " lacks the line " << kBegin;
  ASSERT_NE(e, std::string::npos) << kDoc << " lacks the line " << kEnd;
  ASSERT_LT(b, e);
  const std::string generated = table_markdown();
  const std::string in_doc = doc.substr(b + kBegin.size(), e - b - kBegin.size());
  if (std::getenv("HG_WRITE_DOC") && in_doc != generated) {
    doc.replace(b + kBegin.size(), in_doc.size(), generated);
    std::ofstream(kDoc) << doc;
    return;
  }
  EXPECT_EQ(in_doc, generated) << "docs/CHANNELS.md's table differs from runtime/channels.hpp; HG_WRITE_DOC=1 "
                                  "build/tests/runtime_channels_test rewrites it";
}

TEST(Channels, EveryTypeIsAMessageTypeOfLcmtypes) {
  for (const ch::Channel& c : ch::kTable) {
    const std::string lcm = read(std::string(HG_SOURCE_DIR) + "/lcmtypes/" + c.type + ".lcm");
    EXPECT_TRUE(std::regex_search(lcm, std::regex("\\bstruct\\s+" + std::string(c.type) + "\\b")))
        << c.name << ": no lcmtypes/" << c.type << ".lcm declaring struct " << c.type;
  }
}

TEST(Channels, EveryConstantHasOneRowAndEveryRowIsComplete) {
  const char* constants[] = {ch::kDepth,     ch::kPlateCloud, ch::kOutline,   ch::kPartPose,
                             ch::kGrindPath, ch::kJobRequest, ch::kJobStatus, ch::kRobotStatus,
                             ch::kRobotMove, ch::kHeartbeat,  ch::kLog};
  std::multiset<std::string> rows;
  for (const ch::Channel& c : ch::kTable) {
    rows.insert(c.name);
    EXPECT_TRUE(std::regex_match(c.name, std::regex("HG_[A-Z_]+"))) << c.name;
    EXPECT_STRNE(c.publishers, "") << c.name;
    EXPECT_STRNE(c.subscribers, "") << c.name;
    EXPECT_STRNE(c.what, "") << c.name;
  }
  EXPECT_EQ(rows.size(), std::size(constants));
  for (const char* k : constants) EXPECT_EQ(rows.count(k), 1u) << k;
}
