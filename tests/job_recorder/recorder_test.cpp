// The job history on files: folder names of hostile job ids, one record per job with its final state and
// reason, repeats kept as events, the outline and path files, and jobs interrupted by a recorder that died.
#include <gtest/gtest.h>

#include <filesystem>
#include <fstream>
#include <random>
#include <set>
#include <sstream>
#include <unistd.h>

#include "job_recorder/recorder.hpp"
#include "jobs/job_ledger.hpp"

namespace fs = std::filesystem;
using hg::job_recorder::job_dir_name;
using hg::job_recorder::Recorder;
using hullgrind::job_request_t;
using hullgrind::job_status_t;
using nlohmann::json;

namespace {

// The id back from a folder name (the inverse of the escaping, written here from its definition).
std::string unescape(const std::string& name) {
  std::string out;
  for (std::size_t i = 0; i < name.size(); ++i) {
    if (name[i] == '%' && i + 2 < name.size()) {
      out += char(std::stoi(name.substr(i + 1, 2), nullptr, 16));
      i += 2;
    } else {
      out += name[i];
    }
  }
  return out;
}

bool safe_name(const std::string& n) {
  if (n.empty() || n.size() > 120 || n[0] == '.') return false;
  for (unsigned char c : n)
    if (!(std::isalnum(c) || c == '_' || c == '-' || c == '.' || c == '%' || c == '~')) return false;
  return true;
}

struct TempDir {
  fs::path path;
  explicit TempDir(const std::string& tag) {
    path = fs::temp_directory_path() / ("hg_jobrec_" + tag + "_" + std::to_string(getpid()));
    fs::remove_all(path);
  }
  ~TempDir() { fs::remove_all(path); }
};

json read_json(const fs::path& p) {
  std::ifstream in(p);
  std::stringstream ss;
  ss << in.rdbuf();
  return json::parse(ss.str());
}

std::vector<json> events(const fs::path& dir) {
  std::vector<json> v;
  std::ifstream in(dir / "events.jsonl");
  for (std::string line; std::getline(in, line);) v.push_back(json::parse(line));
  return v;
}

job_request_t request(const std::string& id, std::int8_t action = job_request_t::ACTION_START,
                      const std::string& part = "plate-X") {
  job_request_t r{};
  r.job_id = id;
  r.part_id = part;
  r.action = action;
  r.tool_radius = 0.008;
  return r;
}

job_status_t status(const std::string& id, std::int8_t state, const std::string& source, const std::string& msg,
                    double progress = 0) {
  job_status_t s{};
  s.job_id = id;
  s.source = source;
  s.state = state;
  s.message = msg;
  s.progress = progress;
  return s;
}

hullgrind::outline_t outline(std::int64_t seq) {
  hullgrind::outline_t o{};
  o.header.seq = seq;
  o.header.frame_id = "camera";
  o.status = hullgrind::outline_t::STATUS_OK;
  for (bool hole : {false, true}) {
    hullgrind::outline_loop_t l{};
    l.hole = hole;
    const double s = hole ? 0.05 : 0.3;
    l.u = {0, float(s), float(s), 0};
    l.v = {0, 0, float(s), float(s)};
    l.n = 4;
    o.loops.push_back(l);
  }
  o.num_loops = 2;
  o.plane_normal[2] = -1, o.plane_u_axis[0] = 1, o.plane_v_axis[1] = -1, o.plane_origin[2] = 1.2;
  return o;
}

hullgrind::grind_path_t path(const std::string& id, std::int64_t outline_seq, int n = 3) {
  hullgrind::grind_path_t p{};
  p.job_id = id;
  p.outline_seq = outline_seq;
  p.frame = "robot_base";
  p.n = n;
  for (int i = 0; i < n; ++i) {
    p.position.push_back({0.5 + 0.01 * i, 0, 0.1});
    p.orientation.push_back({0, 1, 0, 0});
    p.speed.push_back(0.02);
    p.kind.push_back(hullgrind::grind_path_t::KIND_GRIND);
    p.loop_index.push_back(0);
  }
  p.tool_radius = 0.008;
  return p;
}

constexpr std::int64_t T0 = 1'764'585'600'000'000;  // 2025-12-01T10:40:00Z

}  // namespace

