#include "station/station.hpp"

#include <sys/socket.h>
#include <sys/time.h>
#include <sys/un.h>
#include <unistd.h>

#include <deque>
#include <filesystem>
#include <mutex>

#include "cell/cell_params.hpp"
#include "hullgrind/heartbeat_t.hpp"
#include "runtime/channels.hpp"
#include "station/api.hpp"
#include "station/server.hpp"

#ifndef HG_STATION_WEB_ROOT
#define HG_STATION_WEB_ROOT "station/web"
#endif

namespace hg::station {

namespace {

using runtime::integer_param;
using runtime::text_param;

// The hand-off from the HTTP thread to the LCM thread: bounded, never blocks either side for long.
class RequestQueue {
 public:
  bool push(const hullgrind::job_request_t& r) {
    std::lock_guard lock(mutex_);
    if (queue_.size() >= kCapacity) return false;
    queue_.push_back(r);
    return true;
  }
  std::deque<hullgrind::job_request_t> take() {
    std::lock_guard lock(mutex_);
    return std::exchange(queue_, {});
  }

 private:
  static constexpr std::size_t kCapacity = 64;
  std::mutex mutex_;
  std::deque<hullgrind::job_request_t> queue_;
};

// The supervisor's status-json over its control socket (RUN_DIR/supervisor.sock), at most 300 ms.
Json supervisor_status(const std::string& run_dir) {
  const std::string path = run_dir + "/supervisor.sock";
  sockaddr_un addr{};
  if (run_dir.empty() || path.size() >= sizeof(addr.sun_path)) return nullptr;
  addr.sun_family = AF_UNIX;
  std::copy(path.begin(), path.end(), addr.sun_path);
  const int fd = ::socket(AF_UNIX, SOCK_STREAM | SOCK_CLOEXEC, 0);
  if (fd < 0) return nullptr;
  timeval tv{0, 300000};
  ::setsockopt(fd, SOL_SOCKET, SO_RCVTIMEO, &tv, sizeof tv);
  ::setsockopt(fd, SOL_SOCKET, SO_SNDTIMEO, &tv, sizeof tv);
  std::string data;
  if (::connect(fd, reinterpret_cast<sockaddr*>(&addr), sizeof addr) == 0 &&
      ::send(fd, "status-json", 11, MSG_NOSIGNAL) == 11) {
    ::shutdown(fd, SHUT_WR);
    char buf[8192];
    for (ssize_t n; (n = ::recv(fd, buf, sizeof buf, 0)) > 0 && data.size() < (1u << 20);) data.append(buf, n);
  }
  ::close(fd);
  Json j = Json::parse(data, nullptr, false);
  return j.is_discarded() ? Json(nullptr) : j;
}

Json cell_summary(const cell::LoadedCell& c) {
  const cell::Calibration& cal = c.cell.calibration;
  return {{"file", c.file},
          {"calibration",
           {{"method", cal.method},
            {"date", cal.date},
            {"rms_mm", cal.rms_mm},
            {"worst_mm", cal.worst_mm},
            {"features", cal.features},
            {"eye_in_hand", cal.camera_to_flange.has_value()}}},
          {"tool", {{"radius", c.cell.tool.radius}, {"tilt", c.cell.tool.tilt}}},
          {"max_speed", c.cell.max_speed},
          {"max_accel", c.cell.max_accel},
          {"workspace_min", {c.cell.workspace_min.x(), c.cell.workspace_min.y(), c.cell.workspace_min.z()}},
          {"workspace_max", {c.cell.workspace_max.x(), c.cell.workspace_max.y(), c.cell.workspace_max.z()}}};
}

// Everything that lives while the loop runs; the server stops (joins its thread) first.
struct Station {
  std::unique_ptr<Sessions> sessions;
  LoginLimiter limiter;
  std::unique_ptr<LiveState> live;
  std::unique_ptr<History> history;
  RequestQueue requests;
  std::unique_ptr<Api> api;
  std::unique_ptr<Server> server;
  std::string users_file;
  std::filesystem::file_time_type users_mtime{};
  std::string users_problem;  // why the users file is not in use, for the heartbeat
  std::mutex supervisor_mutex;
  Json supervisor_cache;
  std::chrono::steady_clock::time_point supervisor_time{};
  ~Station() {
    if (server) server->stop();
  }
};

ServerConfig server_config(const runtime::Node& node) {
  ServerConfig c;
  c.address = node.params().text("address");
  c.port = int(node.params().integer("port"));
  c.tls_cert = node.params().text("tls-cert");
  c.tls_key = node.params().text("tls-key");
  c.max_body = std::size_t(node.params().integer("max-body"));
  c.read_timeout = std::chrono::milliseconds(std::int64_t(node.params().number("read-timeout") * 1000));
  c.idle_timeout = std::chrono::milliseconds(std::int64_t(node.params().number("idle-timeout") * 1000));
  c.max_connections = int(node.params().integer("max-connections"));
  return c;
}

void subscribe(runtime::Node& node, LiveState& live) {
  namespace ch = channels;
  node.subscribe<hullgrind::heartbeat_t>(
      ch::kHeartbeat, [&live](const auto& m, const runtime::Delivery& d) { live.on_heartbeat(m, d.recv_utime); });
  node.subscribe<hullgrind::robot_status_t>(
      ch::kRobotStatus, [&live](const auto& m, const runtime::Delivery& d) { live.on_robot(m, d.recv_utime); });
  node.subscribe<hullgrind::job_status_t>(
      ch::kJobStatus, [&live](const auto& m, const runtime::Delivery& d) { live.on_status(m, d.recv_utime); });
  node.subscribe<hullgrind::plate_cloud_t>(
      ch::kPlateCloud, [&live](const auto& m, const runtime::Delivery& d) { live.on_cloud(m, d.recv_utime); });
  node.subscribe<hullgrind::outline_t>(
      ch::kOutline, [&live](const auto& m, const runtime::Delivery& d) { live.on_outline(m, d.recv_utime); });
  node.subscribe<hullgrind::grind_path_t>(
      ch::kGrindPath, [&live](const auto& m, const runtime::Delivery& d) { live.on_path(m, d.recv_utime); });
}

ApiConfig api_config(const runtime::Node& node, const cell::LoadedCell& cell, Station& st) {
  ApiConfig c;
  c.tls = !node.params().text("tls-cert").empty();
  c.web_root = node.params().text("web-root").empty() ? HG_STATION_WEB_ROOT : node.params().text("web-root");
  c.three_root = node.params().text("three-root");
  c.limits.max_speed = cell.cell.max_speed;
  c.cell = cell_summary(cell);
  c.station = [&st] {
    if (!st.server) return Json(nullptr);
    const ServerStats& s = st.server->stats();
    return Json{{"requests", s.requests.load()},
                {"refused", s.bad_requests.load()},
                {"too_large", s.too_large.load()},
                {"timed_out", s.timeouts.load()},
                {"connections_refused", s.refused_connections.load()},
                {"live_clients", s.websockets.load()},
                {"live_clients_dropped", s.websocket_drops.load()}};
  };
  const std::string run_dir = node.params().text("supervisor-dir");
  if (!run_dir.empty())
    c.supervisor = [&st, run_dir] {  // asked at most once a second
      std::lock_guard lock(st.supervisor_mutex);
      const auto now = std::chrono::steady_clock::now();
      if (now - st.supervisor_time > std::chrono::seconds(1)) {
        st.supervisor_cache = supervisor_status(run_dir);
        st.supervisor_time = now;
      }
      return st.supervisor_cache;
    };
  return c;
}

// The users file is read again when it changes (tools/hg-station-user while the station runs). Missing: no
// one can log in (DEGRADED says so); broken: the users read before stay.
void reload_users(Station& st, bool first) {
  std::error_code ec;
  const auto mtime = std::filesystem::last_write_time(st.users_file, ec);
  if (ec) {
    st.users_problem = "no users file " + st.users_file + " (tools/hg-station-user add NAME --role operator)";
    if (st.api) st.api->set_users({});
    return;
  }
  if (!first && mtime == st.users_mtime && st.users_problem.empty()) return;
  st.users_mtime = mtime;
  try {
    auto users = read_users(st.users_file);
    st.users_problem = users.empty() ? "no users in " + st.users_file : "";
    st.api->set_users(std::move(users));
  } catch (const UsersError& e) {
    if (first) throw;
    st.users_problem = e.what();
  }
}

void health(runtime::Node& node, const Station& st) {
  if (!st.users_problem.empty()) node.set_state(hullgrind::heartbeat_t::STATE_DEGRADED, st.users_problem);
  else
    node.set_state(hullgrind::heartbeat_t::STATE_OK);
}

}  // namespace

runtime::ProcessInfo process_info() {
  const double inf = std::numeric_limits<double>::infinity();
  return {
      "hg-station",
      "The operator station: a web page (HTTP and WebSocket, Boost.Beast) to see the cell and the plate, approve "
      "the plan, start, abort and review every job.",
      "Serves station/web/ and the API of docs/station.md on ADDRESS:PORT (127.0.0.1:8080; another address: use TLS).\n"
      "Every API request needs a session (POST /api/login with a user of --users-file, made with\n"
      "tools/hg-station-user); every POST but login needs the session's X-CSRF-Token; viewers may not act.\n"
      "Subscribes HG_JOB_STATUS, HG_HEARTBEAT, HG_ROBOT_STATUS, HG_PLATE_CLOUD, HG_OUTLINE, HG_GRIND_PATH;\n"
      "publishes only HG_JOB_REQUEST (START, APPROVE, REJECT, REPLAN, ABORT, RESET, as hg-lcm-send can).\n"
      "Reads the job history from --jobs-dir (the recorder's folder). Details: docs/station.md.",
      {cell::cell_param(),
       text_param("address", "127.0.0.1", "address to listen on (another than loopback: give tls-cert and tls-key)"),
       integer_param("port", "8080", "TCP port (0: any free port, printed in the log)", 0, 65535),
       text_param("tls-cert", "", "TLS certificate chain, PEM (with tls-key: HTTPS and WSS only)"),
       text_param("tls-key", "", "TLS private key, PEM"),
       text_param("users-file", "",
                  "the users file (tools/hg-station-user; read again when it changes; missing: nobody can log in)"),
       text_param("jobs-dir", "", "the job recorder's folder (out/jobs): the history; empty: no history"),
       text_param("web-root", "", "the page's files; empty: the source tree's station/web"),
       text_param("three-root", "/usr/share/javascript/three", "three.js (Debian's libjs-three), served as /three/"),
       text_param("supervisor-dir", "", "the supervisor's run directory (restarts of every process); empty: none"),
       integer_param("max-body", "1048576", "largest request body, bytes (larger: 413)", 1024, 64 << 20),
       runtime::number_param("read-timeout", "10", "a request must arrive whole within this, s", 0, 3600, true),
       runtime::number_param("idle-timeout", "30", "an idle keep-alive connection is closed after this, s", 0, 3600,
                             true),
       runtime::number_param("session-timeout", "28800", "a session unused this long ends, s", 0, inf, true),
       integer_param("max-connections", "64", "open HTTP connections at most (more: closed at once)", 1, 10000),
       integer_param("cloud-points", "200000", "points of a plate cloud sent to the page at most (every k-th)", 1000,
                     5000000)}};
}

std::shared_ptr<void> attach(runtime::Node& node) {
  if (node.params().text("users-file").empty())
    throw runtime::ConfigError("users-file: required (make one with tools/hg-station-user add NAME --role operator)");
  const cell::LoadedCell cell = cell::load_cell(node.params());
  auto st = std::make_shared<Station>();
  st->sessions =
      std::make_unique<Sessions>(std::chrono::seconds(std::int64_t(node.params().number("session-timeout"))));
  LiveOptions lo;
  lo.camera_to_base = cell.cell.calibration.camera_to_base;
  lo.camera_to_flange = cell.cell.calibration.camera_to_flange;
  lo.cloud_points = std::size_t(node.params().integer("cloud-points"));
  st->live = std::make_unique<LiveState>(lo);
  st->history = std::make_unique<History>(node.params().text("jobs-dir"));
  Station* raw = st.get();
  st->api =
      std::make_unique<Api>(api_config(node, cell, *st), std::vector<User>{}, *st->sessions, st->limiter, *st->live,
                            *st->history, [raw](hullgrind::job_request_t& r) { return raw->requests.push(r); });
  st->users_file = node.params().text("users-file");
  try {
    reload_users(*st, true);
  } catch (const UsersError& e) {
    throw node.params().error("users-file", e.what());
  }
  st->server = std::make_unique<Server>(server_config(node), *st->api, *st->live);
  subscribe(node, *st->live);
  node.every(std::chrono::milliseconds(20), [raw, &node] {
    for (auto& r : raw->requests.take()) node.publish(channels::kJobRequest, r);
  });
  node.every(std::chrono::milliseconds(2000), [raw, &node] {
    reload_users(*raw, false);
    health(node, *raw);
  });
  st->server->start();
  runtime::logf(runtime::Level::Info, "listening on http%s://%s:%d/ (%zu users)",
                node.params().text("tls-cert").empty() ? "" : "s", node.params().text("address").c_str(),
                st->server->port(), st->api->user_count());
  health(node, *st);
  return st;
}

}  // namespace hg::station
