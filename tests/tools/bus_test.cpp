// hg-lcm-send, hg-lcm-dump, tools/record and lcm-logplayer as separate processes on one LCM bus. The suite
// runs inside tests/netns.sh (its own network namespace), so the multicast stays private to it.
#include <gtest/gtest.h>

#include <signal.h>
#include <unistd.h>

#include <chrono>
#include <filesystem>
#include <fstream>
#include <map>
#include <set>
#include <sstream>
#include <thread>

#include "registry.hpp"
#include "sample.hpp"
#include "tests/common/child_process.hpp"

namespace fs = std::filesystem;
using namespace hg::lcmtools;

namespace {

const std::string kUrl = "udpm://239.255.76.67:7667?ttl=0";
const std::string kBin = HG_BIN_DIR;
const std::string kSource = HG_SOURCE_DIR;

const Schema& schema() {
  static const Schema s = Schema::embedded();
  return s;
}

// A tool run by a test, its stdout and stderr in files.
struct Proc {
  hg::test::ChildProcess process;
  fs::path out, err;
};

// Starts argv with stdout and stderr in files; the child gets LCM_DEFAULT_URL = the ttl=0 URL.
Proc start(const std::vector<std::string>& argv, const fs::path& dir, const std::string& tag) {
  Proc p{{}, dir / (tag + ".out"), dir / (tag + ".err")};
  p.process = hg::test::ChildProcess(argv, hg::test::ChildOptions()
                                               .set_env("LCM_DEFAULT_URL", kUrl)
                                               .stdout_to(p.out.string())
                                               .stderr_to(p.err.string())
                                               .search_in_path());
  return p;
}

std::string slurp(const fs::path& f) {
  std::ifstream in(f, std::ios::binary);
  std::stringstream ss;
  ss << in.rdbuf();
  return ss.str();
}

// Exit status of p; a hang guard (not a timing check) kills it after 120 s and fails.
int wait_exit(Proc& p) {
  if (const std::optional<int> code = p.process.wait(std::chrono::seconds(120))) return *code;
  p.process.kill_now();
  ADD_FAILURE() << "process did not exit; stderr: " << slurp(p.err);
  return -1;
}

int run(const std::vector<std::string>& argv, const fs::path& dir, const std::string& tag) {
  Proc p = start(argv, dir, tag);
  return wait_exit(p);
}

// Waits until `file` contains `text` (a process saying it is ready); fails after 30 s.
bool wait_for_text(const fs::path& file, const std::string& text) {
  for (int i = 0; i < 300; ++i) {
    if (slurp(file).find(text) != std::string::npos) return true;
    std::this_thread::sleep_for(std::chrono::milliseconds(100));
  }
  ADD_FAILURE() << "never saw '" << text << "' in " << file;
  return false;
}

Proc start_dump(const std::vector<std::string>& extra, const fs::path& dir, const std::string& tag) {
  std::vector<std::string> argv = {kBin + "/hg-lcm-dump", "--lcm-url", kUrl};
  argv.insert(argv.end(), extra.begin(), extra.end());
  Proc p = start(argv, dir, tag);
  wait_for_text(p.err, "listening on");
  return p;
}

std::vector<Json> json_lines(const fs::path& f) {
  std::vector<Json> out;
  std::istringstream in(slurp(f));
  std::string line;
  while (std::getline(in, line)) {
    Json j = Json::parse(line, nullptr, false);
    EXPECT_FALSE(j.is_discarded()) << "not JSON: " << line;
    out.push_back(j);
  }
  return out;
}

struct TempDir {
  fs::path path;
  explicit TempDir(const std::string& name) {
    path = fs::temp_directory_path() / ("hg-tools-" + name + "-" + std::to_string(getpid()));
    fs::remove_all(path);
    fs::create_directories(path);
  }
  ~TempDir() { fs::remove_all(path); }
};

// Checks that `lines` hold, for every message type, `rounds` messages with seq 0..rounds-1 on the
// type's channel, each exactly the sample hg-lcm-send builds for that seq.
void expect_every_sample(const std::vector<Json>& lines, int rounds) {
  std::map<std::string, std::set<int64_t>> seqs;
  for (const Json& l : lines) {
    ASSERT_FALSE(l.contains("error")) << l.dump();
    const Struct* t = schema().find(l["type"].get<std::string>());
    ASSERT_NE(t, nullptr) << l.dump();
    EXPECT_EQ(l["channel"], default_channel(*t));
    int64_t seq = message_seq(l["msg"]);
    EXPECT_TRUE(seqs[t->full_name()].insert(seq).second) << "seq " << seq << " twice for " << t->full_name();
    Json expected = sample_message(schema(), *t, seq, l["msg"]["header"]["utime"].get<int64_t>());
    EXPECT_EQ(l["msg"], expected) << t->full_name() << " seq " << seq;
  }
  std::set<int64_t> all;
  for (int64_t s = 0; s < rounds; ++s) all.insert(s);
  ASSERT_EQ(seqs.size(), message_types(schema()).size());
  for (const Struct* t : message_types(schema())) EXPECT_EQ(seqs[t->full_name()], all) << t->full_name();
}

// Reads an LCM log file directly (the event format of lcm-logger: sync word, event number, utime,
// channel length, data length, channel, data) and counts events per channel; an independent look at
// what the log holds.
std::map<std::string, int> count_log_events(const fs::path& log, int* bad) {
  std::string b = slurp(log);
  auto be = [&](std::size_t at, int n) {
    uint64_t v = 0;
    for (int i = 0; i < n; ++i) v = (v << 8) | static_cast<uint8_t>(b[at + i]);
    return v;
  };
  std::map<std::string, int> counts;
  std::size_t at = 0;
  *bad = 0;
  while (at + 28 <= b.size()) {
    if (be(at, 4) != 0xEDA1DA01u) {
      ++*bad;
      break;
    }
    uint32_t chan_len = static_cast<uint32_t>(be(at + 20, 4));
    uint32_t data_len = static_cast<uint32_t>(be(at + 24, 4));
    if (at + 28 + chan_len + data_len > b.size()) {
      ++*bad;
      break;
    }
    std::string channel = b.substr(at + 28, chan_len);
    std::string data = b.substr(at + 28 + chan_len, data_len);
    Decoded d = decode_message(schema(), reinterpret_cast<const uint8_t*>(data.data()), data.size(), {});
    if (!d.type) ++*bad;
    ++counts[channel];
    at += 28 + chan_len + data_len;
  }
  if (at != b.size()) ++*bad;
  return counts;
}

}  // namespace