TEST(JobDirName, HostileIdsStayInsideTheRootAndDistinctIdsGetDistinctNames) {
  EXPECT_EQ(job_dir_name(""), "");
  EXPECT_EQ(job_dir_name("demo-20261201-104000"), "demo-20261201-104000");
  EXPECT_EQ(job_dir_name("a.b"), "a.b");
  EXPECT_EQ(job_dir_name(".."), "%2E.");
  EXPECT_EQ(job_dir_name("../etc"), "%2E.%2Fetc");
  EXPECT_EQ(job_dir_name("a/b"), "a%2Fb");
  EXPECT_EQ(job_dir_name("x\n\x01"), "x%0A%01");
  std::mt19937 rng(15);
  std::set<std::string> ids, names;
  const std::string nasty = "./%~\\\x7f\x80\xff \t\n\x1b.";
  for (int i = 0; i < 20000; ++i) {
    std::string id;
    const int len = 1 + int(rng() % 40);
    for (int k = 0; k < len; ++k) {
      const unsigned r = rng() % 4;
      id += r == 0 ? char(rng() % 256) : r == 1 ? nasty[rng() % nasty.size()] : char('a' + rng() % 3);
    }
    const std::string n = job_dir_name(id);
    ASSERT_TRUE(safe_name(n)) << n;
    EXPECT_NE(n, ".");
    EXPECT_NE(n, "..");
    EXPECT_EQ(unescape(n), id);  // short ids: reversible, so distinct ids never share a folder
    if (ids.insert(id).second) EXPECT_TRUE(names.insert(n).second) << n;
  }
  // Long ids are cut and hashed; still safe and still distinct.
  const std::string long_a(500, '/'), long_b = std::string(499, '/') + "x";
  EXPECT_TRUE(safe_name(job_dir_name(long_a)));
  EXPECT_TRUE(safe_name(job_dir_name(long_b)));
  EXPECT_NE(job_dir_name(long_a), job_dir_name(long_b));
}

TEST(JobRecorder, HostileJobIdIsRecordedInsideTheRoot) {
  TempDir tmp("hostile");
  Recorder rec(tmp.path, T0);
  for (const std::string& id :
       std::vector<std::string>{"../escape", "/abs/path", "..", ".", "a/../../b", std::string("ctl\x01\x7f", 5)}) {
    rec.on_request(request(id), T0);
    const fs::path dir = rec.dir_of(id);
    EXPECT_EQ(fs::canonical(dir).parent_path(), fs::canonical(tmp.path)) << id;
    EXPECT_EQ(read_json(dir / "job.json")["job_id"], id);
  }
  EXPECT_FALSE(fs::exists(tmp.path.parent_path() / "escape"));
  rec.on_request(request(""), T0);  // not recordable: counted
  EXPECT_EQ(rec.stats().rejected_ids, 1);
  std::size_t dirs = 0;
  for (const auto& e : fs::directory_iterator(tmp.path)) dirs += e.is_directory();
  EXPECT_EQ(dirs, 6u);
}

TEST(JobRecorder, ARecordPerJobWithItsFinalStateReasonOutlineAndPath) {
  TempDir tmp("jobs");
  Recorder rec(tmp.path, T0);
  rec.on_outline(outline(41), T0);
  rec.on_outline(outline(42), T0 + 1);
  for (int i = 0; i < 3; ++i) rec.on_request(request("A"), T0 + 10 + i);  // a retrying writer
  rec.on_request(request("B", job_request_t::ACTION_START, "plate-Y"), T0 + 20);
  rec.on_status(status("A", job_status_t::STATE_PLANNING, "hg-path-planner", "planning"), T0 + 30);
  rec.on_status(status("A", job_status_t::STATE_ACCEPTED, "hg-robot-bridge", "accepted"), T0 + 31);
  rec.on_status(status("B", job_status_t::STATE_REFUSED, "hg-robot-bridge", "refused: busy with job A"), T0 + 32);
  rec.on_path(path("A", 42), T0 + 40);
  rec.on_path(path("A", 41, 7), T0 + 41);  // a second path is an event, not the job's path
  rec.on_status(status("A", job_status_t::STATE_PLANNED, "hg-path-planner", "3 waypoints"), T0 + 42);
  rec.on_status(status("A", job_status_t::STATE_RUNNING, "hg-robot-bridge", "running", 0.5), T0 + 50);
  rec.on_status(status("A", job_status_t::STATE_DONE, "hg-robot-bridge", "path complete", 1), 2'000'000 + T0);
  rec.on_status(status("A", job_status_t::STATE_DONE, "hg-robot-bridge", "repeated START ...", 1), T0 + 3'000'000);
  rec.on_status(status("B", job_status_t::STATE_PLANNED, "hg-path-planner", "late"), T0 + 60);  // after B ended

  const json a = read_json(tmp.path / "A" / "job.json");
  EXPECT_EQ(a["state"], "DONE");
  EXPECT_EQ(a["final"], true);
  EXPECT_EQ(a["reason"], "path complete");
  EXPECT_EQ(a["part_id"], "plate-X");
  EXPECT_EQ(a["requests"], 3);
  EXPECT_EQ(a["request"]["tool_radius"], 0.008);
  EXPECT_EQ(a["requested_utime"], T0 + 10);
  EXPECT_EQ(a["ended"], "2025-12-01T10:40:02.000Z");
  EXPECT_EQ(a["path"]["waypoints"], 3);
  EXPECT_EQ(a["outline"]["seq"], 42);
  EXPECT_FALSE(a.contains("interrupted"));
  const json p = read_json(tmp.path / "A" / "path.json");
  EXPECT_EQ(p["job_id"], "A");
  EXPECT_EQ(p["waypoints"].size(), 3u);
  const json o = read_json(tmp.path / "A" / "outline.json");
  ASSERT_EQ(o["loops"].size(), 2u);
  EXPECT_EQ(o["loops"][1]["hole"], true);
  // Every request and status is an event, in order.
  const auto ev = events(tmp.path / "A");
  int requests = 0, statuses = 0, paths = 0;
  for (const auto& e : ev)
    requests += e["event"] == "request", statuses += e["event"] == "status", paths += e["event"] == "path";
  EXPECT_EQ(requests, 3);
  EXPECT_EQ(statuses, 6);
  EXPECT_EQ(paths, 2);
  for (std::size_t i = 1; i < ev.size(); ++i) EXPECT_LE(ev[i - 1]["utime"], ev[i]["utime"]);

  const json b = read_json(tmp.path / "B" / "job.json");
  EXPECT_EQ(b["state"], "REFUSED");  // the first end stands
  EXPECT_EQ(b["reason"], "refused: busy with job A");
  EXPECT_EQ(b["part_id"], "plate-Y");
  EXPECT_FALSE(fs::exists(tmp.path / "B" / "path.json"));
  EXPECT_EQ(rec.stats().records, 2);
}

