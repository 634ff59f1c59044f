// hg-path-planner on the bus (inside a private network namespace): outline + job request -> grind path
// and PLANNED; an error-status outline, a bad outline and garbage give error statuses and the process
// keeps running.
#include <algorithm>
#include <gtest/gtest.h>

#include <chrono>
#include <cmath>
#include <cstdio>
#include <filesystem>
#include <fstream>
#include <unistd.h>
#include <map>
#include <optional>

#include <lcm/lcm-cpp.hpp>

#include "hullgrind/grind_path_t.hpp"
#include "hullgrind/heartbeat_t.hpp"
#include "hullgrind/job_request_t.hpp"
#include "hullgrind/job_status_t.hpp"
#include "hullgrind/outline_t.hpp"
#include "runtime/node.hpp"
#include "tests/common/cell_file.hpp"
#include "tests/common/child_process.hpp"
#include "tests/path_planner/camera_plane.hpp"

using namespace std::chrono_literals;
using Clock = std::chrono::steady_clock;

namespace {

struct Bus {
  explicit Bus(lcm::LCM& lcm) {
    lcm.subscribe("HG_HEARTBEAT", &Bus::on_beat, this);
    lcm.subscribe("HG_GRIND_PATH", &Bus::on_path, this);
    lcm.subscribe("HG_JOB_STATUS", &Bus::on_status, this);
  }
  void on_beat(const lcm::ReceiveBuffer*, const std::string&, const hullgrind::heartbeat_t* m) { beats.push_back(*m); }
  void on_path(const lcm::ReceiveBuffer*, const std::string&, const hullgrind::grind_path_t* m) {
    paths.push_back(*m);
    order.push_back("path " + m->job_id + " " + std::to_string(m->revision));
  }
  void on_status(const lcm::ReceiveBuffer*, const std::string&, const hullgrind::job_status_t* m) {
    statuses.push_back(*m);
    if (m->state == hullgrind::job_status_t::STATE_PLANNED && !m->answer)
      order.push_back("planned " + m->job_id + " " + std::to_string(m->plan_revision));
  }
  std::vector<std::string> order;  // paths and PLANNED statuses as they came
  std::vector<hullgrind::heartbeat_t> beats;
  std::vector<hullgrind::grind_path_t> paths;
  std::vector<hullgrind::job_status_t> statuses;
};

hullgrind::outline_loop_t loop(bool hole, std::vector<std::pair<double, double>> pts) {
  hullgrind::outline_loop_t l{};
  l.hole = hole;
  l.n = int32_t(pts.size());
  for (auto [u, v] : pts) l.u.push_back(u), l.v.push_back(v);
  return l;
}

// 0.3 x 0.2 plate seen from a camera looking down (normal toward the camera), 1.19 m away, with a
// 60 x 40 mm cut-out.
hullgrind::outline_t plate_outline(std::int64_t seq) {
  hullgrind::outline_t o = hg::path_planner::test::outline_in_camera_plane(seq);
  o.loops.push_back(loop(false, {{0, 0}, {0.3, 0}, {0.3, 0.2}, {0, 0.2}}));
  // 60 x 40 mm cut-out with R8 corner fillets (every 22.5 deg): a round tool cannot reach into sharp ones.
  o.loops.push_back(
      loop(true, {{0.16, 0.088}, {0.159391, 0.0849385}, {0.1576569, 0.0823431}, {0.1550615, 0.080609}, {0.152, 0.08},
                  {0.108, 0.08}, {0.1049385, 0.080609}, {0.1023431, 0.0823431}, {0.100609, 0.0849385}, {0.1, 0.088},
                  {0.1, 0.112},  {0.100609, 0.1150615}, {0.1023431, 0.1176569}, {0.1049385, 0.119391}, {0.108, 0.12},
                  {0.152, 0.12}, {0.1550615, 0.119391}, {0.1576569, 0.1176569}, {0.159391, 0.1150615}, {0.16, 0.112}}));
  o.num_loops = 2;
  return o;
}

hullgrind::job_request_t start(const std::string& id) {
  hullgrind::job_request_t r{};
  r.job_id = id;
  r.part_id = "plate";
  r.action = +hullgrind::job_request_t::ACTION_START;
  r.tool_radius = 0.005;  // the rest zero: configured defaults
  return r;
}

class PathPlannerProcess : public testing::Test {
 protected:
  void SetUp() override {
    ASSERT_TRUE(lcm.good()) << "no LCM: the test must run inside tests/netns.sh";
    start_planner({});
  }
  void start_planner(const std::vector<std::string>& extra) {
    if (planner.started()) {
      ASSERT_EQ(planner.stop(), 0);
    }
    std::vector<std::string> cmd = {std::string(HG_BIN_DIR) + "/hg-path-planner", "--log-level", "warn",
                                    "--outline-max-age", "30", "--cell", hg::test::shipped_cell(),
                                    // no robot bridge acknowledges a path here: no copies (resend_test.cpp)
                                    "--path-resends", "0"};
    cmd.insert(cmd.end(), extra.begin(), extra.end());
    bus.beats.clear();
    planner = hg::test::ChildProcess(cmd);
    ASSERT_TRUE(planner.started());
    // Subscribed once it beats (this one: a beat of the one before may still be queued).
    const int pid = planner.pid();
    ASSERT_TRUE(wait_for([&] { return !bus.beats.empty() && bus.beats.back().pid == pid; }, 5s))
        << "no heartbeat from hg-path-planner";
  }
  int count(const std::string& id, std::int8_t state, bool answers) {
    int n = 0;
    for (const auto& m : bus.statuses) n += m.job_id == id && m.state == state && m.answer == answers;
    return n;
  }
  void TearDown() override {
    if (HasFailure())
      for (const auto& m : bus.statuses)
        std::fprintf(stderr, "status %s %s %d%s: %s\n", m.source.c_str(), m.job_id.c_str(), int(m.state),
                     m.answer ? " (answer)" : "", m.message.c_str());
    if (planner.started()) {
      EXPECT_EQ(planner.stop(), 0) << "unclean exit";
    }
  }
  template <class Pred>
  bool wait_for(Pred pred, std::chrono::milliseconds limit) {
    const auto end = Clock::now() + limit;
    while (Clock::now() < end) {
      if (pred()) return true;
      lcm.handleTimeout(20);
    }
    return pred();
  }
  std::optional<hullgrind::job_status_t> final_status(const std::string& id) {
    std::optional<hullgrind::job_status_t> s;
    wait_for(
        [&] {
          for (const auto& m : bus.statuses)
            if (m.job_id == id && m.state != hullgrind::job_status_t::STATE_PLANNING) {
              s = m;
              return true;
            }
          return false;
        },
        5s);
    return s;
  }
  lcm::LCM lcm{hg::runtime::default_lcm_url()};
  Bus bus{lcm};
  hg::test::ChildProcess planner;
};

}  // namespace