TEST(ToolsBus, SamplesOfEveryTypeDecodeInAnotherProcess) {
  TempDir dir("samples");
  const int rounds = 12;
  const int total = rounds * static_cast<int>(message_types(schema()).size());
  Proc dump = start_dump({"--full", "--count", std::to_string(total), "--timeout", "60"}, dir.path, "dump");
  EXPECT_EQ(run({kBin + "/hg-lcm-send", "sample", "--type", "all", "--count", std::to_string(rounds), "--rate", "100"},
                dir.path, "send"),
            0);
  EXPECT_EQ(wait_exit(dump), 0) << slurp(dump.err);
  std::vector<Json> lines = json_lines(dump.out);
  ASSERT_EQ(static_cast<int>(lines.size()), total);
  expect_every_sample(lines, rounds);
}

TEST(ToolsBus, GarbageIsReportedAndTheDumpKeepsDecoding) {
  TempDir dir("garbage");
  const int garbage = 40, good = 5;
  Proc dump = start_dump({"--count", std::to_string(good), "--timeout", "60", "--summary"}, dir.path, "dump");
  EXPECT_EQ(run({kBin + "/hg-lcm-send", "garbage", "--channel", "HG_GARBAGE", "--count", std::to_string(garbage)},
                dir.path, "garbage"),
            0);
  EXPECT_EQ(run({kBin + "/hg-lcm-send", "sample", "--type", "heartbeat_t", "--count", std::to_string(good)}, dir.path,
                "send"),
            0);
  EXPECT_EQ(wait_exit(dump), 0) << slurp(dump.err);
  std::vector<Json> lines = json_lines(dump.out);
  int errors = 0;
  std::set<int64_t> seqs;
  std::set<std::string> reasons;
  for (const Json& l : lines) {
    if (l.contains("error")) {
      EXPECT_EQ(l["channel"], "HG_GARBAGE");
      EXPECT_FALSE(l.contains("msg"));
      std::string why = l["error"];
      reasons.insert(why.find("unknown fingerprint") != std::string::npos ? "fingerprint"
                     : why.find("trailing") != std::string::npos          ? "trailing"
                     : why.find("truncated") != std::string::npos         ? "truncated"
                                                                          : "length");
      ++errors;
    } else {
      EXPECT_EQ(l["type"], "hullgrind.heartbeat_t");
      seqs.insert(message_seq(l["msg"]));
    }
  }
  EXPECT_EQ(errors, garbage);
  EXPECT_EQ(reasons.size(), 4u);  // every kind of garbage was seen and told apart
  EXPECT_EQ(seqs, (std::set<int64_t>{0, 1, 2, 3, 4}));
  EXPECT_NE(slurp(dump.err).find("summary HG_GARBAGE decoded 0 errors 40"), std::string::npos) << slurp(dump.err);
}