TEST(JobRecorder, AJobOpenWhenTheRecorderDiesIsMarkedInterruptedAndALaterStatusStillEndsIt) {
  TempDir tmp("interrupted");
  {
    Recorder rec(tmp.path, T0);
    rec.on_request(request("K"), T0);
    rec.on_status(status("K", job_status_t::STATE_RUNNING, "hg-robot-bridge", "waypoint 4", 0.3), T0 + 5'000'000);
    rec.on_request(request("L"), T0);
    rec.on_status(status("L", job_status_t::STATE_DONE, "hg-robot-bridge", "path complete", 1), T0 + 1);
  }  // killed: no stop()
  const json before = read_json(tmp.path / "K" / "job.json");
  EXPECT_EQ(before["state"], "RUNNING");  // what was on disk when it died is whole
  EXPECT_FALSE(before.contains("interrupted"));
  {
    Recorder rec(tmp.path, T0 + 60'000'000);
    const json k = read_json(tmp.path / "K" / "job.json");
    ASSERT_TRUE(k.contains("interrupted"));
    EXPECT_EQ(k["interrupted"]["last_state"], "RUNNING");
    EXPECT_EQ(k["interrupted"]["last_update"], "2025-12-01T10:40:05.000Z");
    EXPECT_EQ(k["interrupted"]["at"], "2025-12-01T10:41:00.000Z");
    EXPECT_EQ(k["final"], false);
    EXPECT_FALSE(read_json(tmp.path / "L" / "job.json").contains("interrupted"));  // L had ended
    // The robot bridge, restarted, reports how the job ended: the record ends there.
    rec.on_status(status("K", job_status_t::STATE_ABORTED, "hg-robot-bridge", "restarted while job K was running"),
                  T0 + 61'000'000);
    const json k2 = read_json(tmp.path / "K" / "job.json");
    EXPECT_EQ(k2["state"], "ABORTED");
    EXPECT_EQ(k2["final"], true);
    EXPECT_FALSE(k2.contains("interrupted"));
    EXPECT_EQ(k2["resumed_after_interruption"]["last_state"], "RUNNING");
    // A clean stop marks what is still open.
    rec.on_request(request("M"), T0 + 62'000'000);
    rec.on_status(status("M", job_status_t::STATE_PLANNING, "hg-path-planner", "waiting"), T0 + 62'000'000);
    rec.stop(T0 + 63'000'000);
    const json m = read_json(tmp.path / "M" / "job.json");
    ASSERT_TRUE(m.contains("interrupted"));
    EXPECT_NE(m["interrupted"]["why"].get<std::string>().find("stopped while the job was PLANNING"), std::string::npos);
  }
  // Garbage where a record should be: counted and skipped, the rest still works.
  fs::create_directories(tmp.path / "junk");
  std::ofstream(tmp.path / "junk" / "job.json") << "{not json";
  Recorder rec(tmp.path, T0 + 70'000'000);
  EXPECT_EQ(rec.stats().bad_records, 1);
  rec.on_request(request("N"), T0 + 70'000'000);
  EXPECT_EQ(read_json(tmp.path / "N" / "job.json")["job_id"], "N");
}