TEST_F(PathPlannerProcess, OutlineAndJobGivePathAndPlanned) {
  auto o = plate_outline(7);
  lcm.publish("HG_OUTLINE", &o);
  auto r = start("job-1");
  const auto sent = std::chrono::steady_clock::now();
  lcm.publish("HG_JOB_REQUEST", &r);
  const auto s = final_status("job-1");
  ASSERT_TRUE(s.has_value());
  EXPECT_EQ(s->state, +hullgrind::job_status_t::STATE_PLANNED) << s->message;
  EXPECT_EQ(s->source, "hg-path-planner");
  ASSERT_TRUE(wait_for([&] { return !bus.paths.empty(); }, 2s));
  const double request_to_path = std::chrono::duration<double>(std::chrono::steady_clock::now() - sent).count();
  const auto& p = bus.paths.front();
  // The planner's own compute time: some work, and within what this test waited from the request to the path.
  EXPECT_GT(p.compute_time, 0);
  EXPECT_LE(p.compute_time, request_to_path);
  EXPECT_EQ(p.job_id, "job-1");
  EXPECT_EQ(p.outline_seq, 7);
  EXPECT_EQ(p.frame, "robot_base");
  EXPECT_DOUBLE_EQ(p.tool_radius, 0.005);
  ASSERT_EQ(std::size_t(p.n), p.position.size());
  ASSERT_GT(p.n, 50);
  bool hole_ground = false, outer_ground = false;
  for (int i = 0; i < p.n; ++i) {
    double q = 0;
    for (double c : p.orientation[i]) q += c * c;
    EXPECT_NEAR(q, 1, 1e-9);
    if (p.kind[i] == hullgrind::grind_path_t::KIND_GRIND) {
      (p.loop_index[i] == 1 ? hole_ground : outer_ground) = true;
      // Plate (x, y) -> base (0.5 + x, y, 0.01) with the default hand-eye calibration.
      EXPECT_NEAR(p.position[i][2], 0.01, 1e-9);
    }
  }
  EXPECT_TRUE(hole_ground);
  EXPECT_TRUE(outer_ground);
  // The first revision, with the coverage of both loops: every edge reached by the 5 mm tool (R8 fillets).
  EXPECT_EQ(p.revision, 1);
  ASSERT_EQ(p.num_loops, 2);
  for (int k = 0; k < 2; ++k) {
    EXPECT_EQ(p.coverage[k].loop_index, k);
    EXPECT_EQ(p.coverage[k].hole, k == 1);
    EXPECT_TRUE(p.coverage[k].planned);
    EXPECT_NEAR(p.coverage[k].reached_length, p.coverage[k].edge_length, 1e-12);
  }
  EXPECT_NEAR(p.coverage[0].edge_length, 1.0, 1e-3);  // 2 x (0.3 + 0.2) m
  EXPECT_EQ(p.num_unreached, 0);
  // The smoothed edge the tool grinds: both loops, on the drawn rectangle and cut-out (0.5 m along x in the
  // base frame), in the plane of the plate.
  ASSERT_EQ(std::size_t(p.num_edge_points), p.edge.size());
  ASSERT_EQ(p.edge_loop.size(), p.edge.size());
  int per_loop[2] = {0, 0};
  for (int i = 0; i < p.num_edge_points; ++i) {
    const int k = p.edge_loop[i];
    ASSERT_TRUE(k == 0 || k == 1);
    ++per_loop[k];
    const double x = p.edge[i][0] - 0.5, y = p.edge[i][1];
    const double x0 = k == 0 ? 0 : 0.1, x1 = k == 0 ? 0.3 : 0.16, y0 = k == 0 ? 0 : 0.08, y1 = k == 0 ? 0.2 : 0.12;
    const double off_box = std::min({std::abs(x - x0), std::abs(x - x1), std::abs(y - y0), std::abs(y - y1)});
    EXPECT_TRUE(x > x0 - 1e-4 && x < x1 + 1e-4 && y > y0 - 1e-4 && y < y1 + 1e-4) << x << " " << y;
    if (k == 0) EXPECT_LT(off_box, 1e-4) << x << " " << y;  // the cut-out's fillets lie inside its box
    EXPECT_NEAR(p.edge[i][2], p.edge[0][2], 1e-9);
  }
  EXPECT_GE(per_loop[0], 4);
  EXPECT_GE(per_loop[1], 20);
  // PLANNING came before PLANNED, and PLANNED (revision 1) before the path.
  ASSERT_GE(bus.statuses.size(), 2u);
  EXPECT_EQ(bus.statuses.front().state, +hullgrind::job_status_t::STATE_PLANNING);
  EXPECT_EQ(s->plan_revision, 1);
  EXPECT_EQ(bus.order, (std::vector<std::string>{"planned job-1 1", "path job-1 1"}));
}