TEST(ToolsBus, TypeFilterJobCommandAndExitCodes) {
  TempDir dir("filter");
  Proc dump = start_dump({"--type", "job_request_t", "--count", "1", "--timeout", "60"}, dir.path, "dump");
  EXPECT_EQ(
      run({kBin + "/hg-lcm-send", "sample", "--type", "heartbeat_t,robot_status_t", "--count", "3"}, dir.path, "noise"),
      0);
  EXPECT_EQ(run({kBin + "/hg-lcm-send", "job", "--job-id", "J-42", "--part-id", "plate 7", "--action", "abort",
                 "--tool-radius", "0.012", "--direction", "conventional", "--flipped", "--seq", "9"},
                dir.path, "job"),
            0);
  EXPECT_EQ(wait_exit(dump), 0) << slurp(dump.err);
  std::vector<Json> lines = json_lines(dump.out);
  ASSERT_EQ(lines.size(), 1u);
  const Json& m = lines[0]["msg"];
  EXPECT_EQ(lines[0]["channel"], "HG_JOB_REQUEST");
  EXPECT_EQ(m["job_id"], "J-42");
  EXPECT_EQ(m["part_id"], "plate 7");
  EXPECT_EQ(m["action"], 1);     // ACTION_ABORT
  EXPECT_EQ(m["direction"], 1);  // DIRECTION_CONVENTIONAL
  EXPECT_EQ(m["flipped"], true);
  EXPECT_EQ(m["tool_radius"], 0.012);
  EXPECT_EQ(m["grind_speed"], 0.0);
  EXPECT_EQ(m["header"]["seq"], 9);
  EXPECT_GT(m["header"]["utime"].get<int64_t>(), 0);

  // Nothing published: --count not reached -> 3; no --count -> 0. Bad usage -> 2.
  EXPECT_EQ(run({kBin + "/hg-lcm-dump", "--channels", "HG_NOBODY", "--count", "1", "--timeout", "0.3"}, dir.path, "t1"),
            3);
  EXPECT_EQ(run({kBin + "/hg-lcm-dump", "--channels", "HG_NOBODY", "--timeout", "0.3"}, dir.path, "t2"), 0);
  EXPECT_EQ(run({kBin + "/hg-lcm-dump", "--count", "many"}, dir.path, "t3"), 2);
  EXPECT_EQ(run({kBin + "/hg-lcm-dump", "--type", "no_such_t"}, dir.path, "t4"), 2);
  EXPECT_EQ(run({kBin + "/hg-lcm-send", "job"}, dir.path, "t5"), 2);

  // The operator's actions: approve (with exclusions and the revision seen), reject, replan, query.
  Proc ops = start_dump({"--type", "job_request_t", "--count", "4", "--timeout", "60"}, dir.path, "ops");
  EXPECT_EQ(run({kBin + "/hg-lcm-send", "approve", "--job-id", "J-7", "--exclude-loops", "3,5", "--revision", "2",
                 "--by", "ann"},
                dir.path, "approve"),
            0);
  EXPECT_EQ(run({kBin + "/hg-lcm-send", "reject", "--job-id", "J-8", "--by", "bo"}, dir.path, "reject"), 0);
  EXPECT_EQ(run({kBin + "/hg-lcm-send", "replan", "--job-id", "J-9", "--tool-radius", "0.008"}, dir.path, "replan"), 0);
  EXPECT_EQ(run({kBin + "/hg-lcm-send", "query"}, dir.path, "query"), 0);
  EXPECT_EQ(wait_exit(ops), 0) << slurp(ops.err);
  lines = json_lines(ops.out);
  ASSERT_EQ(lines.size(), 4u);
  EXPECT_EQ(lines[0]["msg"]["action"], 3);  // ACTION_APPROVE
  EXPECT_EQ(lines[0]["msg"]["actor"], "operator ann");
  EXPECT_EQ(lines[0]["msg"]["plan_revision"], 2);
  EXPECT_EQ(lines[0]["msg"]["excluded_loops"], Json::array({3, 5}));
  EXPECT_EQ(lines[0]["msg"]["num_excluded"], 2);
  EXPECT_EQ(lines[1]["msg"]["action"], 4);  // ACTION_REJECT
  EXPECT_EQ(lines[1]["msg"]["actor"], "operator bo");
  EXPECT_EQ(lines[2]["msg"]["action"], 5);  // ACTION_REPLAN
  EXPECT_EQ(lines[2]["msg"]["tool_radius"], 0.008);
  EXPECT_EQ(lines[3]["msg"]["action"], 6);  // ACTION_QUERY
  EXPECT_EQ(lines[3]["msg"]["job_id"], "");
  // Who decides is required; a loop list must be indices.
  EXPECT_EQ(run({kBin + "/hg-lcm-send", "approve", "--job-id", "J-7"}, dir.path, "t6"), 2);
  EXPECT_EQ(run({kBin + "/hg-lcm-send", "reject", "--job-id", "J-7"}, dir.path, "t7"), 2);
  EXPECT_EQ(
      run({kBin + "/hg-lcm-send", "approve", "--job-id", "J-7", "--by", "x", "--exclude-loops", "3,a"}, dir.path, "t8"),
      2);
  EXPECT_EQ(
      run({kBin + "/hg-lcm-send", "reject", "--job-id", "J-7", "--by", "x", "--tool-radius", "1"}, dir.path, "t9"), 2);

  // SIGTERM: clean exit 0 with the summary printed.
  Proc idle = start_dump({"--summary"}, dir.path, "idle");
  idle.process.signal(SIGTERM);
  EXPECT_EQ(wait_exit(idle), 0);
  EXPECT_NE(slurp(idle.err).find("summary total decoded 0"), std::string::npos) << slurp(idle.err);
}

