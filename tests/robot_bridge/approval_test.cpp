// The approval step of the robot bridge on the simulated robot (the test's own clock): nothing reaches the
// robot before APPROVED; the cell's auto policy approves only a plan reaching every edge; exclusions take the
// loops' waypoints out and are checked again; REJECT, ABORT in every state the bridge holds, answers for
// unknown and ended jobs, a REPLAN's new revision, QUERY; DONE only when every loop not excluded was reached.
#include <gtest/gtest.h>

#include <algorithm>
#include <filesystem>
#include <fstream>
#include <random>
#include <set>

#include "harness.hpp"

using namespace rbtest;
using hullgrind::edge_stretch_t;
using hullgrind::grind_path_t;

namespace {

BridgeConfig operator_cfg() { return BridgeConfig{}; }  // the default: every plan waits for an operator

const std::vector<LoopSpec> kThree = {{0.40, 0.0}, {0.50, 0.0}, {0.60, 0.0}};

// Ticks of robot_status_t in which the robot moved or ran (anything but idle at home).
bool robot_moved(const Harness& h) {
  for (const auto& r : h.robot)
    if (r.mode == robot_status_t::MODE_RUNNING || r.tcp_position[0] != 0.5 || r.tcp_position[2] != 0.3) return true;
  return false;
}

int count_state(const Harness& h, const std::string& job, std::int8_t state, bool answers = false) {
  return int(std::count_if(h.statuses.begin(), h.statuses.end(), [&](const job_status_t& s) {
    return s.job_id == job && s.state == state && s.answer == answers;
  }));
}

// The states the bridge published for a job (not answers), in order.
std::vector<int> states_of(const Harness& h, const std::string& job) {
  std::vector<int> out;
  for (const auto& s : h.statuses)
    if (s.job_id == job && !s.answer && (out.empty() || out.back() != s.state)) out.push_back(s.state);
  return out;
}

}  // namespace

TEST(RobotBridgeApproval, AnOperatorCellHoldsEveryPlanUntilApproved) {
  Harness h({}, operator_cfg());
  h.send("j", job_request_t::ACTION_START);
  h.path(loops_path("j", kThree));  // reaches every edge: still an operator's decision here
  ASSERT_EQ(h.last().state, +job_status_t::STATE_AWAITING_APPROVAL) << h.last().message;
  EXPECT_EQ(h.last().plan_revision, 1);
  EXPECT_EQ(h.last().num_unground, 0);
  EXPECT_EQ(h.bridge->state(), Bridge::State::Awaiting);
  h.tick(3000);  // 30 s: nothing moves on its own
  EXPECT_FALSE(robot_moved(h));
  EXPECT_EQ(count_state(h, "j", job_status_t::STATE_RUNNING), 0);
  // Refused approvals are answers: the job still awaits, nothing moves.
  h.send(approval("j", ""));
  EXPECT_EQ(h.last().state, +job_status_t::STATE_AWAITING_APPROVAL);
  EXPECT_TRUE(h.last().answer);
  EXPECT_NE(h.last().message.find("names who approves"), std::string::npos) << h.last().message;
  h.send(approval("j", "ann", {}, 2));
  EXPECT_TRUE(h.last().answer);
  EXPECT_NE(h.last().message.find("revision 2 is not the plan held (revision 1)"), std::string::npos)
      << h.last().message;
  h.send(approval("j", "ann", {7}));
  EXPECT_NE(h.last().message.find("loop 7 is not a loop"), std::string::npos) << h.last().message;
  h.tick(100);
  EXPECT_FALSE(robot_moved(h));
  h.send(approval("j", "ann", {}, 1));
  ASSERT_TRUE(h.run_until("j", job_status_t::STATE_DONE)) << h.last().message;
  EXPECT_EQ(states_of(h, "j"),
            (std::vector<int>{job_status_t::STATE_ACCEPTED, job_status_t::STATE_AWAITING_APPROVAL,
                              job_status_t::STATE_APPROVED, job_status_t::STATE_RUNNING, job_status_t::STATE_DONE}));
  EXPECT_EQ(h.last().actor, "operator ann");
  EXPECT_EQ(h.last().num_unground, 0);
  EXPECT_EQ(h.last().message, "path complete");
}

