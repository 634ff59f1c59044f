// The job ledger every job-handling process keeps: the last state per job id, bounded, oldest forgotten.
#include <gtest/gtest.h>

#include <string>

#include "hullgrind/job_request_t.hpp"
#include "hullgrind/job_status_t.hpp"
#include "runtime/job_ledger.hpp"

using hg::runtime::JobLedger;
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
  EXPECT_EQ(hg::runtime::job_state_name(job_status_t::STATE_REFUSED), "REFUSED");
  EXPECT_EQ(hg::runtime::job_state_name(42), "42");
  for (std::int8_t s = 0; s < 8; ++s)
    EXPECT_EQ(hg::runtime::job_state_final(s), s >= job_status_t::STATE_DONE) << int(s);
  JobLedger::Entry e{"p", job_status_t::STATE_RUNNING, 0.25, "waypoint 12"};
  EXPECT_EQ(hg::runtime::repeat_answer(hullgrind::job_request_t::ACTION_START, "j", e),
            "repeated START of job j: it is RUNNING (waypoint 12); nothing done");
}