TEST(ToolsBus, RecordedSamplesReplayAndDecode) {
  TempDir dir("record");
  const int rounds = 15;
  const int types = static_cast<int>(message_types(schema()).size());
  fs::path log = dir.path / "run.lcmlog";
  Proc rec =
      start({kSource + "/tools/record", "--lcm-url", kUrl, "--channels", "HG_.*|MARK", log.string()}, dir.path, "rec");
  ASSERT_TRUE(wait_for_text(rec.out, "run.lcmlog"));
  EXPECT_EQ(slurp(rec.out), log.string() + "\n");
  EXPECT_EQ(run({kBin + "/hg-lcm-send", "sample", "--type", "all", "--count", std::to_string(rounds), "--rate", "100"},
                dir.path, "send"),
            0);
  // Not on a recorded channel: must not be in the log.
  EXPECT_EQ(run({kBin + "/hg-lcm-send", "sample", "--type", "heartbeat_t", "--channel", "OTHER", "--count", "2"},
                dir.path, "other"),
            0);
  // lcm-logger writes events in the order received but flushes only when a later one arrives: publish
  // markers on a recorded channel until one is on disk; everything published before it is then in the log.
  int bad = 0;
  for (int i = 0; i < 300 && count_log_events(log, &bad)["MARK"] == 0; ++i)
    run({kBin + "/hg-lcm-send", "sample", "--type", "heartbeat_t", "--channel", "MARK", "--count", "1"}, dir.path,
        "mark");
  rec.process.signal(SIGINT);
  EXPECT_EQ(wait_exit(rec), 0) << slurp(rec.err);

  std::map<std::string, int> in_log = count_log_events(log, &bad);
  EXPECT_EQ(bad, 0);
  EXPECT_GE(in_log["MARK"], 1);
  in_log.erase("MARK");
  ASSERT_EQ(static_cast<int>(in_log.size()), types);
  for (const auto& [channel, n] : in_log) EXPECT_EQ(n, rounds) << channel;

  Proc dump = start_dump({"--full", "--count", std::to_string(rounds * types), "--timeout", "60"}, dir.path, "dump");
  EXPECT_EQ(run({"lcm-logplayer", "--lcm-url", kUrl, log.string()}, dir.path, "play"), 0);
  EXPECT_EQ(wait_exit(dump), 0) << slurp(dump.err);
  std::vector<Json> lines = json_lines(dump.out);
  ASSERT_EQ(static_cast<int>(lines.size()), rounds * types);
  expect_every_sample(lines, rounds);
}

