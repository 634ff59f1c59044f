// The job ledger every job-handling process keeps: the last state per job id, bounded, oldest forgotten.
#include <gtest/gtest.h>

#include <filesystem>
#include <fstream>
#include <set>
#include <unistd.h>

#include <string>

#include "hullgrind/job_request_t.hpp"
#include "hullgrind/job_status_t.hpp"
#include "jobs/job_ledger.hpp"

using hg::jobs::JobLedger;
using hullgrind::job_status_t;

TEST(JobLedger, KeepsTheLastStateAndTheFirstPartName) {
  JobLedger l;
  EXPECT_EQ(l.find("a"), nullptr);
  l.set("a", "plate-7", job_status_t::STATE_ACCEPTED, 0, "accepted");
  l.set("a", "", job_status_t::STATE_RUNNING, 0.5, "waypoint 3");
  const JobLedger::Entry* e = l.find("a");
  ASSERT_NE(e, nullptr);
  EXPECT_EQ(e->state, +job_status_t::STATE_RUNNING);
  EXPECT_EQ(e->progress, 0.5);
  EXPECT_EQ(e->message, "waypoint 3");
  EXPECT_EQ(e->part_id, "plate-7");  // a status without a part name keeps the one known
  EXPECT_EQ(l.find("b"), nullptr);
  EXPECT_EQ(l.size(), 1u);
}

TEST(JobLedger, ForgetsTheOldestIdsBeyondItsCapacity) {
  JobLedger l(100);
  for (int i = 0; i < 1000; ++i) {
    l.set("job-" + std::to_string(i), "", job_status_t::STATE_DONE, 1, "");
    l.set("job-" + std::to_string(i), "", job_status_t::STATE_DONE, 1, "");  // an update is not a new id
  }
  EXPECT_EQ(l.size(), 100u);
  for (int i = 0; i < 1000; ++i) EXPECT_EQ(l.find("job-" + std::to_string(i)) != nullptr, i >= 900) << i;
}

TEST(JobLedger, NamesAndAnswers) {
  EXPECT_EQ(hg::jobs::job_state_name(job_status_t::STATE_REFUSED), "REFUSED");
  EXPECT_EQ(hg::jobs::job_state_name(42), "42");
  // Terminal: DONE, FAILED, ABORTED, REFUSED, INCOMPLETE, REJECTED, NEEDS_RESCAN (lcmtypes/job_status_t.lcm).
  const std::set<int> terminal = {4, 5, 6, 7, 10, 11, 12};
  for (std::int8_t s = 0; s < 13; ++s) {
    EXPECT_EQ(hg::jobs::job_state_final(s), terminal.count(s) == 1) << int(s);
    EXPECT_EQ(hg::jobs::job_state_of_name(hg::jobs::job_state_name(s)), s);
  }
  EXPECT_EQ(hg::jobs::job_state_name(job_status_t::STATE_AWAITING_APPROVAL), "AWAITING_APPROVAL");
  EXPECT_EQ(hg::jobs::job_state_name(job_status_t::STATE_INCOMPLETE), "INCOMPLETE");
  EXPECT_EQ(hg::jobs::job_state_of_name("interrupted"), -1);
  EXPECT_EQ(hg::jobs::job_action_name(hullgrind::job_request_t::ACTION_APPROVE), "APPROVE");
  EXPECT_EQ(hg::jobs::job_action_name(hullgrind::job_request_t::ACTION_QUERY), "QUERY");
  JobLedger::Entry e{"p", job_status_t::STATE_RUNNING, 0.25, "waypoint 12"};
  EXPECT_EQ(hg::jobs::repeat_answer(hullgrind::job_request_t::ACTION_START, "j", e),
            "repeated START of job j: it is RUNNING (waypoint 12); nothing done");
}

// The job history as the processes read it across restarts: job.json's state, final and first request time.
TEST(JobLedger, RecordedJobsComeFromTheHistoryFolder) {
  namespace fs = std::filesystem;
  const fs::path root = fs::path(::testing::TempDir()) / ("ledger_jobs_" + std::to_string(getpid()));
  fs::create_directories(root / "a%2Fb");
  std::ofstream(root / "a%2Fb" / "job.json")
      << R"({"job_id": "a/b", "state": "INCOMPLETE", "final": true, "reason": "hole 2", "requested_utime": 5})";
  fs::create_directories(root / "open");
  std::ofstream(root / "open" / "job.json")
      << R"({"job_id": "open", "state": "RUNNING", "final": false, "message": "waypoint 3", "requested_utime": 10000000})";
  fs::create_directories(root / "bad");
  std::ofstream(root / "bad" / "job.json") << "{not json";
  const auto ended = hg::jobs::recorded_job(root.string(), "a/b");
  ASSERT_TRUE(ended);
  EXPECT_EQ(ended->state, +job_status_t::STATE_INCOMPLETE);
  EXPECT_TRUE(ended->ended);
  EXPECT_EQ(ended->message, "hole 2");
  EXPECT_TRUE(hg::jobs::recorded_before(ended, 0));
  const auto open = hg::jobs::recorded_job(root.string(), "open");
  ASSERT_TRUE(open);
  EXPECT_FALSE(open->ended);
  EXPECT_FALSE(hg::jobs::recorded_before(open, 10500000));  // the same START, heard by the recorder first
  EXPECT_TRUE(hg::jobs::recorded_before(open, 11000001));   // a START more than a second later
  EXPECT_FALSE(hg::jobs::recorded_job(root.string(), "bad"));
  EXPECT_FALSE(hg::jobs::recorded_job(root.string(), "none"));
  EXPECT_FALSE(hg::jobs::recorded_job("", "a/b"));  // jobs-dir off
  fs::remove_all(root);
}