// REPLAN plans the job again on the outline it was planned on, as the next revision, and only while the robot
// bridge holds the plan awaiting approval.
TEST_F(PathPlannerProcess, ReplanGivesTheNextRevisionOnlyWhileAwaitingApproval) {
  auto o = plate_outline(21);
  lcm.publish("HG_OUTLINE", &o);
  auto r = start("job-r");
  lcm.publish("HG_JOB_REQUEST", &r);
  ASSERT_TRUE(wait_for([&] { return bus.paths.size() == 1; }, 5s));
  auto replan = r;
  replan.action = +hullgrind::job_request_t::ACTION_REPLAN;
  replan.tool_radius = 0.004;
  lcm.publish("HG_JOB_REQUEST", &replan);  // nobody said AWAITING_APPROVAL: refused
  ASSERT_TRUE(wait_for([&] { return count("job-r", hullgrind::job_status_t::STATE_PLANNED, true) == 1; }, 5s));
  EXPECT_NE(bus.statuses.back().message.find("not awaiting approval"), std::string::npos)
      << bus.statuses.back().message;
  auto other = plate_outline(22);  // a newer outline: the replan still uses the job's own
  for (auto& u : other.loops[1].u) u += 0.01;
  lcm.publish("HG_OUTLINE", &other);
  hullgrind::job_status_t held{};
  held.job_id = "job-r";
  held.source = "hg-robot-bridge";
  held.state = +hullgrind::job_status_t::STATE_AWAITING_APPROVAL;
  held.plan_revision = 1;
  lcm.publish("HG_JOB_STATUS", &held);
  lcm.publish("HG_JOB_REQUEST", &replan);
  ASSERT_TRUE(wait_for([&] { return bus.paths.size() == 2; }, 5s));
  const auto& p2 = bus.paths[1];
  EXPECT_EQ(p2.job_id, "job-r");
  EXPECT_EQ(p2.revision, 2);
  EXPECT_EQ(p2.outline_seq, 21);
  EXPECT_DOUBLE_EQ(p2.tool_radius, 0.004);
  EXPECT_EQ(bus.order.back(), "path job-r 2");
  EXPECT_EQ(bus.order[bus.order.size() - 2], "planned job-r 2");
  lcm.publish("HG_JOB_REQUEST", &replan);  // the bridge has not held revision 2 yet: refused
  ASSERT_TRUE(wait_for([&] { return count("job-r", hullgrind::job_status_t::STATE_PLANNED, true) == 2; }, 5s));
  wait_for([] { return false; }, 300ms);
  EXPECT_EQ(bus.paths.size(), 2u);
}

