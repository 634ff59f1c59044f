// hg-job-recorder on the bus (own network namespace) with tools/hg-jobs reading what it wrote: a job to DONE
// with its outline and path, a hostile job id kept inside the directory, and a job open when the recorder is
// killed (-9) shown as interrupted with its last state after a restart, then ended by a later status; and
// kill -9 of the recorder at random moments just before the robot bridge's DONE: the restarted recorder
// catches up (QUERY) and every record ends as the bus ended it.
#include <gtest/gtest.h>

#include <lcm/lcm-cpp.hpp>

#include <chrono>
#include <csignal>
#include <cstdio>
#include <filesystem>
#include <fstream>
#include <map>
#include <random>
#include <sstream>
#include <thread>
#include <unistd.h>

#include <nlohmann/json.hpp>

#include "hullgrind/grind_path_t.hpp"
#include "hullgrind/heartbeat_t.hpp"
#include "hullgrind/job_request_t.hpp"
#include "hullgrind/job_status_t.hpp"
#include "hullgrind/outline_t.hpp"
#include "job_recorder/recorder.hpp"
#include "runtime/lcm_url.hpp"
#include "jobs/job_ledger.hpp"
#include "tests/common/cell_file.hpp"
#include "tests/robot_bridge/test_paths.hpp"
#include "tests/common/child_process.hpp"

namespace fs = std::filesystem;
using hullgrind::job_request_t;
using hullgrind::job_status_t;
using nlohmann::json;
using namespace std::chrono_literals;

namespace {

struct Fixture {
  lcm::LCM lcm{hg::runtime::default_lcm_url()};
  fs::path dir = fs::temp_directory_path() / ("hg_jobrec_proc_" + std::to_string(getpid()));
  int beats = 0, beat_pid = -1;
  void on_beat(const lcm::ReceiveBuffer*, const std::string&, const hullgrind::heartbeat_t* b) {
    if (b->process != "hg-job-recorder") return;
    ++beats;
    beat_pid = b->pid;
  }
  Fixture() {
    fs::remove_all(dir);
    lcm.subscribe("HG_HEARTBEAT", &Fixture::on_beat, this);
  }
  ~Fixture() { fs::remove_all(dir); }
  hg::test::ChildProcess start() {
    hg::test::ChildProcess p(
        {std::string(HG_BIN_DIR) + "/hg-job-recorder", "--dir", dir.string(), "--log-level", "warn"});
    beats = 0;
    const int pid = p.pid();
    wait([&] { return beats > 0 && beat_pid == pid; }, 10s);  // subscribed once it beats (this one)
    return p;
  }
  template <class Pred>
  bool wait(Pred pred, std::chrono::milliseconds limit) {
    const auto end = std::chrono::steady_clock::now() + limit;
    while (std::chrono::steady_clock::now() < end) {
      if (pred()) return true;
      lcm.handleTimeout(20);
    }
    return pred();
  }
  void request(const std::string& id, const std::string& part) {
    job_request_t r{};
    r.job_id = id;
    r.part_id = part;
    r.action = job_request_t::ACTION_START;
    lcm.publish("HG_JOB_REQUEST", &r);
  }
  void status(const std::string& id, std::int8_t state, const std::string& source, const std::string& msg) {
    job_status_t s{};
    s.job_id = id;
    s.source = source;
    s.state = state;
    s.message = msg;
    lcm.publish("HG_JOB_STATUS", &s);
  }
  json record(const std::string& id) {
    std::ifstream in(dir / hg::job_recorder::job_dir_name(id) / "job.json");
    std::stringstream ss;
    ss << in.rdbuf();
    return json::parse(ss.str(), nullptr, false);
  }
  bool record_has(const std::string& id, const std::string& key, const json& value) {
    const json r = record(id);
    return !r.is_discarded() && r.contains(key) && r[key] == value;
  }
};

std::string run(const std::string& cmd) {
  std::string out;
  FILE* p = popen(cmd.c_str(), "r");
  if (!p) return out;
  char buf[4096];
  while (std::size_t n = std::fread(buf, 1, sizeof buf, p)) out.append(buf, n);
  pclose(p);
  return out;
}

std::string hg_jobs(const Fixture& f, const std::string& args) {
  return run(std::string(HG_SOURCE_DIR) + "/tools/hg-jobs --dir " + f.dir.string() + " " + args + " 2>&1");
}

}  // namespace

