// LCM <-> DDS conversion and the check of job requests coming from plant systems.
// LCM -> DDS samples borrow the LCM message's memory (strings, arrays): they are valid while the message
// lives and are only handed to dds_write, which copies.
#pragma once

#include <string>
#include <vector>

#include "hullgrind.h"
#include "hullgrind/grind_path_t.hpp"
#include "hullgrind/heartbeat_t.hpp"
#include "hullgrind/job_request_t.hpp"
#include "hullgrind/job_status_t.hpp"
#include "hullgrind/outline_t.hpp"
#include "hullgrind/part_pose_t.hpp"
#include "hullgrind/robot_status_t.hpp"

namespace hg::dds_gateway {

struct OutlineSample {
  hgdds_Outline s{};
  std::vector<hgdds_OutlineLoop> loops;
};
struct GrindPathSample {
  hgdds_GrindPath s{};
  std::vector<double> position, orientation;  // flattened n x 3, n x 4
  std::vector<hgdds_LoopCoverage> coverage;
  std::vector<hgdds_EdgeStretch> unreached;
};
struct JobStatusSample {
  hgdds_JobStatus s{};
  std::vector<hgdds_EdgeStretch> unground;
};

void to_dds(const hullgrind::outline_t& m, OutlineSample& out);
void to_dds(const hullgrind::grind_path_t& m, GrindPathSample& out);
hgdds_PartPose to_dds(const hullgrind::part_pose_t& m);
void to_dds(const hullgrind::job_status_t& m, JobStatusSample& out);
hgdds_RobotStatus to_dds(const hullgrind::robot_status_t& m);
hgdds_Health to_dds(const hullgrind::heartbeat_t& m);

// A checked request as it goes onto LCM (header.seq left 0: the publisher numbers it).
hullgrind::job_request_t to_lcm(const hgdds_JobRequest& r);

// Accepted lengths of a job request's texts. The job quantities (tool_radius, tilt, speeds, step,
// safe_height) are checked against their one range, runtime/quantities.hpp; 0 always means "the configured
// default".
struct JobLimits {
  std::size_t max_job_id = 64;    // job id: 1..max_job_id characters of [A-Za-z0-9._:-]
  std::size_t max_part_id = 128;  // part id: free text, printable, at most this many bytes
};

// Empty if the request may go onto LCM; else why not (one sentence naming the field and the value).
std::string check_job_request(const hgdds_JobRequest& r, const JobLimits& limits);

// A string that is safe to echo in a refusal: printable ASCII, others as '?', at most max bytes.
std::string printable(const char* s, std::size_t max);

}  // namespace hg::dds_gateway
