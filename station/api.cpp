#include "station/api.hpp"

#include "runtime/quantities.hpp"

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <set>
#include <optional>

namespace hg::station {

namespace fs = std::filesystem;
using hullgrind::job_request_t;
using hullgrind::job_status_t;

namespace {

constexpr std::size_t kMaxTarget = 2048, kMaxExcluded = 1000;

int hex_digit(char c) {
  if (c >= '0' && c <= '9') return c - '0';
  if (c >= 'a' && c <= 'f') return c - 'a' + 10;
  if (c >= 'A' && c <= 'F') return c - 'A' + 10;
  return -1;
}

std::optional<std::string> url_decode(const std::string& s, bool plus_is_space) {
  std::string out;
  for (std::size_t i = 0; i < s.size(); ++i) {
    char c = s[i];
    if (c == '%') {
      if (i + 2 >= s.size()) return std::nullopt;
      const int hi = hex_digit(s[i + 1]), lo = hex_digit(s[i + 2]);
      if (hi < 0 || lo < 0) return std::nullopt;
      c = static_cast<char>(hi * 16 + lo);
      i += 2;
    } else if (c == '+' && plus_is_space) {
      c = ' ';
    }
    if (static_cast<unsigned char>(c) < 0x20 || c == 0x7f) return std::nullopt;
    out += c;
  }
  return out;
}

std::string content_type_of(const fs::path& p) {
  const std::string ext = p.extension().string();
  if (ext == ".html") return "text/html; charset=utf-8";
  if (ext == ".js") return "text/javascript; charset=utf-8";
  if (ext == ".css") return "text/css; charset=utf-8";
  if (ext == ".png") return "image/png";
  if (ext == ".svg") return "image/svg+xml";
  if (ext == ".ico") return "image/x-icon";
  if (ext == ".json") return "application/json";
  return "application/octet-stream";
}

bool safe_segment(const std::string& s) {
  if (s.empty() || s[0] == '.' || s.size() > 100) return false;
  return std::all_of(s.begin(), s.end(), [](char c) {
    return std::isalnum(static_cast<unsigned char>(c)) || c == '_' || c == '-' || c == '.';
  });
}

HttpResponse ok(Json body, int status = 200) {
  HttpResponse r;
  r.status = status;
  r.body = body.dump(-1, ' ', false, Json::error_handler_t::replace);
  return r;
}

std::string number_text(double v) {
  char buf[32];
  std::snprintf(buf, sizeof buf, "%g", v);
  return buf;
}

// A job quantity under its name (runtime/quantities.hpp): within its one range and at most `max` (the cell's
// limit), or an error text naming it.
std::string quantity_option(const Json& options, const quantity::Quantity& q, double max, double& out) {
  auto it = options.find(q.name);
  if (it == options.end() || it->is_null()) return "";
  if (!it->is_number()) return std::string("options.") + q.name + ": must be a number";
  const double v = it->get<double>();
  if (std::string why = quantity::out_of_range(q, v); !why.empty()) return "options." + why;
  if (v > max)
    return std::string("options.") + q.name + ": " + number_text(v) + " exceeds the cell's " + number_text(max);
  out = v;
  return "";
}

std::string actor_of(const Session& s) { return "operator " + s.user; }

// The wall clock in microseconds, as LCM's receive times.
std::int64_t wall_utime() {
  return std::chrono::duration_cast<std::chrono::microseconds>(std::chrono::system_clock::now().time_since_epoch())
      .count();
}

}  // namespace

HttpResponse json_error(int status, const std::string& message) {
  HttpResponse r = ok({{"error", message}, {"status", status}}, status);
  return r;
}

std::optional<Target> parse_target(const std::string& target) {
  if (target.empty() || target.size() > kMaxTarget || target[0] != '/') return std::nullopt;
  const std::size_t q = target.find('?');
  const std::string path = target.substr(0, q);
  Target t;
  std::size_t start = 1;
  while (start <= path.size()) {
    const std::size_t end = std::min(path.find('/', start), path.size());
    auto seg = url_decode(path.substr(start, end - start), false);
    if (!seg) return std::nullopt;
    if (!seg->empty()) t.segments.push_back(*seg);
    start = end + 1;
  }
  if (q == std::string::npos) return t;
  const std::string query = target.substr(q + 1);
  for (std::size_t s = 0; s < query.size();) {
    const std::size_t e = std::min(query.find('&', s), query.size());
    const std::string pair = query.substr(s, e - s);
    const std::size_t eq = pair.find('=');
    auto k = url_decode(pair.substr(0, eq), true);
    auto v = url_decode(eq == std::string::npos ? "" : pair.substr(eq + 1), true);
    if (!k || !v) return std::nullopt;
    if (!k->empty()) t.query[*k] = *v;
    s = e + 1;
  }
  return t;
}

bool valid_job_id(const std::string& id) {
  if (id.empty() || id.size() > 120) return false;
  return std::all_of(id.begin(), id.end(), [](char c) { return c > 0x20 && c < 0x7f; });
}

bool valid_part_id(const std::string& id) {
  if (id.empty() || id.size() > 64) return false;
  return std::all_of(id.begin(), id.end(), [](char c) {
    const auto u = static_cast<unsigned char>(c);
    return u >= 0x20 && u != 0x7f;
  });
}

std::string apply_options(const Json& options, const OptionLimits& limits, job_request_t& req) {
  if (options.is_null()) return "";
  if (!options.is_object()) return "options: must be an object";
  static const std::set<std::string> known = {"grind_speed", "travel_speed", "step", "safe_height", "direction"};
  for (const auto& [key, value] : options.items())
    if (!known.count(key))
      return "options." + key + ": unknown (grind_speed, travel_speed, step, safe_height, direction)";
  const double inf = std::numeric_limits<double>::infinity();
  for (const std::string& e : {quantity_option(options, quantity::kGrindSpeed, limits.max_speed, req.grind_speed),
                               quantity_option(options, quantity::kTravelSpeed, limits.max_speed, req.travel_speed),
                               quantity_option(options, quantity::kStep, inf, req.step),
                               quantity_option(options, quantity::kSafeHeight, inf, req.safe_height)})
    if (!e.empty()) return e;
  auto dir = options.find("direction");
  if (dir != options.end() && !dir->is_null()) {
    const auto d = dir->is_string() ? job::direction_from_name(dir->get<std::string>()) : std::nullopt;
    if (!d) return "options.direction: must be \"climb\" or \"conventional\"";
    req.direction = std::int8_t(*d);
  }
  return "";
}

Api::Api(ApiConfig config, std::vector<User> users, Sessions& sessions, LoginLimiter& limiter, LiveState& live,
         const History& history, RequestSink sink)
    : config_(std::move(config)),
      sessions_(sessions),
      limiter_(limiter),
      live_(live),
      history_(history),
      sink_(std::move(sink)) {
  set_users(std::move(users));
}

void Api::set_users(std::vector<User> users) {
  std::map<std::string, User> by_name;
  for (User& u : users) by_name[u.name] = std::move(u);
  std::lock_guard lock(users_mutex_);
  users_ = std::move(by_name);
}

std::size_t Api::user_count() const {
  std::lock_guard lock(users_mutex_);
  return users_.size();
}

std::string Api::cookie_value(const std::string& header, const std::string& name) {
  std::size_t pos = 0;
  while (pos < header.size()) {
    const std::size_t end = std::min(header.find(';', pos), header.size());
    std::string part = header.substr(pos, end - pos);
    const std::size_t b = part.find_first_not_of(' ');
    if (b != std::string::npos) part = part.substr(b);
    if (part.size() > name.size() && part.compare(0, name.size(), name) == 0 && part[name.size()] == '=')
      return part.substr(name.size() + 1);
    pos = end + 1;
  }
  return "";
}

std::optional<Session> Api::session_of(const HttpRequest& req) {
  const std::string id = cookie_value(req.cookie, kCookie);
  if (id.empty()) return std::nullopt;
  auto s = sessions_.find(id, std::chrono::steady_clock::now());
  if (!s) return s;
  std::lock_guard lock(users_mutex_);
  auto u = users_.find(s->user);
  if (u == users_.end() || u->second.role != s->role) {  // removed, or the role changed: log in again
    sessions_.remove(id);
    return std::nullopt;
  }
  return s;
}

HttpResponse Api::handle(const HttpRequest& req) {
  auto t = parse_target(req.target);
  if (!t) return json_error(400, "malformed request target");
  if (!t->segments.empty() && t->segments[0] == "api") return route_api(req, *t);
  if (req.method != "GET" && req.method != "HEAD") return json_error(405, "only GET outside /api");
  return static_file(*t);
}

HttpResponse Api::route_api(const HttpRequest& req, const Target& t) {
  const bool post = req.method == "POST";
  if (!post && req.method != "GET") return json_error(405, "method " + req.method + " not allowed");
  if (post && t.segments.size() == 2 && t.segments[1] == "login") return login(req);
  auto session = session_of(req);
  if (!session && !post && t.segments.size() == 2 && t.segments[1] == "session")
    return ok({{"user", nullptr}});  // the page asks whether it is logged in: not an error
  if (!session) return json_error(401, "not logged in");
  if (!post && t.segments.size() == 2 && t.segments[1] == "session")
    return ok({{"user", session->user}, {"role", role_name(session->role)}, {"csrf", session->csrf}});
  if (!post) return get_api(t);
  if (req.csrf.empty() || req.csrf != session->csrf) return json_error(403, "missing or wrong X-CSRF-Token");
  if (t.segments.size() == 2 && t.segments[1] == "logout") return logout(req);
  if (session->role != Role::Operator) return json_error(403, "user " + session->user + " is a viewer");
  if (!req.body.empty() && req.content_type.rfind("application/json", 0) != 0)
    return json_error(415, "the body must be application/json");
  Json body = req.body.empty() ? Json::object() : Json::parse(req.body, nullptr, false);
  if (body.is_discarded() || !body.is_object()) return json_error(400, "the body is not a JSON object");
  return post_api(*session, t, body);
}

HttpResponse Api::get_api(const Target& t) {
  const auto& s = t.segments;
  if (s.size() == 2 && s[1] == "cell") return cell();
  if (s.size() == 2 && s[1] == "jobs") return jobs(t);
  if (s.size() == 3 && s[1] == "jobs") return job(s[2]);
  if (s.size() == 5 && s[1] == "jobs" && s[3] == "files") return job_file(s[2], s[4]);
  if (s.size() == 2 && s[1] == "live") return json_error(400, "/api/live is a WebSocket: send Upgrade");
  return json_error(404, "no such API: GET /" + (s.size() > 1 ? s[0] + "/" + s[1] : s[0]));
}

HttpResponse Api::post_api(const Session& session, const Target& t, const Json& body) {
  const auto& s = t.segments;
  if (s.size() == 2 && s[1] == "jobs") return start_job(session, body);
  if (s.size() == 3 && s[1] == "robot" && s[2] == "reset") return job_action(session, "", "reset", body);
  if (s.size() == 4 && s[1] == "jobs") return job_action(session, s[2], s[3], body);
  return json_error(404, "no such API: POST /" + (s.size() > 1 ? s[0] + "/" + s[1] : s[0]));
}

HttpResponse Api::login(const HttpRequest& req) {
  Json body = Json::parse(req.body, nullptr, false);
  if (body.is_discarded() || !body.is_object() || !body.contains("user") || !body["user"].is_string() ||
      !body.contains("password") || !body["password"].is_string())
    return json_error(400, "login needs {\"user\": text, \"password\": text}");
  const std::string user = body["user"], password = body["password"];
  const auto now = std::chrono::steady_clock::now();
  const std::string user_key = "user " + user.substr(0, 64), peer_key = "peer " + req.peer;
  const int wait = std::max(limiter_.wait_seconds(user_key, now), limiter_.wait_seconds(peer_key, now));
  if (wait > 0) {
    HttpResponse r = json_error(429, "too many failed logins: try again in " + std::to_string(wait) + " s");
    r.headers.emplace_back("Retry-After", std::to_string(wait));
    return r;
  }
  std::optional<User> found;
  {
    std::lock_guard lock(users_mutex_);
    auto it = users_.find(user);
    if (it != users_.end()) found = it->second;
  }
  if (!found || password.size() > 1024 || !verify_password(found->hash, password)) {
    limiter_.failed(user_key, now);
    limiter_.failed(peer_key, now);
    return json_error(401, "wrong user or password");
  }
  limiter_.succeeded(user_key);
  const Session s = sessions_.create(found->name, found->role, now);
  HttpResponse r = ok({{"user", s.user}, {"role", role_name(s.role)}, {"csrf", s.csrf}});
  r.headers.emplace_back("Set-Cookie", std::string(kCookie) + "=" + s.id + "; Path=/; HttpOnly; SameSite=Strict" +
                                           (config_.tls ? "; Secure" : ""));
  return r;
}

HttpResponse Api::logout(const HttpRequest& req) {
  sessions_.remove(cookie_value(req.cookie, kCookie));
  HttpResponse r = ok({{"logged_out", true}});
  r.headers.emplace_back("Set-Cookie", std::string(kCookie) + "=; Path=/; HttpOnly; SameSite=Strict; Max-Age=0" +
                                           (config_.tls ? "; Secure" : ""));
  return r;
}

HttpResponse Api::cell() const {
  const std::int64_t now = wall_utime();
  Json processes = live_.processes(now), robot = live_.robot(now);
  Json faults = Json::array();
  for (const Json& p : processes)
    if (p["state"] == hullgrind::heartbeat_t::STATE_ERROR || p["state"] == hullgrind::heartbeat_t::STATE_DEGRADED)
      faults.push_back({{"source", p["process"]}, {"reason", p["state_text"]}});
  if (robot.is_object() && robot["fault_code"] != 0)
    faults.push_back({{"source", "robot"}, {"reason", robot["fault_text"]}, {"code", robot["fault_code"]}});
  Json supervisor = config_.supervisor ? config_.supervisor() : Json(nullptr);
  return ok({{"processes", processes},
             {"supervisor", supervisor},
             {"robot", robot},
             {"camera_fps", live_.camera_fps()},
             {"cell", config_.cell},
             {"faults", faults},
             {"limits", {{"max_speed", config_.limits.max_speed}}},
             {"station", config_.station ? config_.station() : Json(nullptr)}});
}

HttpResponse Api::jobs(const Target& t) const {
  HistoryFilter f;
  auto q = [&](const char* k) {
    auto it = t.query.find(k);
    return it == t.query.end() ? std::string() : it->second.substr(0, 120);
  };
  f.state = q("state"), f.part = q("part"), f.from = q("from"), f.to = q("to");
  Json rows = history_.list(f);
  std::set<std::string> recorded;
  for (const Json& r : rows) recorded.insert(r["job_id"].get<std::string>());
  Json live = Json::array();  // jobs the station heard that the ledger does not hold (yet)
  for (const Json& j : live_.jobs())
    if (!recorded.count(j["job_id"].get<std::string>()) && (f.state.empty() || j["state"] == f.state) &&
        j["part_id"].get<std::string>().find(f.part) != std::string::npos)
      live.push_back(j);
  return ok({{"jobs", rows}, {"live_only", live}, {"ledger", history_.enabled()}});
}

HttpResponse Api::job(const std::string& id) const {
  if (!valid_job_id(id)) return json_error(400, "bad job id");
  auto record = history_.record(id);
  Json live = live_.job(id);
  if (!record && live.is_null()) return json_error(404, "no job " + id);
  return ok({{"job_id", id}, {"record", record ? *record : Json(nullptr)}, {"live", live}});
}

HttpResponse Api::job_file(const std::string& id, const std::string& name) const {
  if (!valid_job_id(id)) return json_error(400, "bad job id");
  if (!History::downloadable_name(name)) return json_error(404, "no file " + name + " in a job record");
  auto f = history_.file(id, name);
  if (!f) return json_error(404, "job " + id + " has no " + name);
  HttpResponse r;
  r.file = *f;
  r.content_type = name.ends_with(".json") ? "application/json" : name.ends_with(".png") ? "image/png" : "text/plain";
  r.headers.emplace_back("Content-Disposition", "attachment; filename=\"" + name + "\"");
  return r;
}

HttpResponse Api::start_job(const Session& s, const Json& body) {
  for (const auto& [key, v] : body.items())
    if (key != "part_id" && key != "options") return json_error(400, key + ": unknown (part_id, options)");
  if (!body.contains("part_id") || !body["part_id"].is_string() || !valid_part_id(body["part_id"]))
    return json_error(400, "part_id: 1-64 printable characters");
  job_request_t req{};
  const std::string err = apply_options(body.value("options", Json(nullptr)), config_.limits, req);
  if (!err.empty()) return json_error(400, err);
  req.job_id = "st-" + random_token(6);
  req.part_id = body["part_id"];
  req.action = job_request_t::ACTION_START;
  req.actor = actor_of(s);
  HttpResponse answer = send(req, 202, {{"job_id", req.job_id}, {"part_id", req.part_id}});
  if (answer.status == 202) live_.on_requested(req, wall_utime());
  return answer;
}

HttpResponse Api::job_action(const Session& s, const std::string& id, const std::string& action, const Json& body) {
  if (action != "reset" && !valid_job_id(id)) return json_error(400, "bad job id");
  if (action == "approve") return approve(s, id, body);
  job_request_t req{};
  req.job_id = id;
  req.actor = actor_of(s);
  if (action == "reject") {
    req.action = job_request_t::ACTION_REJECT;
  } else if (action == "abort") {
    req.action = job_request_t::ACTION_ABORT;
  } else if (action == "reset") {
    req.action = job_request_t::ACTION_RESET;
    req.job_id = "reset-" + random_token(6);  // a RESET needs an id of its own (robot bridge)
  } else if (action == "replan") {
    for (const auto& [key, v] : body.items())
      if (key != "options") return json_error(400, key + ": unknown (options)");
    const std::string err = apply_options(body.value("options", Json::object()), config_.limits, req);
    if (!err.empty()) return json_error(400, err);
    req.action = job_request_t::ACTION_REPLAN;
  } else {
    return json_error(404, "no such action: " + action);
  }
  const int state = live_.job_state(id);
  if (action != "reset" && state >= 0 && state_terminal(state))
    return json_error(409, "job " + id + " has ended " + state_name(state));
  return send(req, 202, {{"job_id", req.job_id}, {"action", action}});
}

HttpResponse Api::approve(const Session& s, const std::string& id, const Json& body) {
  for (const auto& [key, v] : body.items())
    if (key != "exclude_loops" && key != "plan_revision")
      return json_error(400, key + ": unknown (exclude_loops, plan_revision)");
  job_request_t req{};
  req.job_id = id;
  req.actor = actor_of(s);
  req.action = job_request_t::ACTION_APPROVE;
  const Json none = Json::array();
  const Json& loops = body.contains("exclude_loops") ? body["exclude_loops"] : none;
  if (!loops.is_array() || loops.size() > kMaxExcluded) return json_error(400, "exclude_loops: a list of loop numbers");
  std::set<int> seen;
  for (const Json& l : loops) {
    if (!l.is_number_integer() || l.get<long long>() < 0 || l.get<long long>() > 32767)
      return json_error(400, "exclude_loops: every entry a loop number 0..32767");
    if (seen.insert(l.get<int>()).second) req.excluded_loops.push_back(static_cast<std::int16_t>(l.get<int>()));
  }
  req.num_excluded = static_cast<std::int32_t>(req.excluded_loops.size());
  if (body.contains("plan_revision")) {
    if (!body["plan_revision"].is_number_integer() || body["plan_revision"].get<long long>() < 0 ||
        body["plan_revision"].get<long long>() > 1000000)
      return json_error(400, "plan_revision: a whole number >= 0 (0: the latest)");
    req.plan_revision = body["plan_revision"].get<std::int32_t>();
  }
  const int state = live_.job_state(id);
  if (state >= 0 && state != job_status_t::STATE_AWAITING_APPROVAL)
    return json_error(409, "job " + id + " is " + state_name(state) + ", not AWAITING_APPROVAL");
  return send(req, 202, {{"job_id", id}, {"action", "approve"}, {"exclude_loops", req.excluded_loops}});
}

HttpResponse Api::send(job_request_t& req, int status, Json answer) {
  if (!sink_ || !sink_(req)) return json_error(503, "the bus queue is full: try again");
  return ok(std::move(answer), status);
}

HttpResponse Api::static_file(const Target& t) const {
  fs::path root = config_.web_root;
  std::vector<std::string> segs = t.segments;
  if (!segs.empty() && segs[0] == "three") {
    root = config_.three_root;
    segs.erase(segs.begin());
  }
  if (segs.empty()) segs.push_back("index.html");
  fs::path p = root;
  for (const std::string& s : segs) {
    if (!safe_segment(s)) return json_error(404, "not found");
    p /= s;
  }
  std::error_code ec;
  if (root.empty() || !fs::is_regular_file(p, ec)) return json_error(404, "not found");
  HttpResponse r;
  r.file = p;
  r.content_type = content_type_of(p);
  return r;
}

}  // namespace hg::station