TEST(JobRecorderProcess, RecordsJobsAndTheirEndsAcrossAKill) {
  Fixture f;
  ASSERT_TRUE(f.lcm.good()) << "no LCM: the test must run inside tests/netns.sh";
  auto rec = f.start();
  ASSERT_GT(f.beats, 0) << "no heartbeat from hg-job-recorder";

  hullgrind::outline_t o{};
  o.header.seq = 5;
  o.status = hullgrind::outline_t::STATUS_OK;
  hullgrind::outline_loop_t l{};
  l.u = {0, 0.3f, 0.3f, 0};
  l.v = {0, 0, 0.2f, 0.2f};
  l.n = 4;
  o.loops = {l};
  o.num_loops = 1;
  f.lcm.publish("HG_OUTLINE", &o);
  f.request("job-1", "hull-X");
  f.status("job-1", job_status_t::STATE_PLANNING, "hg-path-planner", "planning");
  hullgrind::grind_path_t p{};
  p.job_id = "job-1";
  p.outline_seq = 5;
  p.frame = "robot_base";
  p.n = 2;
  p.position = {{0.5, 0, 0.1}, {0.6, 0, 0.1}};
  p.orientation = {{0, 1, 0, 0}, {0, 1, 0, 0}};
  p.speed = {0.02, 0.02};
  p.kind = {0, 2};
  p.loop_index = {-1, 0};
  f.lcm.publish("HG_GRIND_PATH", &p);
  f.status("job-1", job_status_t::STATE_DONE, "hg-robot-bridge", "path complete");
  const std::string evil = "../../evil/\x01id";
  f.request(evil, "hull-Y");
  f.status(evil, job_status_t::STATE_REFUSED, "hg-robot-bridge", "refused: busy with job job-1");
  ASSERT_TRUE(
      f.wait([&] { return f.record_has("job-1", "state", "DONE") && f.record_has(evil, "state", "REFUSED"); }, 10s));
  EXPECT_TRUE(fs::exists(f.dir / "job-1" / "path.json"));
  EXPECT_TRUE(fs::exists(f.dir / "job-1" / "outline.json"));
  EXPECT_FALSE(fs::exists(f.dir.parent_path().parent_path() / "evil"));
  EXPECT_EQ(fs::canonical(f.dir / hg::job_recorder::job_dir_name(evil)).parent_path(), fs::canonical(f.dir));

  // A job running when the recorder is killed.
  f.request("job-2", "hull-Z");
  f.status("job-2", job_status_t::STATE_RUNNING, "hg-robot-bridge", "waypoint 3");
  ASSERT_TRUE(f.wait([&] { return f.record_has("job-2", "state", "RUNNING"); }, 10s));
  rec.kill_now();
  EXPECT_TRUE(f.record_has("job-2", "final", false));
  rec = f.start();
  ASSERT_GT(f.beats, 0) << "no heartbeat from the restarted hg-job-recorder";
  EXPECT_TRUE(f.record("job-2").contains("interrupted"));
  std::string list = hg_jobs(f, "list");
  EXPECT_NE(list.find("job-1"), std::string::npos) << list;
  EXPECT_NE(list.find("hull-X"), std::string::npos) << list;
  EXPECT_NE(list.find("interrupted (last RUNNING"), std::string::npos) << list;
  EXPECT_NE(hg_jobs(f, "list --part hull-X").find("path complete"), std::string::npos);
  EXPECT_EQ(hg_jobs(f, "list --part hull-X").find("job-2"), std::string::npos);
  const std::string show = hg_jobs(f, "show job-1");
  EXPECT_NE(show.find("state     DONE"), std::string::npos) << show;
  EXPECT_NE(show.find("2 waypoints"), std::string::npos) << show;
  EXPECT_NE(show.find("1 loops (0 holes)"), std::string::npos) << show;
  EXPECT_NE(hg_jobs(f, "show nope").find("no job 'nope'"), std::string::npos);

  // The restarted robot bridge reports how job-2 ended: the record ends there.
  f.status("job-2", job_status_t::STATE_ABORTED, "hg-robot-bridge", "restarted while job job-2 was running");
  ASSERT_TRUE(f.wait([&] { return f.record_has("job-2", "state", "ABORTED"); }, 10s));
  EXPECT_TRUE(f.record_has("job-2", "final", true));
  EXPECT_NE(hg_jobs(f, "show job-2").find("restarted while job job-2 was running"), std::string::npos);
  // A job still open at a clean stop is marked interrupted by the recorder itself.
  f.request("job-3", "hull-W");
  ASSERT_TRUE(f.wait([&] { return f.record_has("job-3", "requests", 1); }, 10s));
  EXPECT_EQ(rec.stop(), 0);
  EXPECT_TRUE(f.record("job-3").contains("interrupted"));
}