TEST(RobotBridgeApproval, AutoPolicyApprovesOnlyAPlanReachingEveryEdge) {
  const std::int8_t causes[] = {edge_stretch_t::CAUSE_UNREACHED, edge_stretch_t::CAUSE_TOO_SMALL,
                                edge_stretch_t::CAUSE_CORNER};
  for (std::int8_t cause : causes) {
    Harness h;  // approval: auto
    h.send("g", job_request_t::ACTION_START);
    grind_path_t p = loops_path("g", kThree);
    leave_unground(p, 2, 0.004, cause);
    h.path(p);
    ASSERT_EQ(h.last().state, +job_status_t::STATE_AWAITING_APPROVAL) << int(cause) << h.last().message;
    ASSERT_EQ(h.last().num_unground, 1);
    EXPECT_EQ(h.last().unground[0].loop_index, 2);
    EXPECT_EQ(h.last().unground[0].cause, cause);
    EXPECT_NE(h.last().message.find("hole 2: 4.0 mm"), std::string::npos) << h.last().message;
    h.tick(500);
    EXPECT_FALSE(robot_moved(h));
  }
  Harness h;
  h.send("f", job_request_t::ACTION_START);
  h.path(loops_path("f", kThree));
  EXPECT_EQ(states_of(h, "f"), (std::vector<int>{job_status_t::STATE_ACCEPTED, job_status_t::STATE_APPROVED,
                                                 job_status_t::STATE_RUNNING}));
  EXPECT_EQ(h.last().actor, "policy auto");
  ASSERT_TRUE(h.run_until("f", job_status_t::STATE_DONE));
}

// Property over seeds: random plans (2..5 loops, random unreached stretches on random loops), approved with a
// random set of exclusions. Expected independently: DONE exactly when every loop with an unreached stretch is
// excluded; unground lists each unreached stretch of a loop not excluded and each excluded loop, nothing else.
TEST(RobotBridgeApproval, AJobWithAnUngroundEdgeNobodyExcludedNeverEndsDone) {
  std::mt19937 rng(22);
  for (int seed = 0; seed < 40; ++seed) {
    const int loops = 2 + int(rng() % 4);
    std::vector<LoopSpec> specs;
    for (int k = 0; k < loops; ++k) specs.push_back({0.35 + 0.08 * k, 0.0});
    grind_path_t p = loops_path("p", specs);
    std::set<int> gaps, excluded;
    for (int k = 0; k < loops; ++k)
      if (rng() % 3 == 0)
        leave_unground(p, k, 0.001 * (1 + rng() % 9), edge_stretch_t::CAUSE_UNREACHED), gaps.insert(k);
    for (int k = 1; k < loops; ++k)  // loop 0 always ground: something is left to run
      if (rng() % 3 == 0) excluded.insert(k);
    Harness h;
    h.send("p", job_request_t::ACTION_START);
    h.path(p);
    if (gaps.empty()) {
      ASSERT_EQ(h.last().state, +job_status_t::STATE_RUNNING) << seed;  // auto-approved
    } else {
      ASSERT_EQ(h.last().state, +job_status_t::STATE_AWAITING_APPROVAL) << seed;
      h.send(approval("p", "bo", std::vector<std::int16_t>(excluded.begin(), excluded.end())));
      ASSERT_EQ(h.last().state, +job_status_t::STATE_RUNNING) << seed << h.last().message;
    }
    ASSERT_TRUE(h.run_until("p", job_status_t::STATE_DONE) || h.run_until("p", job_status_t::STATE_INCOMPLETE, 1))
        << seed;
    const bool all_excluded = gaps.empty() || std::includes(excluded.begin(), excluded.end(), gaps.begin(), gaps.end());
    const job_status_t& end = h.last();
    EXPECT_EQ(end.state, all_excluded ? +job_status_t::STATE_DONE : +job_status_t::STATE_INCOMPLETE) << seed;
    std::multiset<std::pair<int, int>> expected, got;  // (loop, cause)
    if (!gaps.empty())
      for (int k : excluded) expected.insert({k, edge_stretch_t::CAUSE_EXCLUDED});
    for (int k : gaps)
      if (!excluded.count(k) || gaps.empty()) expected.insert({k, edge_stretch_t::CAUSE_UNREACHED});
    for (const auto& s : end.unground) got.insert({s.loop_index, s.cause});
    EXPECT_EQ(got, expected) << seed << ": " << end.message;
    if (end.state == job_status_t::STATE_INCOMPLETE)
      for (int k : gaps)
        if (!excluded.count(k))
          EXPECT_NE(end.message.find((k == 0 ? "outer loop " : "hole ") + std::to_string(k) + ":"), std::string::npos)
              << seed << ": " << end.message;
  }
}