// --small-hole skip plans the rest of the part, and the skipped cut-out is an unground stretch of the plan
// (CAUSE_TOO_SMALL, its whole edge), so no auto-approval and no DONE can hide it.
TEST_F(PathPlannerProcess, ASkippedHoleIsAnUngroundStretchOfThePlan) {
  start_planner({"--small-hole", "skip"});
  auto o = plate_outline(31);
  o.loops.push_back(loop(true, {{0.22, 0.05}, {0.235, 0.05}, {0.235, 0.065}, {0.22, 0.065}}));  // 15 mm square
  o.num_loops = 3;
  lcm.publish("HG_OUTLINE", &o);
  auto r = start("job-s");
  r.tool_radius = 0.01;
  lcm.publish("HG_JOB_REQUEST", &r);
  ASSERT_TRUE(wait_for([&] { return !bus.paths.empty(); }, 5s));
  const auto& p = bus.paths[0];
  ASSERT_EQ(p.num_loops, 3);
  EXPECT_FALSE(p.coverage[2].planned);
  EXPECT_EQ(p.coverage[2].reached_length, 0);
  EXPECT_NE(p.coverage[2].reason.find("too small"), std::string::npos) << p.coverage[2].reason;
  int too_small = 0;
  for (const auto& u : p.unreached)
    if (u.loop_index == 2) {
      ++too_small;
      EXPECT_EQ(u.cause, +hullgrind::edge_stretch_t::CAUSE_TOO_SMALL);
      EXPECT_TRUE(u.hole);
      EXPECT_NEAR(u.length, p.coverage[2].edge_length, 1e-12);
    }
  EXPECT_EQ(too_small, 1);
  for (int i = 0; i < p.n; ++i) EXPECT_NE(p.loop_index[i], 2);
  const auto s = final_status("job-s");
  ASSERT_TRUE(s);
  EXPECT_EQ(s->num_unground, p.num_unreached);
}