namespace {

// The bus's own word on how each job ended: the first status with a terminal state that is no answer (the
// robot bridge's DONE; any other terminal state from anyone), with when it came.
struct Ends {
  std::map<std::string, std::string> state;
  std::map<std::string, std::chrono::steady_clock::time_point> at;
  void on_status(const lcm::ReceiveBuffer*, const std::string&, const job_status_t* s) {
    const bool ends = (s->state == job_status_t::STATE_DONE && s->source == "hg-robot-bridge") ||
                      (hg::jobs::job_state_final(s->state) && s->state != job_status_t::STATE_DONE);
    if (s->answer || !ends || state.count(s->job_id)) return;
    state[s->job_id] = hg::jobs::job_state_name(s->state);
    at[s->job_id] = std::chrono::steady_clock::now();
  }
};

}  // namespace

TEST(JobRecorderProcess, AnEndPublishedWhileTheRecorderIsDownIsCaughtUp) {
  Fixture f;
  ASSERT_TRUE(f.lcm.good()) << "no LCM: the test must run inside tests/netns.sh";
  Ends ends;
  f.lcm.subscribe("HG_JOB_STATUS", &Ends::on_status, &ends);
  // The simulated cell approves a plan reaching every edge by itself: START, path, RUNNING, DONE ~0.5 s later.
  hg::test::ChildProcess bridge({std::string(HG_BIN_DIR) + "/hg-robot-bridge", "--driver", "sim", "--sim-time-scale",
                                 "10", "--cell", hg::test::sim_cell(), "--log-level", "error"});
  ASSERT_TRUE(bridge.started());
  auto rec = f.start();
  ASSERT_GT(f.beats, 0);
  int down_at_end = 0, jobs = 0;
  for (unsigned seed : {1u, 2u, 3u}) {
    std::mt19937 rng(seed);
    for (int i = 0; i < 8; ++i, ++jobs) {
      const std::string id = "k" + std::to_string(seed) + "-" + std::to_string(i);
      f.request(id, "part");
      ASSERT_TRUE(f.wait([&] { return f.record_has(id, "state", "ACCEPTED"); }, 10s)) << id;
      auto p = rbtest::make_path(id, {{0.5, 0, 0.2, 0.1, 0}, {0.7, 0, 0.2, 0.1, 2}, {0.5, 0, 0.3, 0.1, 4}});
      f.lcm.publish("HG_GRIND_PATH", &p);
      // RUNNING, or already DONE on a loaded machine (the run takes ~0.55 s and job.json holds the latest state).
      ASSERT_TRUE(
          f.wait([&] { return f.record_has(id, "state", "RUNNING") || f.record_has(id, "state", "DONE"); }, 10s))
          << id;
      // The run takes ~0.55 s: killed somewhere in its last 0.35 s or just after, down for 0.2..0.8 s.
      f.wait([] { return false; }, std::chrono::milliseconds(200 + rng() % 400));
      rec.kill_now();
      const auto killed = std::chrono::steady_clock::now();
      f.wait([] { return false; }, std::chrono::milliseconds(200 + rng() % 600));
      const auto restarted = std::chrono::steady_clock::now();
      if (ends.at.count(id) && ends.at[id] > killed && ends.at[id] < restarted) ++down_at_end;
      rec = f.start();
      ASSERT_TRUE(f.wait([&] { return ends.state.count(id) && f.record_has(id, "final", true); }, 10s))
          << id << ": " << f.record(id).dump();
      EXPECT_EQ(f.record(id)["state"], ends.state[id]) << id;
      EXPECT_EQ(ends.state[id], "DONE") << id;
    }
  }
  std::printf("%d of %d DONEs were published while the recorder was down\n", down_at_end, jobs);
  EXPECT_GT(down_at_end, jobs / 4);  // the catch-up was exercised, not only the live path
  for (const auto& [id, state] : ends.state) EXPECT_EQ(f.record(id)["state"], state) << id;
  EXPECT_EQ(rec.stop(), 0);
  EXPECT_EQ(bridge.stop(), 0);
}