TEST(RobotBridgeApproval, ExcludedLoopsAreNotRunAndTheRestIsCheckedAgain) {
  Harness h({}, operator_cfg());
  h.send("x", job_request_t::ACTION_START);
  grind_path_t p = loops_path("x", kThree);
  h.path(p);
  h.send(approval("x", "cy", {1}));
  ASSERT_EQ(h.last().state, +job_status_t::STATE_RUNNING) << h.last().message;
  ASSERT_TRUE(h.run_until("x", job_status_t::STATE_DONE));
  // Loop 1's square (x in [0.50, 0.52], z = 0.1) was never visited: the robot reports kept to the other loops.
  for (const auto& r : h.robot)
    EXPECT_FALSE(r.tcp_position[0] > 0.495 && r.tcp_position[0] < 0.525 && r.tcp_position[2] < 0.1 + 1e-6)
        << r.tcp_position[0] << " " << r.tcp_position[2];
  EXPECT_EQ(h.last().message, "path complete; loops 1 excluded by operator cy at approval");
  ASSERT_EQ(h.last().num_unground, 1);
  EXPECT_EQ(h.last().unground[0].cause, +edge_stretch_t::CAUSE_EXCLUDED);
  EXPECT_NEAR(h.last().unground[0].length, 0.08, 1e-12);
  EXPECT_EQ(h.last().excluded_loops, (std::vector<std::int16_t>{1}));
  EXPECT_EQ(h.last().actor, "operator cy");
  // The trimmed path is checked again: here loop 2 is entered from 3 cm below the safe height, straight below
  // loop 0's retract, which without loop 1 reverses the retract (a corner no acceleration can take).
  Harness g({}, operator_cfg());
  g.send("y", job_request_t::ACTION_START);
  g.path(loops_path("y", {{0.40, 0.0}, {0.50, 0.0}, {0.40, 0.0, 0.12}}));
  ASSERT_EQ(g.last().state, +job_status_t::STATE_AWAITING_APPROVAL) << g.last().message;
  g.send(approval("y", "cy", {1}));
  EXPECT_EQ(g.last().state, +job_status_t::STATE_AWAITING_APPROVAL);
  EXPECT_TRUE(g.last().answer);
  EXPECT_NE(g.last().message.find("fails the cell's check"), std::string::npos) << g.last().message;
  g.send(approval("y", "cy", {0, 1, 2}));
  EXPECT_NE(g.last().message.find("nothing left to grind"), std::string::npos) << g.last().message;
  g.tick(200);
  EXPECT_FALSE(robot_moved(g));
  g.send(approval("y", "cy"));  // the whole plan is fine
  EXPECT_TRUE(g.run_until("y", job_status_t::STATE_DONE));
}