TEST(ToolsBus, CommittedLogReplaysAndDecodes) {
  TempDir dir("committed");
  fs::path log = fs::path(HG_TEST_DATA) / "tools" / "samples-all-types.lcmlog";
  ASSERT_TRUE(fs::exists(log)) << log;
  int bad = 0;
  std::map<std::string, int> in_log = count_log_events(log, &bad);
  ASSERT_EQ(bad, 0) << "the committed log no longer decodes: regenerate it (docs/monitoring.md)";
  int total = 0;
  for (const auto& [channel, n] : in_log) total += n;
  ASSERT_EQ(in_log.size(), message_types(schema()).size());

  Proc dump =
      start_dump({"--full", "--count", std::to_string(total), "--timeout", "60", "--summary"}, dir.path, "dump");
  EXPECT_EQ(run({"lcm-logplayer", "--lcm-url", kUrl, "--speed", "4", log.string()}, dir.path, "play"), 0);
  EXPECT_EQ(wait_exit(dump), 0) << slurp(dump.err);
  std::map<std::string, int> replayed;
  for (const Json& l : json_lines(dump.out)) {
    ASSERT_FALSE(l.contains("error")) << l.dump();
    ++replayed[l["channel"].get<std::string>()];
    const Struct* t = schema().find(l["type"].get<std::string>());
    EXPECT_EQ(l["msg"],
              sample_message(schema(), *t, message_seq(l["msg"]), l["msg"]["header"]["utime"].get<int64_t>()));
  }
  EXPECT_EQ(replayed, in_log);
}

TEST(ToolsBus, JsonCommandPublishesWhatDumpPrints) {
  TempDir dir("json");
  const Struct* t = schema().find("grind_path_t");
  Json msg = sample_message(schema(), *t, 11, 123456);
  Proc dump = start_dump({"--full", "--count", "1", "--timeout", "60", "--channels", "HG_X"}, dir.path, "dump");
  EXPECT_EQ(
      run({kBin + "/hg-lcm-send", "json", "--type", "grind_path_t", "--channel", "HG_X", msg.dump()}, dir.path, "send"),
      0);
  EXPECT_EQ(wait_exit(dump), 0) << slurp(dump.err);
  std::vector<Json> lines = json_lines(dump.out);
  ASSERT_EQ(lines.size(), 1u);
  EXPECT_EQ(lines[0]["type"], "hullgrind.grind_path_t");
  EXPECT_EQ(lines[0]["msg"], msg);
  // A field of the wrong kind is refused with its name, nothing is published.
  msg["n"] = "three";
  EXPECT_EQ(
      run({kBin + "/hg-lcm-send", "json", "--type", "grind_path_t", "--channel", "HG_X", msg.dump()}, dir.path, "bad"),
      2);
  EXPECT_NE(slurp(dir.path / "bad.err").find("field 'n'"), std::string::npos) << slurp(dir.path / "bad.err");
}
