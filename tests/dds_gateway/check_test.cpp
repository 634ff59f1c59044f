// check_job_request at its boundaries: what a plant system may send, and what it is told otherwise.
#include <gtest/gtest.h>

#include <cmath>
#include <iterator>
#include <limits>
#include <string>

#include "dds_gateway/convert.hpp"
#include "runtime/quantities.hpp"

using hg::dds_gateway::check_job_request;
using hg::dds_gateway::JobLimits;

namespace {

struct Req {
  std::string job_id = "J-1", part_id = "plate", frame = "";
  hgdds_JobRequest r{};
  Req() { refresh(); }
  hgdds_JobRequest& refresh() {
    r.job_id = job_id.data();
    r.part_id = part_id.data();
    r.header.frame_id = frame.data();
    return r;
  }
};

double above(double v) { return std::nextafter(v, std::numeric_limits<double>::infinity()); }
double below(double v) { return std::nextafter(v, -std::numeric_limits<double>::infinity()); }

TEST(DdsGatewayCheck, AllDefaultsAndEveryIdCharacterAreAccepted) {
  Req q;
  q.job_id = "Az09._:-";
  EXPECT_EQ(check_job_request(q.refresh(), JobLimits{}), "");
  q.job_id = std::string(64, 'x');
  EXPECT_EQ(check_job_request(q.refresh(), JobLimits{}), "");
  q.job_id = std::string(65, 'x');
  EXPECT_NE(check_job_request(q.refresh(), JobLimits{}).find("65 characters"), std::string::npos);
  for (char bad : {' ', '/', '\\', '"', '<', '\x01', '\x7f', '\xc3'}) {
    q.job_id = std::string("a") + bad + "b";
    EXPECT_NE(check_job_request(q.refresh(), JobLimits{}).find("position 1"), std::string::npos) << int(bad);
  }
}

// The gateway checks every job quantity against its one range (runtime/quantities.hpp): both ends in, just
// outside either end out, 0 the default.
TEST(DdsGatewayCheck, ParameterRangesAreTheQuantitiesAndZeroMeansDefault) {
  namespace qn = hg::quantity;
  JobLimits lim;
  struct P {
    const char* name;
    double hgdds_JobRequest::*field;
    double lo, hi;
  } params[] = {{"tool_radius", &hgdds_JobRequest::tool_radius, qn::kToolRadius.min, qn::kToolRadius.max},
                {"tilt", &hgdds_JobRequest::tilt, qn::kTilt.min, qn::kTilt.max},
                {"grind_speed", &hgdds_JobRequest::grind_speed, qn::kGrindSpeed.min, qn::kGrindSpeed.max},
                {"travel_speed", &hgdds_JobRequest::travel_speed, qn::kTravelSpeed.min, qn::kTravelSpeed.max},
                {"step", &hgdds_JobRequest::step, qn::kStep.min, qn::kStep.max},
                {"safe_height", &hgdds_JobRequest::safe_height, qn::kSafeHeight.min, qn::kSafeHeight.max}};
  EXPECT_EQ(std::size(params), std::size(qn::kJobQuantities));
  for (const P& p : params) {
    SCOPED_TRACE(p.name);
    Req q;
    hgdds_JobRequest& r = q.refresh();
    for (double ok : {0.0, p.hi, p.lo > 0 ? p.lo : 1e-9}) {
      r.*p.field = ok;
      EXPECT_EQ(check_job_request(r, lim), "") << ok;
    }
    for (double bad : {above(p.hi), p.lo > 0 ? below(p.lo) : -1e-9, std::numeric_limits<double>::infinity(),
                       std::numeric_limits<double>::quiet_NaN()}) {
      r.*p.field = bad;
      std::string why = check_job_request(r, lim);
      EXPECT_EQ(why.rfind(p.name, 0), 0u) << bad << ": " << why;
    }
  }
}

TEST(DdsGatewayCheck, ActionDirectionAndPartIdAreChecked) {
  Req q;
  hgdds_JobRequest& r = q.refresh();
  for (int a = 0; a <= 6; ++a) {  // START, ABORT, RESET, APPROVE, REJECT, REPLAN, QUERY
    r.action = int8_t(a);
    EXPECT_EQ(check_job_request(r, JobLimits{}), "");
  }
  r.action = 7;
  EXPECT_NE(check_job_request(r, JobLimits{}).find("action 7"), std::string::npos);
  r.action = -1;
  EXPECT_NE(check_job_request(r, JobLimits{}).find("action -1"), std::string::npos);
  r.action = 0;
  r.direction = 2;
  EXPECT_NE(check_job_request(r, JobLimits{}).find("direction 2"), std::string::npos);
  r.direction = 1;
  q.part_id = std::string(128, 'p');
  EXPECT_EQ(check_job_request(q.refresh(), JobLimits{}), "");
  q.part_id = std::string(129, 'p');
  EXPECT_NE(check_job_request(q.refresh(), JobLimits{}).find("129 bytes"), std::string::npos);
  q.part_id = "tab\there";
  EXPECT_NE(check_job_request(q.refresh(), JobLimits{}).find("control character at position 3"), std::string::npos);
  q.part_id = "";
  EXPECT_EQ(check_job_request(q.refresh(), JobLimits{}), "");
  r.job_id = nullptr;  // a sample without strings is refused, not crashed on
  EXPECT_EQ(check_job_request(r, JobLimits{}), "job_id is empty");
}

TEST(DdsGatewayCheck, PrintableEchoesSafely) {
  EXPECT_EQ(hg::dds_gateway::printable("a\nb\x01\xff", 64), "a?b??");
  EXPECT_EQ(hg::dds_gateway::printable(std::string(80, 'z').c_str(), 64), std::string(64, 'z'));
  EXPECT_EQ(hg::dds_gateway::printable(nullptr, 64), "");
}

}  // namespace
