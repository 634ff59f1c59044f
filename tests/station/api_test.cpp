// hg-station's request handling without sockets (station/api.hpp): login and sessions, CSRF, roles, input
// validation with the planner's ranges, routing, static files, the users file, the login rate limit.
#include <gtest/gtest.h>

#include <filesystem>
#include <fstream>
#include <random>

#include "station/api.hpp"

namespace hg::station {
namespace {

namespace fs = std::filesystem;

// One hash per role for the whole binary: argon2id is slow on purpose.
const std::vector<User>& test_users() {
  static const std::vector<User> users = {{"op", Role::Operator, hash_password("op-password")},
                                          {"vi", Role::Viewer, hash_password("vi-password")}};
  return users;
}

struct Fixture : ::testing::Test {
  fs::path dir = fs::temp_directory_path() / ("hg-station-api-" + random_token(6));
  Sessions sessions{std::chrono::seconds(3600)};
  LoginLimiter limiter{3, std::chrono::seconds(60)};
  LiveState live{LiveOptions{}};
  History history{dir / "jobs"};
  std::vector<hullgrind::job_request_t> sent;
  std::unique_ptr<Api> api;

  void SetUp() override {
    fs::create_directories(dir / "web");
    fs::create_directories(dir / "jobs");
    std::ofstream(dir / "web" / "index.html") << "<!doctype html>";
    std::ofstream(dir / "secret.txt") << "secret";
    ApiConfig c;
    c.web_root = dir / "web";
    c.three_root = dir / "web";
    c.limits.max_speed = 0.25;
    api = std::make_unique<Api>(c, test_users(), sessions, limiter, live, history, [this](auto& r) {
      sent.push_back(r);
      return true;
    });
  }
  void TearDown() override { fs::remove_all(dir); }