TEST(RobotBridgeApproval, RejectEndsTheJobAndLaterActionsAreAnswered) {
  Harness h({}, operator_cfg());
  h.send("r", job_request_t::ACTION_START);
  h.path(loops_path("r", kThree));
  job_request_t rej = request("r", job_request_t::ACTION_REJECT);
  rej.actor = "operator dee";
  h.send(rej);
  EXPECT_EQ(h.last().state, +job_status_t::STATE_REJECTED);
  EXPECT_FALSE(h.last().answer);
  EXPECT_EQ(h.last().actor, "operator dee");
  EXPECT_EQ(h.bridge->state(), Bridge::State::Idle);
  for (std::int8_t a : {job_request_t::ACTION_APPROVE, job_request_t::ACTION_REJECT, job_request_t::ACTION_START,
                        job_request_t::ACTION_ABORT, job_request_t::ACTION_REPLAN}) {
    job_request_t r = request("r", a);
    r.actor = "operator dee";
    h.send(r);
    EXPECT_EQ(h.last().state, +job_status_t::STATE_REJECTED) << int(a);
    EXPECT_TRUE(h.last().answer) << int(a);
  }
  h.path(loops_path("r", kThree));  // a plan for an ended job never runs
  h.tick(300);
  EXPECT_FALSE(robot_moved(h));
  EXPECT_EQ(count_state(h, "r", job_status_t::STATE_REJECTED), 1);
  // Unknown jobs: answered, nothing recorded, nothing changes.
  for (std::int8_t a : {job_request_t::ACTION_APPROVE, job_request_t::ACTION_REJECT, job_request_t::ACTION_REPLAN}) {
    h.send(request("ghost", a));
    EXPECT_EQ(h.last().state, +job_status_t::STATE_REFUSED);
    EXPECT_TRUE(h.last().answer);
    EXPECT_NE(h.last().message.find("no such job"), std::string::npos) << h.last().message;
  }
  EXPECT_EQ(h.bridge->ledger().find("ghost"), nullptr);
  h.send("s", job_request_t::ACTION_START);  // the bridge is free
  EXPECT_EQ(h.last().state, +job_status_t::STATE_ACCEPTED);
}

TEST(RobotBridgeApproval, AbortWorksInEveryStateTheBridgeHolds) {
  enum Stage { Accepted, Awaiting, Running };
  for (Stage stage : {Accepted, Awaiting, Running}) {
    Harness h({}, operator_cfg());
    h.send("a", job_request_t::ACTION_START);
    if (stage != Accepted) h.path(loops_path("a", kThree));
    if (stage == Running) h.send(approval("a", "eve"));
    h.tick(50);
    job_request_t abort = request("a", job_request_t::ACTION_ABORT);
    abort.actor = "operator eve";
    h.send(abort);
    EXPECT_EQ(h.last().state, +job_status_t::STATE_ABORTED) << stage;
    EXPECT_FALSE(h.last().answer);
    EXPECT_NE(h.last().message.find("aborted by operator eve"), std::string::npos) << h.last().message;
    EXPECT_EQ(h.bridge->state(), Bridge::State::Idle);
    h.send(approval("a", "eve"));  // too late: answered ABORTED
    EXPECT_EQ(h.last().state, +job_status_t::STATE_ABORTED);
    EXPECT_TRUE(h.last().answer);
    const double x = h.robot.back().tcp_position[0];
    h.tick(300);
    EXPECT_EQ(h.robot.back().tcp_position[0], x);
    EXPECT_EQ(robot_moved(h), stage == Running) << stage;
  }
}