// QUERY answers the planner's last status of each job (answer = true); the job history (--jobs-dir) keeps a
// job that ended from being planned again by a planner that never saw it.
TEST_F(PathPlannerProcess, QueryAndTheJobHistory) {
  namespace fs = std::filesystem;
  const fs::path jobs = fs::path(testing::TempDir()) / ("pp_jobs_" + std::to_string(getpid()));
  fs::create_directories(jobs / "old");
  std::ofstream(jobs / "old" / "job.json")
      << R"({"job_id": "old", "state": "INCOMPLETE", "final": true, "reason": "hole 2 unground", "requested_utime": 1})";
  start_planner({"--jobs-dir", jobs.string()});
  auto o = plate_outline(41);
  lcm.publish("HG_OUTLINE", &o);
  auto old = start("old");
  lcm.publish("HG_JOB_REQUEST", &old);
  ASSERT_TRUE(wait_for([&] { return count("old", hullgrind::job_status_t::STATE_INCOMPLETE, true) == 1; }, 5s));
  EXPECT_NE(bus.statuses.back().message.find("the job history holds it as INCOMPLETE"), std::string::npos);
  auto fresh = start("fresh");
  lcm.publish("HG_JOB_REQUEST", &fresh);
  ASSERT_TRUE(wait_for([&] { return bus.paths.size() == 1; }, 5s));
  EXPECT_EQ(bus.paths[0].job_id, "fresh");
  hullgrind::job_request_t query{};
  query.action = +hullgrind::job_request_t::ACTION_QUERY;
  lcm.publish("HG_JOB_REQUEST", &query);
  ASSERT_TRUE(wait_for([&] { return count("fresh", hullgrind::job_status_t::STATE_PLANNED, true) == 1; }, 5s));
  EXPECT_EQ(count("old", hullgrind::job_status_t::STATE_INCOMPLETE, false), 0);  // never its own state
  fs::remove_all(jobs);
}

