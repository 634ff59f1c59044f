// runtime::Node without sockets: parameter precedence, command-line errors, decode-error counting and
// header sequence numbers, over LCM's in-process memq:// provider.
#include <gtest/gtest.h>

#include <unistd.h>

#include <cstdint>
#include <string>
#include <vector>

#include "hullgrind/job_request_t.hpp"
#include "runtime/node.hpp"
#include "tests/common/temp_file.hpp"

namespace hr = hg::runtime;

namespace {

hr::ProcessInfo info() {
  return {"hg-test",
          "a test process",
          "",
          {{"speed", "0.05", "grind speed, m/s"},
           {"mode", "dshi", "point location"},
           {"limits", "1,2,3", "a list"},
           {"dry-run", "", "do nothing", true}}};
}

struct Argv {
  std::vector<std::string> args;
  std::vector<char*> ptrs;
  explicit Argv(std::vector<std::string> a) : args(std::move(a)) {
    args.insert(args.begin(), "hg-test");
    for (auto& s : args) ptrs.push_back(s.data());
    ptrs.push_back(nullptr);
  }
  int argc() const { return int(args.size()); }
  char** argv() { return ptrs.data(); }
};

TEST(RuntimeNode, CommandLineBeatsConfigBeatsDefault) {
  std::string cfg = hg::test::temp_yaml("speed: 0.5\nmode: ds\n");
  Argv a({"--lcm-url", "memq://", "--config", cfg, "--mode", "ordinary", "--dry-run"});
  hr::Node node(info(), a.argc(), a.argv());
  EXPECT_EQ(node.params().text("mode"), "ordinary");                           // command line
  EXPECT_EQ(node.params().number("speed"), 0.5);                               // config
  EXPECT_EQ(node.params().numbers("limits"), (std::vector<double>{1, 2, 3}));  // default
  EXPECT_TRUE(node.params().flag("dry-run"));
  EXPECT_TRUE(node.params().given("speed"));
  EXPECT_FALSE(node.params().given("limits"));
  EXPECT_EQ(node.lcm_url(), "memq://");
  unlink(cfg.c_str());
}

TEST(RuntimeNode, FlagDefaultsToFalse) {
  Argv a({"--lcm-url=memq://"});
  hr::Node node(info(), a.argc(), a.argv());
  EXPECT_FALSE(node.params().flag("dry-run"));
  EXPECT_EQ(node.params().text("mode"), "dshi");
}

TEST(RuntimeNodeDeathTest, UnknownOptionExits2) {
  Argv a({"--lcm-url", "memq://", "--no-such-thing", "1"});
  EXPECT_EXIT(hr::Node(info(), a.argc(), a.argv()), testing::ExitedWithCode(2), "unknown option --no-such-thing");
}

TEST(RuntimeNodeDeathTest, MissingConfigExits2) {
  Argv a({"--lcm-url", "memq://", "--config", "/nonexistent.yaml"});
  EXPECT_EXIT(hr::Node(info(), a.argc(), a.argv()), testing::ExitedWithCode(2), "/nonexistent.yaml");
}

TEST(RuntimeNodeDeathTest, HelpExits0AndListsParameters) {
  Argv a({"--help"});
  EXPECT_EXIT(
      {
        // --help prints to stdout; route it to stderr so the death test can match it.
        dup2(2, 1);
        hr::Node(info(), a.argc(), a.argv());
      },
      testing::ExitedWithCode(0), "--speed VALUE +grind speed, m/s \\[default: 0.05\\]");
}

TEST(RuntimeNode, GarbageIsCountedAndSkipped) {
  Argv a({"--lcm-url", "memq://"});
  hr::Node node(info(), a.argc(), a.argv());
  int delivered = 0;
  node.subscribe<hullgrind::job_request_t>("HG_JOB_REQUEST",
                                           [&](const hullgrind::job_request_t& m, const hr::Delivery&) {
                                             ++delivered;
                                             EXPECT_EQ(m.job_id, "j7");
                                           });
  hullgrind::job_request_t good{};
  good.job_id = "j7";
  std::vector<uint8_t> bytes(good.getEncodedSize());
  good.encode(bytes.data(), 0, int(bytes.size()));

  const uint8_t junk[] = {0xde, 0xad, 0xbe, 0xef, 1, 2, 3};
  node.lcm().publish("HG_JOB_REQUEST", junk, sizeof junk);                         // foreign fingerprint
  node.lcm().publish("HG_JOB_REQUEST", bytes.data(), unsigned(bytes.size() - 3));  // truncated
  std::vector<uint8_t> longer = bytes;
  longer.push_back(0);
  node.lcm().publish("HG_JOB_REQUEST", longer.data(), unsigned(longer.size()));  // trailing byte
  node.lcm().publish("HG_JOB_REQUEST", bytes.data(), unsigned(bytes.size()));    // good
  for (int i = 0; i < 4; ++i) node.lcm().handleTimeout(100);
  EXPECT_EQ(delivered, 1);
  EXPECT_EQ(node.counters().decode_errors.load(), 3);
  EXPECT_EQ(node.counters().received.load(), 1);
}

TEST(RuntimeNode, PublishFillsHeaderSequencePerChannel) {
  Argv a({"--lcm-url", "memq://"});
  hr::Node node(info(), a.argc(), a.argv());
  std::vector<int64_t> seqs;
  node.subscribe<hullgrind::job_request_t>("A", [&](const hullgrind::job_request_t& m, const hr::Delivery&) {
    seqs.push_back(m.header.seq);
    EXPECT_GT(m.header.utime, 1'600'000'000'000'000);
  });
  for (int i = 0; i < 3; ++i) {
    hullgrind::job_request_t m{};
    node.publish("A", m);
    node.lcm().handleTimeout(100);
  }
  hullgrind::job_request_t other{};
  node.publish("B", other);
  EXPECT_EQ(other.header.seq, 0);  // B counts on its own
  EXPECT_EQ(seqs, (std::vector<int64_t>{0, 1, 2}));
  EXPECT_EQ(node.counters().published.load(), 4);
}

}  // namespace