  HttpResponse call(const std::string& method, const std::string& target, const std::string& body = "",
                    const std::string& cookie = "", const std::string& csrf = "") {
    HttpRequest r{method, target, cookie, csrf, "application/json", body, "127.0.0.1"};
    return api->handle(r);
  }
  // Logs in; returns {cookie header, csrf}.
  std::pair<std::string, std::string> login(const std::string& user, const std::string& pw) {
    HttpResponse r = call("POST", "/api/login", Json{{"user", user}, {"password", pw}}.dump());
    EXPECT_EQ(r.status, 200) << r.body;
    std::string cookie;
    for (auto& [k, v] : r.headers)
      if (k == "Set-Cookie") cookie = v.substr(0, v.find(';'));
    return {cookie, Json::parse(r.body)["csrf"].get<std::string>()};
  }
  Json body(const HttpResponse& r) { return Json::parse(r.body); }
};

TEST(StationAuth, PasswordHashIsArgon2idSaltedAndVerifies) {
  const std::string a = hash_password("correct horse"), b = hash_password("correct horse");
  EXPECT_EQ(a.rfind("$argon2id$", 0), 0u);
  EXPECT_NE(a, b);  // salted
  EXPECT_TRUE(verify_password(a, "correct horse"));
  EXPECT_FALSE(verify_password(a, "correct horsE"));
  EXPECT_FALSE(verify_password("", "x"));
  EXPECT_FALSE(verify_password("garbage", "x"));
}

TEST(StationAuth, UsersFileRoundTripsAndNamesTheLineOfAnError) {
  const fs::path f = fs::temp_directory_path() / ("hg-users-" + random_token(4));
  write_users(f.string(), test_users());
  EXPECT_EQ(fs::status(f).permissions() & fs::perms::all, fs::perms::owner_read | fs::perms::owner_write);
  auto back = read_users(f.string());
  ASSERT_EQ(back.size(), 2u);
  EXPECT_EQ(back[1].name, "vi");
  EXPECT_EQ(back[1].role, Role::Viewer);
  fs::remove(f);
  for (const char* bad : {"x operator", "x admin $argon2id$v", "x operator $sha1$abc", "b@d operator $argon2id$x",
                          "x viewer $argon2id$1\nx viewer $argon2id$2"}) {
    try {
      parse_users(std::string("# c\n") + bad + "\n", "users");
      ADD_FAILURE() << bad;
    } catch (const UsersError& e) {
      EXPECT_NE(std::string(e.what()).find("users line "), std::string::npos) << e.what();
    }
  }
}

TEST(StationAuth, SessionsExpireWhenIdleAndAreBounded) {
  Sessions s(std::chrono::seconds(10), 3);
  const auto t0 = std::chrono::steady_clock::now();
  Session a = s.create("a", Role::Operator, t0);
  EXPECT_EQ(a.id.size(), 64u);
  EXPECT_NE(a.id, a.csrf);
  EXPECT_TRUE(s.find(a.id, t0 + std::chrono::seconds(9)));
  EXPECT_TRUE(s.find(a.id, t0 + std::chrono::seconds(18)));  // refreshed by the last use
  EXPECT_FALSE(s.find(a.id, t0 + std::chrono::seconds(40)));
  for (int i = 0; i < 10; ++i) s.create("u", Role::Viewer, t0);
  EXPECT_EQ(s.size(), 3u);
}

TEST(StationAuth, LoginLimiterWaitsAfterFailuresAndForgetsAfterTheWindow) {
  LoginLimiter l(3, std::chrono::seconds(60));
  const auto t0 = std::chrono::steady_clock::now();
  for (int i = 0; i < 3; ++i) {
    EXPECT_EQ(l.wait_seconds("k", t0), 0);
    l.failed("k", t0);
  }
  EXPECT_GT(l.wait_seconds("k", t0 + std::chrono::seconds(1)), 0);
  EXPECT_EQ(l.wait_seconds("other", t0), 0);
  EXPECT_EQ(l.wait_seconds("k", t0 + std::chrono::seconds(61)), 0);
}

TEST_F(Fixture, EveryApiButLoginNeedsASession) {
  for (const char* t : {"/api/cell", "/api/jobs", "/api/jobs/x", "/api/jobs/x/files/path.json", "/api/live"})
    EXPECT_EQ(call("GET", t).status, 401) << t;
  for (const char* t : {"/api/jobs", "/api/jobs/x/approve", "/api/jobs/x/abort", "/api/robot/reset", "/api/logout"})
    EXPECT_EQ(call("POST", t, "{}").status, 401) << t;
  EXPECT_EQ(body(call("GET", "/api/session"))["user"], nullptr);
  EXPECT_TRUE(sent.empty());
}

TEST_F(Fixture, LoginSetsAStrictHttpOnlyCookieAndWrongPasswordsAreRateLimited) {
  HttpResponse r = call("POST", "/api/login", R"({"user":"op","password":"op-password"})");
  ASSERT_EQ(r.status, 200);
  std::string cookie;
  for (auto& [k, v] : r.headers)
    if (k == "Set-Cookie") cookie = v;
  EXPECT_NE(cookie.find("HttpOnly"), std::string::npos);
  EXPECT_NE(cookie.find("SameSite=Strict"), std::string::npos);
  EXPECT_EQ(cookie.find("Secure"), std::string::npos);  // no TLS here
  EXPECT_EQ(call("POST", "/api/login", R"({"user":"op","password":"nope"})").status, 401);
  EXPECT_EQ(call("POST", "/api/login", R"({"user":"nobody","password":"nope"})").status, 401);
  EXPECT_EQ(call("POST", "/api/login", R"({"user":"op"})").status, 400);
  EXPECT_EQ(call("POST", "/api/login", "not json").status, 400);
  for (int i = 0; i < 3; ++i) call("POST", "/api/login", R"({"user":"vi","password":"nope"})");
  // Rate limited now: even the right password waits (429 with Retry-After).
  HttpResponse limited = call("POST", "/api/login", R"({"user":"vi","password":"vi-password"})");
  EXPECT_EQ(limited.status, 429);
  EXPECT_EQ(limited.headers.at(0).first, "Retry-After");
}

TEST_F(Fixture, PostsNeedTheSessionsCsrfTokenAndAnOperator) {
  auto [cookie, csrf] = login("op", "op-password");
  const std::string start = R"({"part_id":"plate-7"})";
  EXPECT_EQ(call("POST", "/api/jobs", start, cookie).status, 403);
  // The session's token with its first character changed (to one it is not: a token may begin with '0').
  const std::string forged = (csrf[0] == '0' ? "1" : "0") + csrf.substr(1);
  EXPECT_EQ(call("POST", "/api/jobs", start, cookie, forged).status, 403);
  HttpResponse ok = call("POST", "/api/jobs", start, cookie, csrf);
  ASSERT_EQ(ok.status, 202) << ok.body;
  ASSERT_EQ(sent.size(), 1u);
  EXPECT_EQ(int(sent[0].action), int(hullgrind::job_request_t::ACTION_START));
  EXPECT_EQ(sent[0].part_id, "plate-7");
  EXPECT_EQ(sent[0].actor, "operator op");
  EXPECT_EQ(sent[0].job_id, body(ok)["job_id"]);
  // The page opens the job right after the POST, before any process answers on the bus: it is there.
  HttpResponse opened = call("GET", "/api/jobs/" + sent[0].job_id, "", cookie);
  ASSERT_EQ(opened.status, 200) << opened.body;
  EXPECT_EQ(body(opened)["live"]["state"], "REQUESTED");
  EXPECT_EQ(body(opened)["live"]["part_id"], "plate-7");
  auto [vcookie, vcsrf] = login("vi", "vi-password");
  EXPECT_EQ(call("POST", "/api/jobs", start, vcookie, vcsrf).status, 403);
  EXPECT_EQ(call("POST", "/api/jobs/x/approve", "{}", vcookie, vcsrf).status, 403);
  EXPECT_EQ(call("GET", "/api/cell", "", vcookie).status, 200);
  EXPECT_EQ(call("POST", "/api/logout", "{}", vcookie, vcsrf).status, 200);  // a viewer may log out
  EXPECT_EQ(call("GET", "/api/cell", "", vcookie).status, 401);
  EXPECT_EQ(sent.size(), 1u);
}

TEST_F(Fixture, OptionsAreValidatedWithThePlannersRangesAndTheCellsSpeed) {
  auto [cookie, csrf] = login("op", "op-password");
  auto start = [&](const std::string& options) {
    return call("POST", "/api/jobs", R"({"part_id":"p","options":)" + options + "}", cookie, csrf);
  };
  for (const char* bad :
       {R"({"grind_speed":0})", R"({"grind_speed":0.26})", R"({"grind_speed":-1})", R"({"grind_speed":"fast"})",
        R"({"travel_speed":1})", R"({"step":0})", R"({"step":-0.1})", R"({"safe_height":0})", R"({"direction":"up"})",
        R"({"tool_radius":0.02})", R"([1])", R"({"grind_speed":1e400})"}) {
    HttpResponse r = start(bad);
    EXPECT_EQ(r.status, 400) << bad;
    EXPECT_TRUE(body(r).contains("error"));
  }
  EXPECT_TRUE(sent.empty());
  ASSERT_EQ(start(R"({"grind_speed":0.25,"step":0.003,"direction":"conventional","travel_speed":0.2})").status, 202);
  ASSERT_EQ(sent.size(), 1u);
  EXPECT_DOUBLE_EQ(sent[0].grind_speed, 0.25);
  EXPECT_DOUBLE_EQ(sent[0].step, 0.003);
  EXPECT_EQ(int(sent[0].direction), int(hullgrind::job_request_t::DIRECTION_CONVENTIONAL));
  for (const char* bad_part :
       {R"({"part_id":""})", R"({"part_id":7})", "{}", R"({"part_id":"a\u0001b"})", R"({"part_id":"p","extra":1})"})
    EXPECT_EQ(call("POST", "/api/jobs", bad_part, cookie, csrf).status, 400) << bad_part;
}

TEST_F(Fixture, ApproveCarriesExcludedLoopsAndRevisionAndRefusesBadLists) {
  auto [cookie, csrf] = login("op", "op-password");
  HttpResponse r =
      call("POST", "/api/jobs/job-1/approve", R"({"exclude_loops":[2,0,2],"plan_revision":3})", cookie, csrf);
  ASSERT_EQ(r.status, 202) << r.body;
  ASSERT_EQ(sent.size(), 1u);
  EXPECT_EQ(int(sent[0].action), int(hullgrind::job_request_t::ACTION_APPROVE));
  EXPECT_EQ(sent[0].job_id, "job-1");
  EXPECT_EQ(sent[0].excluded_loops, (std::vector<std::int16_t>{2, 0}));
  EXPECT_EQ(sent[0].num_excluded, 2);
  EXPECT_EQ(sent[0].plan_revision, 3);
  for (const char* bad : {R"({"exclude_loops":[-1]})", R"({"exclude_loops":[40000]})", R"({"exclude_loops":"1"})",
                          R"({"exclude_loops":[1.5]})", R"({"plan_revision":-2})", R"({"other":1})"})
    EXPECT_EQ(call("POST", "/api/jobs/job-1/approve", bad, cookie, csrf).status, 400) << bad;
  EXPECT_EQ(sent.size(), 1u);
}

TEST_F(Fixture, ActionsMapToTheJobProtocol) {
  auto [cookie, csrf] = login("op", "op-password");
  ASSERT_EQ(call("POST", "/api/jobs/j/reject", "", cookie, csrf).status, 202);
  ASSERT_EQ(call("POST", "/api/jobs/j/abort", "{}", cookie, csrf).status, 202);
  ASSERT_EQ(call("POST", "/api/jobs/j/replan", R"({"options":{"step":0.004}})", cookie, csrf).status, 202);
  ASSERT_EQ(call("POST", "/api/robot/reset", "{}", cookie, csrf).status, 202);
  EXPECT_EQ(call("POST", "/api/jobs/j/explode", "{}", cookie, csrf).status, 404);
  ASSERT_EQ(sent.size(), 4u);
  EXPECT_EQ(int(sent[0].action), int(hullgrind::job_request_t::ACTION_REJECT));
  EXPECT_EQ(int(sent[1].action), int(hullgrind::job_request_t::ACTION_ABORT));
  EXPECT_EQ(int(sent[2].action), int(hullgrind::job_request_t::ACTION_REPLAN));
  EXPECT_DOUBLE_EQ(sent[2].step, 0.004);
  EXPECT_EQ(int(sent[3].action), int(hullgrind::job_request_t::ACTION_RESET));
  EXPECT_EQ(sent[3].job_id.rfind("reset-", 0), 0u);  // a RESET has an id of its own
  for (const auto& r : sent) EXPECT_EQ(r.actor, "operator op");
}

TEST_F(Fixture, AnEndedJobIsNotActedOn) {
  hullgrind::job_status_t s{};
  s.job_id = "done-1";
  s.source = "hg-robot-bridge";
  s.state = hullgrind::job_status_t::STATE_DONE;
  live.on_status(s, 1);
  auto [cookie, csrf] = login("op", "op-password");
  EXPECT_EQ(call("POST", "/api/jobs/done-1/abort", "{}", cookie, csrf).status, 409);
  EXPECT_EQ(call("POST", "/api/jobs/done-1/approve", "{}", cookie, csrf).status, 409);
  EXPECT_TRUE(sent.empty());
}

TEST_F(Fixture, StaticFilesStayInsideTheWebRoot) {
  EXPECT_EQ(call("GET", "/").status, 200);
  EXPECT_EQ(call("GET", "/").file, dir / "web" / "index.html");
  for (const char* t : {"/../secret.txt", "/%2e%2e/secret.txt", "/..%2Fsecret.txt", "/.hidden", "/three/../x", "/a%00b",
                        "/nope.js", "relative", ""})
    EXPECT_TRUE(call("GET", t).file.empty()) << t;
  EXPECT_EQ(call("DELETE", "/").status, 405);
  EXPECT_EQ(call("PUT", "/api/jobs").status, 405);
}

TEST_F(Fixture, HistoryListsFiltersAndServesOnlyRecordFiles) {
  auto [cookie, csrf] = login("op", "op-password");
  auto record = [&](const std::string& id, const std::string& part, const std::string& state, const std::string& day) {
    fs::create_directories(dir / "jobs" / id);
    std::ofstream(dir / "jobs" / id / "job.json")
        << Json{{"job_id", id}, {"part_id", part}, {"state", state}, {"requested", day + "T10:00:00Z"}}.dump();
    std::ofstream(dir / "jobs" / id / "path.json") << R"({"job_id":")" + id + "\"}";
    std::ofstream(dir / "jobs" / id / "other.bin") << "x";
  };
  record("a", "plate-1", "DONE", "2026-11-01");
  record("b", "plate-2", "FAILED", "2026-11-02");
  record("c", "hull-1", "DONE", "2026-11-03");
  fs::create_directories(dir / "jobs" / "broken");
  std::ofstream(dir / "jobs" / "broken" / "job.json") << "{not json";
  auto ids = [&](const std::string& q) {
    std::vector<std::string> out;
    const Json list = body(call("GET", "/api/jobs" + q, "", cookie));
    for (const Json& j : list["jobs"]) out.push_back(j["job_id"]);
    return out;
  };
  EXPECT_EQ(ids(""), (std::vector<std::string>{"c", "b", "a"}));
  EXPECT_EQ(ids("?state=DONE"), (std::vector<std::string>{"c", "a"}));
  EXPECT_EQ(ids("?part=plate"), (std::vector<std::string>{"b", "a"}));
  EXPECT_EQ(ids("?from=2026-11-02&to=2026-11-02"), (std::vector<std::string>{"b"}));
  HttpResponse f = call("GET", "/api/jobs/a/files/path.json", "", cookie);
  EXPECT_EQ(f.file, dir / "jobs" / "a" / "path.json");
  EXPECT_EQ(call("GET", "/api/jobs/a/files/other.bin", "", cookie).status, 404);
  EXPECT_EQ(call("GET", "/api/jobs/a/files/..%2Fb%2Fpath.json", "", cookie).status, 404);
  EXPECT_EQ(call("GET", "/api/jobs/zzz", "", cookie).status, 404);
  Json rec = body(call("GET", "/api/jobs/b", "", cookie));
  EXPECT_EQ(rec["record"]["job"]["state"], "FAILED");
  EXPECT_EQ(rec["record"]["files"].size(), 2u);  // job.json, path.json
}

TEST(StationTarget, RandomTargetsNeverThrowAndDecodeOnlyValidEscapes) {
  std::mt19937 rng(7);
  const std::string alphabet = "/%?&=+.aZ09\x01\x7f ";
  for (int i = 0; i < 20000; ++i) {
    std::string t;
    const int n = int(rng() % 40);
    for (int k = 0; k < n; ++k) t += alphabet[rng() % alphabet.size()];
    auto parsed = parse_target(t);
    if (parsed)
      for (const std::string& s : parsed->segments)
        for (char c : s) EXPECT_GE(static_cast<unsigned char>(c), 0x20) << t;
  }
  auto t = parse_target("/api/jobs/a%2Fb?state=DONE&part=x+y");
  ASSERT_TRUE(t);
  EXPECT_EQ(t->segments, (std::vector<std::string>{"api", "jobs", "a/b"}));
  EXPECT_EQ(t->query["part"], "x y");
  EXPECT_FALSE(parse_target("/a%zz"));
  EXPECT_FALSE(parse_target("/a%2"));
}

}  // namespace
}  // namespace hg::station
