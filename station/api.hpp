// The station's request handling without sockets: one HTTP request in (method, target, the headers that
// matter, body), one response out. Authentication (session cookie), CSRF, roles, input validation and
// routing all happen here, so the gtests and the fuzz target drive exactly what the server runs.
// The API is documented in docs/station.md.
#pragma once

#include <chrono>
#include <filesystem>
#include <functional>
#include <map>
#include <mutex>
#include <optional>
#include <string>
#include <utility>
#include <vector>

#include "hullgrind/job_request_t.hpp"
#include "station/auth.hpp"
#include "station/history.hpp"
#include "station/live.hpp"

namespace hg::station {

struct HttpRequest {
  std::string method;  // "GET", "POST", ...
  std::string target;  // "/api/jobs?state=DONE"
  std::string cookie;  // the Cookie header
  std::string csrf;    // the X-CSRF-Token header
  std::string content_type;
  std::string body;
  std::string peer;  // the client's address (login rate limit)
};

struct HttpResponse {
  int status = 200;
  std::string content_type = "application/json";
  std::string body;
  std::vector<std::pair<std::string, std::string>> headers;  // extra (Set-Cookie, Retry-After, ...)
  std::filesystem::path file;                                // when set: send this file (body empty)
};

// What a job request may change, with the planner's ranges (path_planner/io.cpp) and the cell's speed limit.
struct OptionLimits {
  double max_speed = 0.25;  // the cell file's max-speed, m/s
};

struct ApiConfig {
  bool tls = false;
  std::filesystem::path web_root;    // index.html, *.js, *.css
  std::filesystem::path three_root;  // three.js (Debian's libjs-three)
  OptionLimits limits;
  Json cell;                         // what GET /api/cell says about the cell file (calibration, tool, limits)
  std::function<Json()> supervisor;  // the supervisor's status-json, or null
  std::function<Json()> station;     // the server's counters, or null
};

// Where job requests go: the bounded queue to the LCM thread. False when it is full (503).
using RequestSink = std::function<bool(hullgrind::job_request_t&)>;

// The URL-decoded path and query of a target; nullopt for a malformed one (bad %, control bytes, too long).
struct Target {
  std::vector<std::string> segments;  // "/api/jobs/x" -> {"api", "jobs", "x"}
  std::map<std::string, std::string> query;
};
std::optional<Target> parse_target(const std::string& target);

// Options of POST /api/jobs and .../replan into the request (0 / DIRECTION_CLIMB: the planner's default).
// Returns the error text naming the key, or "" when valid.
std::string apply_options(const Json& options, const OptionLimits& limits, hullgrind::job_request_t& req);

// A job id from the page or a path segment: 1..120 printable ASCII characters.
bool valid_job_id(const std::string& id);
// A part id: 1..64 printable characters (UTF-8 allowed), no control bytes.
bool valid_part_id(const std::string& id);

class Api {
 public:
  Api(ApiConfig config, std::vector<User> users, Sessions& sessions, LoginLimiter& limiter, LiveState& live,
      const History& history, RequestSink sink);

  HttpResponse handle(const HttpRequest& req);
  // Replaces the users (the users file changed); sessions of removed users end at their next request.
  void set_users(std::vector<User> users);
  std::size_t user_count() const;
  // The session a request's cookie names (the WebSocket upgrade asks this).
  std::optional<Session> session_of(const HttpRequest& req);
  static std::string cookie_value(const std::string& cookie_header, const std::string& name);
  static constexpr const char* kCookie = "hg_session";

 private:
  HttpResponse route_api(const HttpRequest& req, const Target& t);
  HttpResponse get_api(const Target& t);
  HttpResponse post_api(const Session& s, const Target& t, const Json& body);
  HttpResponse login(const HttpRequest& req);
  HttpResponse logout(const HttpRequest& req);
  HttpResponse cell() const;
  HttpResponse jobs(const Target& t) const;
  HttpResponse job(const std::string& id) const;
  HttpResponse job_file(const std::string& id, const std::string& name) const;
  HttpResponse start_job(const Session& s, const Json& body);
  HttpResponse job_action(const Session& s, const std::string& id, const std::string& action, const Json& body);
  HttpResponse approve(const Session& s, const std::string& id, const Json& body);
  HttpResponse send(hullgrind::job_request_t& req, int status, Json answer);
  HttpResponse static_file(const Target& t) const;

  ApiConfig config_;
  mutable std::mutex users_mutex_;
  std::map<std::string, User> users_;
  Sessions& sessions_;
  LoginLimiter& limiter_;
  LiveState& live_;
  const History& history_;
  RequestSink sink_;
};

HttpResponse json_error(int status, const std::string& message);

}  // namespace hg::station