TEST_F(PathPlannerProcess, ErrorOutlineBadOutlineAndGarbageGiveErrorStatuses) {
  // Garbage on both input channels: counted, skipped.
  const char junk[] = "not an lcm message at all";
  lcm.publish("HG_OUTLINE", junk, sizeof junk);
  lcm.publish("HG_JOB_REQUEST", junk, 5);

  auto bad = plate_outline(1);
  bad.status = +hullgrind::outline_t::STATUS_NO_LOOP;
  bad.error_text = "too few points on the plate";
  bad.loops.clear();
  bad.num_loops = 0;
  lcm.publish("HG_OUTLINE", &bad);
  auto r = start("job-err");
  lcm.publish("HG_JOB_REQUEST", &r);
  auto s = final_status("job-err");
  ASSERT_TRUE(s.has_value());
  EXPECT_EQ(s->state, +hullgrind::job_status_t::STATE_FAILED);
  EXPECT_NE(s->message.find("too few points on the plate"), std::string::npos) << s->message;

  // An outline whose scan quality is poor ends the job NEEDS_RESCAN with the reason, and no path (issue 23).
  auto poor = plate_outline(3);
  poor.quality = +hullgrind::outline_t::QUALITY_POOR;
  poor.quality_text = "42 % of the edge in dropout or shadow";
  lcm.publish("HG_OUTLINE", &poor);
  r = start("job-poor");
  lcm.publish("HG_JOB_REQUEST", &r);
  s = final_status("job-poor");
  ASSERT_TRUE(s.has_value());
  EXPECT_EQ(s->state, +hullgrind::job_status_t::STATE_NEEDS_RESCAN) << s->message;
  EXPECT_NE(s->message.find("scan quality poor, rescan: 42 % of the edge in dropout or shadow"), std::string::npos)
      << s->message;
  EXPECT_TRUE(bus.paths.empty()) << "no path on a poor scan";

  auto nan = plate_outline(2);
  nan.loops[1].u[2] = std::nan("");
  lcm.publish("HG_OUTLINE", &nan);
  r = start("job-nan");
  lcm.publish("HG_JOB_REQUEST", &r);
  s = final_status("job-nan");
  ASSERT_TRUE(s.has_value());
  EXPECT_EQ(s->state, +hullgrind::job_status_t::STATE_FAILED);
  EXPECT_NE(s->message.find("loop 1 point 2 is not finite"), std::string::npos) << s->message;

  // Out of range job parameters.
  auto good = plate_outline(3);
  lcm.publish("HG_OUTLINE", &good);
  r = start("job-neg");
  r.grind_speed = -1;
  lcm.publish("HG_JOB_REQUEST", &r);
  s = final_status("job-neg");
  ASSERT_TRUE(s.has_value());
  EXPECT_EQ(s->state, +hullgrind::job_status_t::STATE_FAILED);
  EXPECT_NE(s->message.find("grind_speed"), std::string::npos) << s->message;

  // More than the cell allows is refused at the job (the process keeps running): a speed above the cell's
  // max-speed (0.25), a tool larger than the cell's (10 mm).
  r = start("job-fast");
  r.travel_speed = 0.4;
  lcm.publish("HG_JOB_REQUEST", &r);
  s = final_status("job-fast");
  ASSERT_TRUE(s.has_value());
  EXPECT_EQ(s->state, +hullgrind::job_status_t::STATE_FAILED);
  EXPECT_NE(s->message.find("travel_speed 0.4 m/s exceeds " + hg::test::shipped_cell() + " max-speed 0.25"),
            std::string::npos)
      << s->message;
  r = start("job-big-tool");
  r.tool_radius = 0.012;
  lcm.publish("HG_JOB_REQUEST", &r);
  s = final_status("job-big-tool");
  ASSERT_TRUE(s.has_value());
  EXPECT_EQ(s->state, +hullgrind::job_status_t::STATE_FAILED);
  EXPECT_NE(s->message.find("tool_radius 0.012 m exceeds " + hg::test::shipped_cell() + " tool.radius 0.01"),
            std::string::npos)
      << s->message;

  // Still alive, still planning, and the garbage was counted.
  r = start("job-ok");
  lcm.publish("HG_JOB_REQUEST", &r);
  s = final_status("job-ok");
  ASSERT_TRUE(s.has_value());
  EXPECT_EQ(s->state, +hullgrind::job_status_t::STATE_PLANNED) << s->message;
  bus.beats.clear();
  ASSERT_TRUE(wait_for([&] { return !bus.beats.empty(); }, 3s));
  EXPECT_GE(bus.beats.back().decode_errors, 2);
  EXPECT_FALSE(planner.wait().has_value()) << "the planner died";
}

