#include "dds_gateway/dds_gateway.hpp"

#include <unistd.h>

#include <cstdlib>

#include "runtime/channels.hpp"

namespace hg::dds_gateway {

using runtime::Level;
using runtime::logf;

runtime::ProcessInfo process_info() {
  return {
      "hg-dds-gateway",
      "LCM <-> Cyclone DDS bridge for plant systems (MES, line control, dashboards).",
      "LCM -> DDS: outline, part poses, grind paths, job status, robot status (at most\n"
      "--robot-status-max-rate Hz), heartbeats as the per-process health topic. Outline, grind path,\n"
      "job status and health are transient-local, keep-last-1 per key: a late joiner gets the current state.\n"
      "DDS -> LCM: job requests, checked (ids, parameter ranges) first; a refused one gets a REFUSED job\n"
      "status saying why, on LCM and DDS, and never reaches HG_JOB_REQUEST.\n"
      "Cyclone is configured by --dds-config (default: $CYCLONEDDS_URI, else the shipped loopback-only\n"
      "dds_gateway/config/cyclonedds-lo.xml). DDS Security is on when the six --dds-security-* files are\n"
      "given (tools/make-dds-security.sh makes a test set); without them the gateway runs unauthenticated,\n"
      "says so loudly and reports DEGRADED. See docs/dds_gateway.md.",
      {
          {"dds-domain", "0", "DDS domain id (0..230)", false, runtime::ParamType::Integer, 0, 230},
          {"dds-topic-prefix", kDefaultTopicPrefix, "prefix of every DDS topic name"},
          {"dds-config", "", "Cyclone configuration (CYCLONEDDS_URI syntax: file://PATH or XML)"},
          {"robot-status-max-rate", "10", "robot status forwarded at most this often, Hz (0: all)", false,
           runtime::ParamType::Number, 0},
          {"dds-security-identity-ca", "", "DDS Security: identity CA certificate (PEM)"},
          {"dds-security-identity-cert", "", "DDS Security: this gateway's identity certificate (PEM)"},
          {"dds-security-private-key", "", "DDS Security: the identity's private key (PEM)"},
          {"dds-security-permissions-ca", "", "DDS Security: permissions CA certificate (PEM)"},
          {"dds-security-governance", "", "DDS Security: governance document signed by the permissions CA"},
          {"dds-security-permissions", "", "DDS Security: this gateway's permissions, signed by the permissions CA"},
      }};
}

Options options_from(const runtime::Node& node) {
  Options o;
  std::int64_t domain = node.params().integer("dds-domain");
  if (domain < 0 || domain > 230)
    throw runtime::ConfigError("dds-domain " + std::to_string(domain) + " is outside 0..230");
  o.domain = int(domain);
  o.topic_prefix = node.params().text("dds-topic-prefix");
  o.cyclone_config = node.params().text("dds-config");
  if (o.cyclone_config.empty()) {
    const char* env = std::getenv("CYCLONEDDS_URI");
    o.cyclone_config = (env && *env) ? env : "file://" + shipped_cyclone_config();
  }
  o.robot_status_max_rate = node.params().number("robot-status-max-rate");
  if (!(o.robot_status_max_rate >= 0)) throw runtime::ConfigError("robot-status-max-rate must be >= 0 (0: no limit)");
  o.security.identity_ca = node.params().text("dds-security-identity-ca");
  o.security.identity_certificate = node.params().text("dds-security-identity-cert");
  o.security.private_key = node.params().text("dds-security-private-key");
  o.security.permissions_ca = node.params().text("dds-security-permissions-ca");
  o.security.governance = node.params().text("dds-security-governance");
  o.security.permissions = node.params().text("dds-security-permissions");
  // A security file that is named but cannot be read is a bad configuration (exit 2), found before DDS starts.
  if (o.security.any())
    if (const std::string p = o.security.problem(); !p.empty()) throw runtime::ConfigError("dds-security: " + p);
  return o;
}

Gateway::Gateway(runtime::Node& node, Options options)
    : node_(node), options_(std::move(options)), write_error_log_(5, std::chrono::seconds(10)) {
  const std::string& prefix = options_.topic_prefix;
  participant_ = Entity(make_participant(options_.domain, options_.cyclone_config, options_.security));
  dds_entity_t pp = participant_.get();
  Qos state = state_qos(), stream = stream_qos();
  auto writer = [&](const dds_topic_descriptor_t* desc, const char* suffix, const Qos& qos) {
    return make_writer(pp, make_topic(pp, desc, prefix + suffix), qos.get());
  };
  w_outline_ = writer(&hgdds_Outline_desc, topic::kOutline, state);
  w_part_pose_ = writer(&hgdds_PartPose_desc, topic::kPartPose, stream);
  w_grind_path_ = writer(&hgdds_GrindPath_desc, topic::kGrindPath, state);
  w_job_status_ = writer(&hgdds_JobStatus_desc, topic::kJobStatus, state);
  w_robot_status_ = writer(&hgdds_RobotStatus_desc, topic::kRobotStatus, stream);
  w_health_ = writer(&hgdds_Health_desc, topic::kHealth, state);
  r_job_request_ = make_reader(pp, make_topic(pp, &hgdds_JobRequest_desc, prefix + topic::kJobRequest), stream.get());

  if (secured()) {
    logf(Level::Info, "DDS Security on: identity %s, permissions %s", options_.security.identity_certificate.c_str(),
         options_.security.permissions.c_str());
  } else {
    logf(Level::Warn, "*****************************************************************************");
    logf(Level::Warn, "* NO DDS SECURITY: the DDS side runs UNAUTHENTICATED and UNENCRYPTED.        *");
    logf(Level::Warn, "* Anyone on DDS domain %3d can read the cell's data and inject job requests. *",
         options_.domain);
    logf(Level::Warn, "* Give the six --dds-security-* files (docs/dds_gateway.md) to secure it.    *");
    logf(Level::Warn, "*****************************************************************************");
    node_.set_state(hullgrind::heartbeat_t::STATE_DEGRADED,
                    "DDS side unauthenticated: no DDS Security configured (docs/dds_gateway.md)");
  }
  logf(Level::Info, "DDS domain %d, topics %s*, Cyclone config %s", options_.domain, prefix.c_str(),
       options_.cyclone_config.c_str());

  // While the loop is held up (a write waiting up to 1 s for a slow reliable reader, or the process short
  // of CPU) LCM must keep what arrives: its default queue of 30 is 30 ms of a 1 kHz part-pose stream, and
  // it drops the newest, so even a state topic would end on a stale state. 10000: 10 s of that stream.
  node_.set_queue_capacity(10000);

  node_.subscribe<hullgrind::outline_t>(channels::kOutline,
                                        [this](const hullgrind::outline_t& m, const runtime::Delivery&) {
                                          OutlineSample s;
                                          to_dds(m, s);
                                          write(w_outline_, &s.s, "outline");
                                        });
  node_.subscribe<hullgrind::part_pose_t>(channels::kPartPose,
                                          [this](const hullgrind::part_pose_t& m, const runtime::Delivery&) {
                                            hgdds_PartPose s = to_dds(m);
                                            write(w_part_pose_, &s, "part pose");
                                          });
  node_.subscribe<hullgrind::grind_path_t>(channels::kGrindPath,
                                           [this](const hullgrind::grind_path_t& m, const runtime::Delivery&) {
                                             GrindPathSample s;
                                             to_dds(m, s);
                                             write(w_grind_path_, &s.s, "grind path");
                                           });
  node_.subscribe<hullgrind::job_status_t>(channels::kJobStatus,
                                           [this](const hullgrind::job_status_t& m, const runtime::Delivery&) {
                                             // The gateway's own refusals went to DDS directly (handle_job_request); do
                                             // not send them twice.
                                             if (m.source == node_.name()) return;
                                             JobStatusSample s;
                                             to_dds(m, s);
                                             write(w_job_status_, &s.s, "job status");
                                           });
  node_.subscribe<hullgrind::robot_status_t>(
      channels::kRobotStatus,
      [this](const hullgrind::robot_status_t& m, const runtime::Delivery&) { on_robot_status(m); });
  node_.subscribe<hullgrind::heartbeat_t>(channels::kHeartbeat,
                                          [this](const hullgrind::heartbeat_t& m, const runtime::Delivery&) {
                                            hgdds_Health s = to_dds(m);
                                            if (m.process == node_.name() && m.pid == ::getpid()) s.thinned = thinned_;
                                            write(w_health_, &s, "health");
                                          });
  // Job requests and the rate-limited robot status are served from the LCM loop, so every LCM publish
  // happens on one thread; 5 ms keeps a request's delay far below anything a plant system would notice.
  node_.every(std::chrono::milliseconds(5), [this] {
    poll_job_requests();
    flush_robot_status();
  });
}

Gateway::~Gateway() = default;

bool Gateway::write(dds_entity_t writer, const void* sample, const char* what) {
  dds_return_t rc = dds_write(writer, sample);
  if (rc < 0) {
    node_.count_dropped();
    std::uint64_t suppressed = 0;
    if (write_error_log_.allow(suppressed))
      logf(Level::Error, "DDS write of a %s failed: %s (%llu similar messages suppressed)", what, dds_strretcode(rc),
           static_cast<unsigned long long>(suppressed));
    return false;
  }
  ++node_.counters().published;
  return true;
}

void Gateway::on_robot_status(const hullgrind::robot_status_t& m) {
  auto now = std::chrono::steady_clock::now();
  double rate = options_.robot_status_max_rate;
  if (rate <= 0 || now - last_robot_status_ >= std::chrono::duration<double>(1.0 / rate)) {
    if (pending_robot_status_) ++thinned_;  // superseded by this newer one
    pending_robot_status_.reset();
    last_robot_status_ = now;
    hgdds_RobotStatus s = to_dds(m);
    write(w_robot_status_, &s, "robot status");
    return;
  }
  if (pending_robot_status_) ++thinned_;
  pending_robot_status_ = m;  // the newest waits for its slot, so the last state always crosses
}

void Gateway::flush_robot_status() {
  if (!pending_robot_status_) return;
  auto now = std::chrono::steady_clock::now();
  if (now - last_robot_status_ < std::chrono::duration<double>(1.0 / options_.robot_status_max_rate)) return;
  last_robot_status_ = now;
  hgdds_RobotStatus s = to_dds(*pending_robot_status_);
  write(w_robot_status_, &s, "robot status");
  pending_robot_status_.reset();
}

void Gateway::poll_job_requests() {
  constexpr int kBatch = 32;
  void* samples[kBatch];
  dds_sample_info_t infos[kBatch];
  for (;;) {
    samples[0] = nullptr;  // loan: Cyclone hands out its own buffers
    dds_return_t n = dds_take(r_job_request_, samples, infos, kBatch, kBatch);
    if (n <= 0) {
      if (n < 0) logf(Level::Error, "DDS take of job requests failed: %s", dds_strretcode(n));
      return;
    }
    for (int i = 0; i < n; ++i) {
      if (!infos[i].valid_data) continue;  // instance state change only (writer gone)
      ++node_.counters().received;
      handle_job_request(*static_cast<const hgdds_JobRequest*>(samples[i]));
    }
    dds_return_loan(r_job_request_, samples, n);
    if (n < kBatch) return;
  }
}

void Gateway::handle_job_request(const hgdds_JobRequest& r) {
  std::string why = check_job_request(r, options_.limits);
  if (why.empty()) {
    hullgrind::job_request_t m = to_lcm(r);
    node_.publish(channels::kJobRequest, m);
    logf(Level::Info, "job request '%s' (action %d) from DDS forwarded to LCM", m.job_id.c_str(), int(m.action));
    return;
  }
  node_.count_dropped();
  hullgrind::job_status_t st{};
  st.job_id = printable(r.job_id, options_.limits.max_job_id);
  st.part_id = printable(r.part_id, options_.limits.max_part_id);
  st.source = node_.name();
  st.state = hullgrind::job_status_t::STATE_REFUSED;
  st.progress = 0;
  st.message = "refused by " + node_.name() + ": " + why;
  logf(Level::Warn, "job request '%s' from DDS refused: %s", st.job_id.c_str(), why.c_str());
  node_.publish(channels::kJobStatus, st);  // fills header seq and utime
  JobStatusSample s;
  to_dds(st, s);
  write(w_job_status_, &s.s, "job status");
}

std::unique_ptr<Gateway> attach(runtime::Node& node) { return std::make_unique<Gateway>(node, options_from(node)); }

}  // namespace hg::dds_gateway