namespace {

hullgrind::edge_stretch_t stretch(int loop, double length, std::int8_t cause) {
  hullgrind::edge_stretch_t e{};
  e.loop_index = std::int16_t(loop);
  e.hole = loop > 0;
  e.length = length;
  e.cause = cause;
  e.reason = "r" + std::to_string(loop);
  return e;
}

void set_unground(job_status_t& s, std::vector<hullgrind::edge_stretch_t> u) {
  s.unground = std::move(u);
  s.num_unground = std::int32_t(s.unground.size());
}

}  // namespace

TEST(JobRecorder, TheRecordKeepsTheApprovalAndTheUngroundStretches) {
  TempDir d("approval");
  Recorder rec(d.path, T0);
  rec.on_request(request("a"), T0);
  rec.on_status(status("a", job_status_t::STATE_PLANNED, "hg-path-planner", "3 loops"), T0 + 1);
  job_status_t awaiting = status("a", job_status_t::STATE_AWAITING_APPROVAL, "hg-robot-bridge", "awaits");
  awaiting.plan_revision = 1;
  set_unground(awaiting, {stretch(2, 0.03, hullgrind::edge_stretch_t::CAUSE_TOO_SMALL)});
  rec.on_status(awaiting, T0 + 2);
  json j = read_json(rec.dir_of("a") / "job.json");
  EXPECT_EQ(j["state"], "AWAITING_APPROVAL");
  EXPECT_EQ(j["final"], false);
  ASSERT_EQ(j["unground"].size(), 1u);
  EXPECT_EQ(j["unground"][0]["cause"], "TOO_SMALL");
  job_request_t approve = request("a", job_request_t::ACTION_APPROVE);
  approve.actor = "operator ann";
  approve.excluded_loops = {2};
  approve.num_excluded = 1;
  rec.on_request(approve, T0 + 3);
  job_status_t approved = status("a", job_status_t::STATE_APPROVED, "hg-robot-bridge", "approved");
  approved.actor = "operator ann";
  approved.plan_revision = 1;
  approved.excluded_loops = {2};
  approved.num_excluded = 1;
  rec.on_status(approved, T0 + 4);
  job_status_t done = status("a", job_status_t::STATE_DONE, "hg-robot-bridge", "path complete; loops 2 excluded", 1);
  done.actor = "operator ann";
  set_unground(done, {stretch(2, 0.03, hullgrind::edge_stretch_t::CAUSE_EXCLUDED)});
  rec.on_status(done, T0 + 5);
  j = read_json(rec.dir_of("a") / "job.json");
  EXPECT_EQ(j["state"], "DONE");
  EXPECT_EQ(j["final"], true);
  EXPECT_EQ(j["request"]["action"], "START");  // the approval is an event, not the job's request
  EXPECT_EQ(j["requests"], 2);
  EXPECT_EQ(j["approval"]["by"], "operator ann");
  EXPECT_EQ(j["approval"]["at_utime"], T0 + 4);
  EXPECT_EQ(j["approval"]["revision"], 1);
  EXPECT_EQ(j["approval"]["excluded_loops"], json::array({2}));
  ASSERT_EQ(j["unground"].size(), 1u);
  EXPECT_EQ(j["unground"][0]["cause"], "EXCLUDED");
  EXPECT_EQ(j["unground"][0]["loop"], 2);
  const std::vector<json> ev = events(rec.dir_of("a"));
  ASSERT_EQ(ev.size(), 6u);
  EXPECT_EQ(ev[3]["request"]["action"], "APPROVE");
  EXPECT_EQ(ev[3]["request"]["excluded_loops"], json::array({2}));
  EXPECT_EQ(ev[4]["actor"], "operator ann");
}

