#include "robot_bridge/ur_driver.hpp"

#include <algorithm>
#include <arpa/inet.h>
#include <cmath>
#include <cerrno>
#include <cstring>
#include <fcntl.h>
#include <netinet/in.h>
#include <netinet/tcp.h>
#include <poll.h>
#include <random>
#include <stdexcept>
#include <sys/socket.h>
#include <unistd.h>

#include "hullgrind/robot_status_t.hpp"
#include "runtime/log.hpp"

namespace hg::robot_bridge {

using hullgrind::robot_status_t;
using runtime::Level;
using runtime::logf;

namespace {

// RTDE package types (protocol version 2).
constexpr std::uint8_t kRequestProtocolVersion = 86;  // 'V'
constexpr std::uint8_t kGetUrcontrolVersion = 118;    // 'v'
constexpr std::uint8_t kTextMessage = 77;             // 'M'
constexpr std::uint8_t kDataPackage = 85;             // 'U'
constexpr std::uint8_t kSetupOutputs = 79;            // 'O'
constexpr std::uint8_t kSetupInputs = 73;             // 'I'
constexpr std::uint8_t kStart = 83;                   // 'S'
constexpr std::uint8_t kPause = 80;                   // 'P'
constexpr std::size_t kMaxPackage = 8192;             // nothing we ask for is larger: bigger means lost framing

constexpr std::int32_t kRobotModeRunning = 7;
constexpr std::uint32_t kRuntimePlaying = 2, kRuntimePausing = 3, kRuntimePaused = 4;
constexpr std::size_t kDataSize = 1 + 8 + 48 + 4 + 4 + 4 + 4;  // recipe id + the fields below

std::uint64_t be64(const std::uint8_t* p) {
  std::uint64_t v = 0;
  for (int i = 0; i < 8; ++i) v = (v << 8) | p[i];
  return v;
}
std::uint32_t be32(const std::uint8_t* p) {
  return std::uint32_t(p[0]) << 24 | std::uint32_t(p[1]) << 16 | std::uint32_t(p[2]) << 8 | p[3];
}
double be_double(const std::uint8_t* p) {
  std::uint64_t u = be64(p);
  double d;
  std::memcpy(&d, &u, 8);
  return d;
}
void put_double(std::vector<std::uint8_t>& out, double d) {
  std::uint64_t u;
  std::memcpy(&u, &d, 8);
  for (int i = 7; i >= 0; --i) out.push_back(std::uint8_t(u >> (8 * i)));
}

// Connects to an IPv4 address with a short timeout; -1 and `error` on failure.
int connect_tcp(const std::string& host, int port, int timeout_ms, std::string& error) {
  sockaddr_in addr{};
  addr.sin_family = AF_INET;
  addr.sin_port = htons(std::uint16_t(port));
  if (inet_pton(AF_INET, host.c_str(), &addr.sin_addr) != 1) return error = "not an IPv4 address: " + host, -1;
  int fd = socket(AF_INET, SOCK_STREAM | SOCK_NONBLOCK | SOCK_CLOEXEC, 0);
  if (fd < 0) return error = std::string("socket: ") + std::strerror(errno), -1;
  if (connect(fd, reinterpret_cast<sockaddr*>(&addr), sizeof addr) != 0) {
    if (errno != EINPROGRESS) {
      error = std::string("connect: ") + std::strerror(errno);
      close(fd);
      return -1;
    }
    pollfd p{fd, POLLOUT, 0};
    int err = 0;
    socklen_t len = sizeof err;
    if (poll(&p, 1, timeout_ms) != 1 || getsockopt(fd, SOL_SOCKET, SO_ERROR, &err, &len) != 0 || err != 0) {
      error = std::string("connect: ") + (err ? std::strerror(err) : "timed out");
      close(fd);
      return -1;
    }
  }
  int one = 1;
  setsockopt(fd, IPPROTO_TCP, TCP_NODELAY, &one, sizeof one);
  return fd;
}

bool send_all(int fd, const void* data, std::size_t size, int timeout_ms) {
  const auto* p = static_cast<const std::uint8_t*>(data);
  while (size > 0) {
    ssize_t n = send(fd, p, size, MSG_NOSIGNAL);
    if (n > 0) {
      p += n;
      size -= std::size_t(n);
      continue;
    }
    if (n < 0 && (errno == EAGAIN || errno == EWOULDBLOCK)) {
      pollfd pf{fd, POLLOUT, 0};
      if (poll(&pf, 1, timeout_ms) != 1) return false;
      continue;
    }
    if (n < 0 && errno == EINTR) continue;
    return false;
  }
  return true;
}

bool is_loopback(const std::string& host) {
  in_addr a{};
  return inet_pton(AF_INET, host.c_str(), &a) == 1 && (ntohl(a.s_addr) >> 24) == 127;
}

}  // namespace

const char* ur_robot_mode_name(int m) {
  switch (m) {
    case -1: return "NO_CONTROLLER";
    case 0: return "DISCONNECTED";
    case 1: return "CONFIRM_SAFETY";
    case 2: return "BOOTING";
    case 3: return "POWER_OFF";
    case 4: return "POWER_ON";
    case 5: return "IDLE";
    case 6: return "BACKDRIVE";
    case 7: return "RUNNING";
    case 8: return "UPDATING_FIRMWARE";
  }
  return "UNKNOWN";
}

const char* ur_safety_mode_name(int m) {
  switch (m) {
    case 1: return "NORMAL";
    case 2: return "REDUCED";
    case 3: return "PROTECTIVE_STOP";
    case 4: return "RECOVERY";
    case 5: return "SAFEGUARD_STOP";
    case 6: return "SYSTEM_EMERGENCY_STOP";
    case 7: return "ROBOT_EMERGENCY_STOP";
    case 8: return "VIOLATION";
    case 9: return "FAULT";
    case 10: return "VALIDATE_JOINT_ID";
    case 11: return "UNDEFINED_SAFETY_MODE";
    case 12: return "AUTOMATIC_MODE_SAFEGUARD_STOP";
    case 13: return "SYSTEM_THREE_POSITION_ENABLING_STOP";
  }
  return "UNKNOWN";
}

UrDriver::UrDriver(UrOptions options) : o_(std::move(options)) {
  in_addr a{};
  if (inet_pton(AF_INET, o_.host.c_str(), &a) != 1)
    throw std::invalid_argument("ur host '" + o_.host + "' is not an IPv4 address");
  if (!is_loopback(o_.host) && !o_.allow_remote)
    throw std::invalid_argument("ur host " + o_.host +
                                " is not loopback: set --ur-allow-remote to drive a real controller");
  backoff_ = o_.backoff_initial;
  state_.not_ready = "controller not connected";
}

UrDriver::~UrDriver() {
  if (fd_ >= 0) close(fd_);
}

void UrDriver::decode_error(const std::string& what) { on_decode_error("RTDE: " + what); }

void UrDriver::latch(std::int32_t code, const std::string& text) {
  if (state_.fault_code != 0) return;  // the first fault is the one reported
  state_.fault_code = code;
  state_.fault_text = text;
  logf(Level::Error, "ur: %s", text.c_str());
}

bool UrDriver::send_rtde(std::uint8_t type, const std::vector<std::uint8_t>& payload) {
  std::vector<std::uint8_t> pkg;
  const std::size_t size = 3 + payload.size();
  pkg.push_back(std::uint8_t(size >> 8));
  pkg.push_back(std::uint8_t(size));
  pkg.push_back(type);
  pkg.insert(pkg.end(), payload.begin(), payload.end());
  return send_all(fd_, pkg.data(), pkg.size(), 200);
}

void UrDriver::try_connect(double now) {
  std::string error;
  fd_ = connect_tcp(o_.host, o_.rtde_port, 200, error);
  if (fd_ < 0) {
    next_attempt_ = now + backoff_;
    backoff_ = std::min(backoff_ * 2, o_.backoff_max);
    static runtime::RateLimiter limit;
    std::uint64_t suppressed = 0;
    if (limit.allow(suppressed))
      logf(Level::Warn, "ur: RTDE %s:%d: %s; retrying", o_.host.c_str(), o_.rtde_port, error.c_str());
    return;
  }
  rx_.clear();
  link_ = Link::WaitVersion;
  link_since_ = now;
  if (!send_rtde(kRequestProtocolVersion, {0, 2})) drop("cannot send the protocol version request", now);
}

void UrDriver::drop(const std::string& why, double now) {
  if (fd_ >= 0) close(fd_);
  fd_ = -1;
  const bool was_streaming = link_ == Link::Streaming;
  link_ = Link::Down;
  have_data_ = false;
  rx_.clear();
  state_.connected = false;
  state_.pose_valid = false;
  next_attempt_ = now + backoff_;
  backoff_ = std::min(backoff_ * 2, o_.backoff_max);
  if (was_streaming || ever_streamed_)
    latch(robot_status_t::FAULT_CONNECTION_LOST, "controller connection lost: " + why);
  else
    logf(Level::Warn, "ur: RTDE handshake failed: %s", why.c_str());
  // A running program is left to stop(): the script port may still reach the controller even though RTDE
  // does not, and the program must not run on unobserved.
}

void UrDriver::read_socket(double now) {
  std::uint8_t buf[16384];
  for (;;) {
    ssize_t n = recv(fd_, buf, sizeof buf, 0);
    if (n > 0) {
      rx_.insert(rx_.end(), buf, buf + n);
      continue;
    }
    if (n == 0) return drop("the controller closed the RTDE connection", now);
    if (errno == EAGAIN || errno == EWOULDBLOCK) break;
    if (errno == EINTR) continue;
    return drop(std::string("RTDE recv: ") + std::strerror(errno), now);
  }
  std::size_t pos = 0;
  while (fd_ >= 0 && rx_.size() - pos >= 3) {
    const std::size_t size = std::size_t(rx_[pos]) << 8 | rx_[pos + 1];
    if (size < 3 || size > kMaxPackage) {
      decode_error("package size " + std::to_string(size) + " is impossible; stream framing lost");
      return drop("RTDE stream framing lost (package size " + std::to_string(size) + ")", now);
    }
    if (rx_.size() - pos < size) break;
    handle(rx_[pos + 2], rx_.data() + pos + 3, size - 3, now);
    pos += size;
  }
  if (fd_ >= 0) rx_.erase(rx_.begin(), rx_.begin() + long(pos));
}

void UrDriver::handle(std::uint8_t type, const std::uint8_t* p, std::size_t size, double now) {
  switch (type) {
    case kRequestProtocolVersion: {
      if (link_ != Link::WaitVersion || size != 1) return decode_error("unexpected protocol version reply");
      if (p[0] != 1) return drop("the controller does not accept RTDE protocol version 2", now);
      std::vector<std::uint8_t> payload;
      put_double(payload, o_.frequency);
      const std::string names = "timestamp,actual_TCP_pose,robot_mode,safety_mode,runtime_state,output_int_register_" +
                                std::to_string(o_.script.progress_register);
      payload.insert(payload.end(), names.begin(), names.end());
      link_ = Link::WaitSetup;
      if (!send_rtde(kSetupOutputs, payload)) drop("cannot send the output recipe", now);
      return;
    }
    case kSetupOutputs: {
      if (link_ != Link::WaitSetup || size < 1) return decode_error("unexpected output setup reply");
      const std::string types(reinterpret_cast<const char*>(p + 1), size - 1);
      if (types != "DOUBLE,VECTOR6D,INT32,INT32,UINT32,INT32")
        return drop("the controller cannot serve the output recipe (types: " + types + ")", now);
      recipe_id_ = p[0];
      link_ = Link::WaitStart;
      if (!send_rtde(kStart, {})) drop("cannot send start", now);
      return;
    }
    case kStart: {
      if (link_ != Link::WaitStart || size != 1) return decode_error("unexpected start reply");
      if (p[0] != 1) return drop("the controller refused to start the RTDE data stream", now);
      link_ = Link::Streaming;
      last_data_ = now;
      ++connections_;
      backoff_ = o_.backoff_initial;
      logf(Level::Info, "ur: RTDE streaming from %s:%d at %.0f Hz%s", o_.host.c_str(), o_.rtde_port, o_.frequency,
           ever_streamed_ ? " (reconnected)" : "");
      ever_streamed_ = true;
      return;
    }
    case kDataPackage: {
      if (link_ != Link::Streaming) return decode_error("data package before the stream started");
      if (size != kDataSize)
        return decode_error("data package of " + std::to_string(size) + " bytes, recipe needs " +
                            std::to_string(kDataSize));
      if (p[0] != recipe_id_) return decode_error("data package for recipe " + std::to_string(p[0]));
      const std::uint8_t* q = p + 1;
      Raw r = raw_;
      r.timestamp = be_double(q), q += 8;
      for (double& v : r.tcp) v = be_double(q), q += 8;
      r.robot_mode = std::int32_t(be32(q)), q += 4;
      r.safety_mode = std::int32_t(be32(q)), q += 4;
      r.runtime_state = be32(q), q += 4;
      r.progress_register = std::int32_t(be32(q));
      for (double v : r.tcp)
        if (!std::isfinite(v)) return decode_error("data package with a non-finite TCP pose");
      ++r.packages;
      raw_ = r;
      last_data_ = now;
      on_data(now);
      return;
    }
    case kTextMessage: {  // v2: uint8 length + message, uint8 length + source, uint8 warning level
      if (size < 1 || size < 1u + p[0] + 1u || size != 1u + p[0] + 1u + p[1 + p[0]] + 1u)
        return decode_error("malformed text message");
      logf(Level::Info, "ur: controller says: %.*s", int(p[0]), reinterpret_cast<const char*>(p + 1));
      return;
    }
    case kGetUrcontrolVersion:
    case kSetupInputs:
    case kPause: return;  // replies to requests we do not make: harmless
    default: return decode_error("unknown package type " + std::to_string(int(type)));
  }
}

void UrDriver::on_data(double now) {
  have_data_ = true;
  state_.connected = true;
  state_.pose_valid = true;
  const Vec3 rv(raw_.tcp[3], raw_.tcp[4], raw_.tcp[5]);
  const double angle = rv.norm();
  state_.tcp.position = Vec3(raw_.tcp[0], raw_.tcp[1], raw_.tcp[2]);
  state_.tcp.orientation = angle > 0 ? Quat(Eigen::AngleAxisd(angle, rv / angle)) : Quat::Identity();
  evaluate(now);
}

void UrDriver::evaluate(double now) {
  const int sm = raw_.safety_mode;
  if (sm == 3 || sm == 5 || sm == 12 || sm == 13)
    latch(robot_status_t::FAULT_PROTECTIVE_STOP, std::string("controller in ") + ur_safety_mode_name(sm));
  else if (sm == 6 || sm == 7)
    latch(robot_status_t::FAULT_EMERGENCY_STOP, std::string("controller in ") + ur_safety_mode_name(sm));
  else if (sm != 1 && sm != 2)
    latch(robot_status_t::FAULT_UNEXPECTED_MODE, std::string("controller safety mode ") + ur_safety_mode_name(sm));
  if (program_) {
    const int n = int(pts_.size()) - 1;
    const std::int32_t reg = raw_.progress_register;
    if (raw_.runtime_state == kRuntimePlaying) seen_playing_ = true;
    if (reg == done_tag_) {
      program_ = false;
      state_.running = false;
      state_.finished = true;
      state_.progress = 1;
      state_.path_index = -1;
    } else if (state_.fault_code == 0 && raw_.robot_mode != kRobotModeRunning) {
      latch(robot_status_t::FAULT_UNEXPECTED_MODE,
            std::string("robot mode ") + ur_robot_mode_name(raw_.robot_mode) + " during the job");
    } else if (seen_playing_ && (raw_.runtime_state == kRuntimePaused || raw_.runtime_state == kRuntimePausing) &&
               state_.fault_code == 0) {
      latch(robot_status_t::FAULT_UNEXPECTED_MODE, "the program was paused on the controller");
    } else if (seen_playing_ && raw_.runtime_state != kRuntimePlaying && state_.fault_code == 0) {
      program_ = false;
      state_.running = false;
      state_.failure = "the program stopped on the controller before the end (at waypoint " +
                       std::to_string(std::max(0, std::min(reg, n - 1))) + ")";
    } else if (!seen_playing_ && now - sent_at_ > o_.start_timeout) {
      program_ = false;
      state_.running = false;
      state_.failure = "the controller did not run the program (is it in remote control?)";
    } else if (seen_playing_ && reg >= 0 && reg < n) {
      state_.path_index = reg;
      // distance done: points before the segment towards waypoint reg, plus the TCP's projection onto it
      const Vec3& a = pts_[std::size_t(reg)];
      const Vec3& b = pts_[std::size_t(reg) + 1];
      const double L = (b - a).norm();
      const double along = L > 0 ? std::clamp((state_.tcp.position - a).dot(b - a) / L, 0.0, L) : 0.0;
      state_.progress = cum_.back() > 0 ? (cum_[std::size_t(reg)] + along) / cum_.back() : 0;
    }
  }
  state_.running = program_;
  const bool safe = sm == 1 || sm == 2;
  state_.ready = link_ == Link::Streaming && state_.fault_code == 0 && safe && raw_.robot_mode == kRobotModeRunning &&
                 !program_ && raw_.runtime_state != kRuntimePlaying;
  state_.not_ready = state_.ready        ? ""
                     : state_.fault_code ? state_.fault_text
                     : !safe             ? std::string("safety mode ") + ur_safety_mode_name(sm)
                     : raw_.robot_mode != kRobotModeRunning
                         ? std::string("robot mode ") + ur_robot_mode_name(raw_.robot_mode)
                     : program_ ? "running a job"
                                : "another program is running on the controller";
}

void UrDriver::update(double now) {
  if (fd_ < 0) {
    state_.connected = false;
    state_.ready = false;
    state_.not_ready = state_.fault_code ? state_.fault_text : "controller not connected";
    if (now >= next_attempt_) try_connect(now);
    if (fd_ < 0) return;
  }
  read_socket(now);
  if (fd_ < 0) return;
  if (link_ != Link::Streaming && now - link_since_ > o_.handshake_timeout)
    return drop("RTDE handshake timed out", now);
  if (link_ == Link::Streaming && now - last_data_ > o_.data_timeout)
    return drop("no RTDE data for " + std::to_string(o_.data_timeout) + " s", now);
  if (link_ == Link::Streaming && have_data_) evaluate(now);
}

std::string UrDriver::send_script(const std::string& script) {
  std::string error;
  int fd = connect_tcp(o_.host, o_.script_port, 500, error);
  if (fd < 0) return "script port " + std::to_string(o_.script_port) + ": " + error;
  const bool ok = send_all(fd, script.data(), script.size(), 1000);
  shutdown(fd, SHUT_WR);
  close(fd);
  return ok ? "" : "script port: send failed";
}

std::string UrDriver::start(const Path& path, double now) {
  update(now);
  if (!state_.ready) return "robot not ready: " + state_.not_ready;
  static std::mt19937 rng{std::random_device{}()};
  // Larger than any waypoint index, different per job (also across bridge restarts).
  done_tag_ = std::int32_t(1000000000 + rng() % 1000000000u);
  ScriptOptions so = o_.script;
  so.done_tag = done_tag_;
  if (std::string err = send_script(make_script(path, so)); !err.empty()) return err;
  pts_.assign(1, state_.tcp.position);
  pts_.insert(pts_.end(), path.position.begin(), path.position.end());
  cum_.assign(1, 0.0);
  for (std::size_t i = 1; i < pts_.size(); ++i) cum_.push_back(cum_.back() + (pts_[i] - pts_[i - 1]).norm());
  program_ = true;
  seen_playing_ = false;
  sent_at_ = now;
  state_.running = true;
  state_.finished = false;
  state_.failure.clear();
  state_.progress = 0;
  state_.path_index = 0;
  state_.ready = false;
  state_.not_ready = "running a job";
  logf(Level::Info, "ur: sent job %s (%zu waypoints) to %s:%d", path.job_id.c_str(), path.size(), o_.host.c_str(),
       o_.script_port);
  return "";
}

void UrDriver::stop(double) {
  const bool had_program = program_;
  program_ = false;
  state_.running = false;
  state_.path_index = -1;
  if (!had_program) return;
  if (std::string err = send_script(stop_script(o_.script.accel)); !err.empty())
    logf(Level::Error, "ur: could not send the stop program: %s", err.c_str());
}

std::string UrDriver::reset(double now) {
  update(now);
  if (link_ != Link::Streaming || !have_data_) return "controller not connected";
  const int sm = raw_.safety_mode;
  if (sm != 1 && sm != 2)
    return std::string("controller still in ") + ur_safety_mode_name(sm) + " (unlock it on the teach pendant)";
  if (raw_.robot_mode != kRobotModeRunning)
    return std::string("robot mode ") + ur_robot_mode_name(raw_.robot_mode) + " (power on and release the brakes)";
  // A program paused by the stop must never resume: replace it with one that only decelerates.
  if (std::string err = send_script(stop_script(o_.script.accel)); !err.empty()) return err;
  state_.fault_code = 0;
  state_.fault_text.clear();
  evaluate(now);
  return "";
}

}  // namespace hg::robot_bridge
