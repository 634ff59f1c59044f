// hg-job-recorder on the bus (own network namespace) with tools/hg-jobs reading what it wrote: a job to DONE
// with its outline and path, a hostile job id kept inside the directory, and a job open when the recorder is
// killed (-9) shown as interrupted with its last state after a restart, then ended by a later status.
#include <gtest/gtest.h>

#include <lcm/lcm-cpp.hpp>

#include <chrono>
#include <csignal>
#include <cstdio>
#include <filesystem>
#include <fstream>
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
  int beats = 0;
  void on_beat(const lcm::ReceiveBuffer*, const std::string&, const hullgrind::heartbeat_t* b) {
    beats += b->process == "hg-job-recorder";
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
    wait([&] { return beats > 0; }, 10s);  // subscribed once it beats
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