TEST(JobRecorder, IncompleteRejectedAndNeedsRescanEndARecordFromAnySource) {
  TempDir d("terminal");
  Recorder rec(d.path, T0);
  const std::int8_t ends[] = {job_status_t::STATE_INCOMPLETE, job_status_t::STATE_REJECTED,
                              job_status_t::STATE_NEEDS_RESCAN};
  for (std::int8_t state : ends) {
    const std::string id = "t" + std::to_string(int(state));
    rec.on_request(request(id), T0);
    job_status_t s =
        status(id, state, state == job_status_t::STATE_NEEDS_RESCAN ? "hg-path-planner" : "hg-robot-bridge", "why");
    if (state == job_status_t::STATE_INCOMPLETE)
      set_unground(s, {stretch(0, 0.004, hullgrind::edge_stretch_t::CAUSE_UNREACHED),
                       stretch(3, 0.02, hullgrind::edge_stretch_t::CAUSE_CORNER)});
    if (state == job_status_t::STATE_REJECTED) s.actor = "operator bo";
    rec.on_status(s, T0 + 1);
    rec.on_status(status(id, job_status_t::STATE_RUNNING, "hg-robot-bridge", "later"), T0 + 2);  // an event only
    const json j = read_json(rec.dir_of(id) / "job.json");
    EXPECT_EQ(j["final"], true) << id;
    EXPECT_EQ(j["state"], hg::jobs::job_state_name(state)) << id;
    EXPECT_EQ(j["reason"], "why");
    if (state == job_status_t::STATE_INCOMPLETE) {
      ASSERT_EQ(j["unground"].size(), 2u);
      EXPECT_EQ(j["unground"][1]["cause"], "CORNER");
      EXPECT_DOUBLE_EQ(j["unground"][1]["length"].get<double>(), 0.02);
    }
    if (state == job_status_t::STATE_REJECTED) EXPECT_EQ(j["rejection"]["by"], "operator bo");
  }
}

// Answers (answer = true) change nothing, except that a terminal one ends a record not ended (the end was
// published while the recorder was down): over random sequences, the record ends exactly as the first
// non-answer end or, without one, the first terminal answer; answers never move a state.
TEST(JobRecorder, ATerminalAnswerEndsAnOpenRecordOtherAnswersChangeNothing) {
  std::mt19937 rng(7);
  const std::int8_t states[] = {job_status_t::STATE_ACCEPTED,          job_status_t::STATE_RUNNING,
                                job_status_t::STATE_AWAITING_APPROVAL, job_status_t::STATE_DONE,
                                job_status_t::STATE_INCOMPLETE,        job_status_t::STATE_ABORTED};
  for (int seed = 0; seed < 60; ++seed) {
    TempDir d("answers" + std::to_string(seed));
    std::string expect_state = "ACCEPTED";
    bool ended = false;
    {
      Recorder rec(d.path, T0);
      rec.on_request(request("q"), T0);
      rec.on_status(status("q", job_status_t::STATE_ACCEPTED, "hg-robot-bridge", "accepted"), T0);
      for (int i = 0; i < 8; ++i) {
        job_status_t s = status("q", states[rng() % 6], "hg-robot-bridge", "m" + std::to_string(i));
        s.answer = rng() % 2;
        if (i == 3 && rng() % 2) {
          rec.stop(T0 + 10);  // the recorder stops and a new one starts: the record is open, interrupted
        }
        const bool terminal = hg::jobs::job_state_final(s.state);
        if (!ended && (!s.answer || terminal)) expect_state = hg::jobs::job_state_name(s.state);
        if (!ended && terminal) ended = true;
        rec.on_status(s, T0 + 20 + i);
      }
    }
    const json j = read_json(d.path / "q" / "job.json");
    EXPECT_EQ(j["state"], expect_state) << seed;
    EXPECT_EQ(j["final"], ended) << seed;
  }
}

TEST(JobRecorder, ANewRevisionReplacesThePathOfAJobNotEnded) {
  TempDir d("revision");
  Recorder rec(d.path, T0);
  rec.on_outline(outline(4), T0);
  rec.on_request(request("v"), T0);
  hullgrind::grind_path_t p1 = path("v", 4, 3), p2 = path("v", 4, 5);
  p1.revision = 1, p2.revision = 2;
  rec.on_path(p1, T0 + 1);
  rec.on_path(p2, T0 + 2);
  rec.on_path(p1, T0 + 3);  // an older revision: an event
  json j = read_json(rec.dir_of("v") / "job.json");
  EXPECT_EQ(j["path"]["revision"], 2);
  EXPECT_EQ(j["path"]["waypoints"], 5);
  EXPECT_EQ(read_json(rec.dir_of("v") / "path.json")["waypoints"].size(), 5u);
  rec.on_status(status("v", job_status_t::STATE_REJECTED, "hg-robot-bridge", "rejected"), T0 + 4);
  hullgrind::grind_path_t p3 = path("v", 4, 7);
  p3.revision = 3;
  rec.on_path(p3, T0 + 5);  // after the end: kept as an event only
  EXPECT_EQ(read_json(rec.dir_of("v") / "job.json")["path"]["revision"], 2);
}
