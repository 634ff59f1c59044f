// hg-dds-gateway: the cell's door to plant systems that speak DDS (Cyclone DDS, types in idl/hullgrind.idl).
//  LCM -> DDS: outline, part poses, grind paths, job status, robot status (rate-limited), heartbeats as a
//              per-process health topic.
//  DDS -> LCM: job requests, checked (check_job_request) before they reach HG_JOB_REQUEST; a refused one
//              is answered with a REFUSED job status (LCM and DDS) that says why.
// With DDS Security configured (six files) peers must authenticate and hold signed permissions; without
// it the gateway warns loudly and reports DEGRADED in its heartbeat.
#pragma once

#include <chrono>
#include <memory>
#include <optional>
#include <string>

#include "dds_gateway/convert.hpp"
#include "dds_gateway/dds_support.hpp"
#include "runtime/node.hpp"

namespace hg::dds_gateway {

struct Options {
  int domain = 0;
  std::string topic_prefix = kDefaultTopicPrefix;
  std::string cyclone_config;         // CYCLONEDDS_URI value handed to dds_create_domain
  double robot_status_max_rate = 10;  // Hz; 0: every robot status crosses
  SecurityFiles security;
  JobLimits limits;
};

runtime::ProcessInfo process_info();
// Options from the node's parameters (command line > config > default). Throws runtime::ConfigError.
Options options_from(const runtime::Node& node);

class Gateway {
 public:
  // Creates the DDS side and wires LCM subscriptions and timers onto `node`. Throws DdsError.
  Gateway(runtime::Node& node, Options options);
  ~Gateway();
  Gateway(const Gateway&) = delete;
  Gateway& operator=(const Gateway&) = delete;

  bool secured() const { return options_.security.any(); }

 private:
  void on_robot_status(const hullgrind::robot_status_t& m);
  void flush_robot_status();
  void poll_job_requests();
  void handle_job_request(const hgdds_JobRequest& r);
  bool write(dds_entity_t writer, const void* sample, const char* what);

  runtime::Node& node_;
  Options options_;
  Entity participant_;
  dds_entity_t w_outline_ = 0, w_part_pose_ = 0, w_grind_path_ = 0, w_job_status_ = 0, w_robot_status_ = 0,
               w_health_ = 0, r_job_request_ = 0;
  std::chrono::steady_clock::time_point last_robot_status_{};
  std::optional<hullgrind::robot_status_t> pending_robot_status_;
  // Robot statuses superseded while waiting for their rate-limit slot: deliberate, not a loss, so not in
  // the heartbeat's `dropped`; reported as `thinned` in the gateway's own Health sample.
  std::int64_t thinned_ = 0;
  runtime::RateLimiter write_error_log_;
};

// Builds the gateway for `node`; throws (runtime::ConfigError on a bad parameter) if the DDS side cannot be made.
std::unique_ptr<Gateway> attach(runtime::Node& node);

}  // namespace hg::dds_gateway