TEST(RobotBridgeApproval, ANewRevisionReplacesTheHeldPlan) {
  Harness h({}, operator_cfg());
  h.send("v", job_request_t::ACTION_START);
  grind_path_t first = loops_path("v", kThree);
  leave_unground(first, 1, 0.01, edge_stretch_t::CAUSE_UNREACHED);
  h.path(first);
  ASSERT_EQ(h.last().plan_revision, 1);
  grind_path_t second = loops_path("v", {{0.40, 0.0}, {0.60, 0.0}});
  second.revision = 2;
  h.path(second);  // the planner's answer to a REPLAN
  EXPECT_EQ(h.last().state, +job_status_t::STATE_AWAITING_APPROVAL);
  EXPECT_EQ(h.last().plan_revision, 2);
  EXPECT_EQ(h.last().num_unground, 0);
  EXPECT_EQ(h.bridge->held_plan().n, second.n);
  h.path(first);  // an old revision is ignored
  EXPECT_TRUE(h.last().answer);
  EXPECT_EQ(h.bridge->held_plan().revision, 2);
  h.send(approval("v", "fay", {}, 1));  // the operator saw revision 1: refused
  EXPECT_TRUE(h.last().answer);
  h.send(approval("v", "fay", {}, 2));
  ASSERT_TRUE(h.run_until("v", job_status_t::STATE_DONE));
  EXPECT_EQ(h.last().plan_revision, 2);
  for (const auto& r : h.robot)  // revision 1's loop at x = 0.50 was not ground
    EXPECT_FALSE(r.tcp_position[0] > 0.495 && r.tcp_position[0] < 0.525 && r.tcp_position[2] < 0.1 + 1e-6);
}

// The planner publishes a path again until the bridge acknowledges it (docs/path_planner.md, "Path delivery"):
// the first copy the bridge sees is taken (the ones before lost on the bus); every later copy is answered
// (answer = true) with the job's state and the revision held, so it acknowledges, and never runs twice.
TEST(RobotBridgeApproval, CopiesOfAPathAreAnsweredWithTheRevisionHeldAndNeverRun) {
  Harness h({}, operator_cfg());
  h.send("c", job_request_t::ACTION_START);
  const grind_path_t p = loops_path("c", kThree);
  h.path(p);
  ASSERT_EQ(h.last().state, +job_status_t::STATE_AWAITING_APPROVAL) << h.last().message;
  EXPECT_FALSE(h.last().answer);
  h.path(p);
  EXPECT_TRUE(h.last().answer);
  EXPECT_EQ(h.last().state, +job_status_t::STATE_AWAITING_APPROVAL);
  EXPECT_EQ(h.last().plan_revision, 1);
  EXPECT_NE(h.last().message.find("ignored: it is AWAITING_APPROVAL"), std::string::npos) << h.last().message;
  EXPECT_EQ(count_state(h, "c", job_status_t::STATE_AWAITING_APPROVAL), 1);
  h.send(approval("c", "fay", {}, 1));
  h.tick(10);
  h.path(p);
  EXPECT_TRUE(h.last().answer);
  EXPECT_EQ(h.last().state, +job_status_t::STATE_RUNNING);
  EXPECT_EQ(h.last().plan_revision, 1);
  ASSERT_TRUE(h.run_until("c", job_status_t::STATE_DONE));
  h.path(p);  // after the end: the end, a terminal state
  EXPECT_TRUE(h.last().answer);
  EXPECT_EQ(h.last().state, +job_status_t::STATE_DONE);
  int runs = 0;
  for (std::size_t i = 0; i < h.robot.size(); ++i)
    runs += h.robot[i].mode == robot_status_t::MODE_RUNNING &&
            (i == 0 || h.robot[i - 1].mode != robot_status_t::MODE_RUNNING);
  EXPECT_EQ(runs, 1);
  EXPECT_EQ(states_of(h, "c"),
            (std::vector<int>{job_status_t::STATE_ACCEPTED, job_status_t::STATE_AWAITING_APPROVAL,
                              job_status_t::STATE_APPROVED, job_status_t::STATE_RUNNING, job_status_t::STATE_DONE}));
}