// A retrying writer repeats START with the same job id; another requester's job is interleaved. Each job id
// is planned once (one HG_GRIND_PATH per id), every repeat is answered with the job's state, and the ABORT of
// a planned job changes nothing here (the robot bridge holds it).
TEST_F(PathPlannerProcess, RepeatedStartPlansOncePerJobId) {
  auto o = plate_outline(11);
  lcm.publish("HG_OUTLINE", &o);
  auto a = start("job-a"), b = start("job-b");
  for (int i = 0; i < 10; ++i) {
    lcm.publish("HG_JOB_REQUEST", &a);
    lcm.publish("HG_JOB_REQUEST", &b);
  }
  auto planned = [&](const std::string& id) {
    int n = 0;
    for (const auto& s : bus.statuses) n += s.job_id == id && s.state == hullgrind::job_status_t::STATE_PLANNED;
    return n;
  };
  ASSERT_TRUE(wait_for([&] { return planned("job-a") >= 1 && planned("job-b") >= 1; }, 10s));
  // Both planned; then the repeats once more, and an ABORT of each, after they were planned.
  for (int i = 0; i < 10; ++i) {
    lcm.publish("HG_JOB_REQUEST", &a);
    lcm.publish("HG_JOB_REQUEST", &b);
  }
  auto abort = a;
  abort.action = +hullgrind::job_request_t::ACTION_ABORT;
  lcm.publish("HG_JOB_REQUEST", &abort);
  // A third job after all that, so that everything before it has been handled when its path comes.
  auto c = start("job-c");
  lcm.publish("HG_JOB_REQUEST", &c);
  ASSERT_TRUE(wait_for([&] { return planned("job-c") >= 1; }, 10s));
  wait_for([] { return false; }, 500ms);
  std::map<std::string, int> paths;
  for (const auto& p : bus.paths) ++paths[p.job_id];
  EXPECT_EQ(paths["job-a"], 1);
  EXPECT_EQ(paths["job-b"], 1);
  EXPECT_EQ(paths["job-c"], 1);
  EXPECT_EQ(paths.size(), 3u);
  EXPECT_EQ(planned("job-a"), 1);
  EXPECT_EQ(planned("job-b"), 1);
  for (const auto& s : bus.statuses)  // nothing aborted, refused or failed
    EXPECT_LE(s.state, +hullgrind::job_status_t::STATE_PLANNED) << s.job_id << ": " << s.message;
}

// A job waiting for its outline: a repeated START is answered PLANNING (not "busy"), a repeated ABORT
// after the first is answered ABORTED, and a START after the abort does not plan it.
TEST_F(PathPlannerProcess, RepeatedStartAndAbortOfAWaitingJobAnswerItsState) {
  auto w = start("job-w");
  for (int i = 0; i < 5; ++i) lcm.publish("HG_JOB_REQUEST", &w);
  auto count = [&](std::int8_t state) {
    int n = 0;
    for (const auto& s : bus.statuses) n += s.job_id == "job-w" && s.state == state;
    return n;
  };
  ASSERT_TRUE(wait_for([&] { return count(hullgrind::job_status_t::STATE_PLANNING) >= 5; }, 5s));
  EXPECT_EQ(count(hullgrind::job_status_t::STATE_REFUSED), 0);
  auto abort = w;
  abort.action = +hullgrind::job_request_t::ACTION_ABORT;
  for (int i = 0; i < 5; ++i) lcm.publish("HG_JOB_REQUEST", &abort);
  ASSERT_TRUE(wait_for([&] { return count(hullgrind::job_status_t::STATE_ABORTED) >= 5; }, 5s));
  lcm.publish("HG_JOB_REQUEST", &w);
  auto o = plate_outline(12);
  lcm.publish("HG_OUTLINE", &o);
  ASSERT_TRUE(wait_for([&] { return count(hullgrind::job_status_t::STATE_ABORTED) >= 6; }, 5s));
  wait_for([] { return false; }, 500ms);
  EXPECT_TRUE(bus.paths.empty()) << "an aborted job was planned";
  EXPECT_EQ(count(hullgrind::job_status_t::STATE_PLANNING), 5);
  EXPECT_EQ(count(hullgrind::job_status_t::STATE_PLANNED), 0);
}