TEST(RobotBridgeApproval, QueryAnswersTheLastStatusOfEveryJobHeld) {
  Harness h({}, operator_cfg());
  h.send("q1", job_request_t::ACTION_START);
  h.path(loops_path("q1", kThree));
  job_request_t rej = request("q1", job_request_t::ACTION_REJECT);
  rej.actor = "operator gil";
  h.send(rej);
  h.send("q2", job_request_t::ACTION_START);
  grind_path_t p = loops_path("q2", kThree);
  leave_unground(p, 2, 0.003, edge_stretch_t::CAUSE_CORNER);
  h.path(p);
  const std::size_t before = h.statuses.size();
  h.send(request("", job_request_t::ACTION_QUERY));
  ASSERT_EQ(h.statuses.size(), before + 2);
  const job_status_t a = h.statuses[before], b = h.statuses[before + 1];
  EXPECT_TRUE(a.answer && b.answer);
  EXPECT_EQ(a.job_id, "q1");
  EXPECT_EQ(a.state, +job_status_t::STATE_REJECTED);
  EXPECT_EQ(a.actor, "operator gil");
  EXPECT_EQ(b.job_id, "q2");
  EXPECT_EQ(b.state, +job_status_t::STATE_AWAITING_APPROVAL);
  ASSERT_EQ(b.num_unground, 1);
  EXPECT_EQ(b.unground[0].cause, +edge_stretch_t::CAUSE_CORNER);
  h.send(request("q1", job_request_t::ACTION_QUERY));
  EXPECT_EQ(h.statuses.size(), before + 3);
  EXPECT_EQ(h.last().state, +job_status_t::STATE_REJECTED);
  h.send(request("never", job_request_t::ACTION_QUERY));  // not held: nothing to say
  EXPECT_EQ(h.statuses.size(), before + 3);
  EXPECT_EQ(h.bridge->state(), Bridge::State::Awaiting);  // a query changes nothing
}

TEST(RobotBridgeApproval, TheJobHistoryKeepsAnEndedJobFromRunningAgain) {
  namespace fs = std::filesystem;
  const fs::path jobs = fs::path(::testing::TempDir()) / ("rb_jobs_" + std::to_string(getpid()));
  fs::create_directories(jobs / "old");
  std::ofstream(jobs / "old" / "job.json")
      << R"({"job_id": "old", "state": "DONE", "final": true, "reason": "path complete", "requested_utime": 1})";
  BridgeConfig cfg = auto_cfg();
  cfg.jobs_dir = jobs.string();
  Harness h({}, cfg);
  h.send("old", job_request_t::ACTION_START);
  EXPECT_EQ(h.last().state, +job_status_t::STATE_DONE);
  EXPECT_TRUE(h.last().answer);
  EXPECT_NE(h.last().message.find("job history holds it as DONE"), std::string::npos) << h.last().message;
  EXPECT_EQ(h.bridge->state(), Bridge::State::Idle);
  h.path(loops_path("old", kThree));
  h.tick(300);
  EXPECT_FALSE(robot_moved(h));
  h.send("new", job_request_t::ACTION_START);  // an id the history does not hold runs
  EXPECT_EQ(h.last().state, +job_status_t::STATE_ACCEPTED);
  fs::remove_all(jobs);
}

// The bridge runs a path only in the cell's base frame (frames.base, BridgeConfig::frame): a path in another
// frame is REFUSED before anything moves, naming both frames; the same path in the configured frame runs.
TEST(RobotBridgeApproval, APathInAnotherFrameIsRefusedAndNothingMoves) {
  for (const std::string base : {"robot_base", "ur10e/base_link"}) {
    BridgeConfig cfg = auto_cfg();
    cfg.frame = base;
    for (const std::string frame : {std::string("camera"), std::string(""), std::string("robot_base"), base}) {
      SCOPED_TRACE(base + " / " + frame);
      Harness h({}, cfg);
      h.send("fr", job_request_t::ACTION_START);
      grind_path_t p = loops_path("fr", kThree);
      p.frame = frame;
      h.path(p);
      if (frame == base) {
        EXPECT_TRUE(h.run_until("fr", job_status_t::STATE_DONE)) << h.last().message;
        continue;
      }
      EXPECT_EQ(h.last().state, +job_status_t::STATE_REFUSED) << h.last().message;
      EXPECT_NE(h.last().message.find("the path is in frame '" + frame + "', not the cell's base frame '" + base +
                                      "' (frames.base)"),
                std::string::npos)
          << h.last().message;
      h.tick(200);
      EXPECT_FALSE(robot_moved(h));
    }
  }
}
