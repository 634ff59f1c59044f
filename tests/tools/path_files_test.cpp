// Path files between the tools: every path file a tool writes (hg-plan, hg-overview, the path_file writer)
// is read back by every reader (the path_file reader, the robot bridge's, hg-robot-export), and
// hg-overview draws the path with the calibration the run used. The recorded run is made here: a job's
// cloud, outline, path (planned with a camera pose that overrides the config's) and statuses in an LCM log.
#include <gtest/gtest.h>
#include <sys/resource.h>
#include <sys/wait.h>

#include <cmath>
#include <filesystem>
#include <fstream>
#include <lcm/lcm-cpp.hpp>
#include <sstream>

#include "hullgrind/job_request_t.hpp"
#include "hullgrind/job_status_t.hpp"
#include "path_planner/io.hpp"
#include "robot_bridge/path.hpp"
#include "path_file/path_file.hpp"
#include "tools/overview/overview.hpp"

namespace {

namespace pp = hg::path_planner;

std::string tmp(const std::string& name) {
  return testing::TempDir() + "/pathfiles_" + testing::UnitTest::GetInstance()->current_test_info()->name() + "_" +
         name;
}
std::string slurp(const std::string& path) {
  std::stringstream ss;
  ss << std::ifstream(path).rdbuf();
  return ss.str();
}
int run(const std::string& command, std::string* out) {
  const std::string log = tmp("tool.txt");
  const int rc = std::system((std::string(HG_BIN_DIR) + "/" + command + " >" + log + " 2>&1").c_str());
  *out = slurp(log);
  return WIFEXITED(rc) ? WEXITSTATUS(rc) : -1;
}
const std::string kPlannerConfig = std::string(HG_SOURCE_DIR) + "/config/path_planner.yaml";
const std::string kShippedCell = std::string(HG_SOURCE_DIR) + "/config/cell.yaml";  // camera 1.2 m up
const std::string kRunCell = std::string(HG_SOURCE_DIR) + "/config/cell-sim.yaml";  // pipeline.toml's, 1.5 m

// The cell of config/pipeline.toml: camera 1.5 m above the table, looking down (config/cell.yaml says 1.2).
// (As the cell files hold them, exactly: the in-process plan below and hg-plan's must agree to the bit.)
const Eigen::Isometry3d kRunCamera = hg::cell::read_cell(kRunCell).calibration.camera_to_base;
const Eigen::Isometry3d kConfigCamera = hg::cell::read_cell(kShippedCell).calibration.camera_to_base;

// A 0.3 x 0.2 m plate with a 60 x 40 mm cut-out, 10 mm thick, seen by that camera: plane 1.49 m away.
struct Scene {
  hullgrind::outline_t outline{};
  pp::OutlineInput input;
  std::vector<pp::Ring> rings;  // plate-plane (u, v)
};
Scene scene() {
  Scene s;
  s.rings = {{{-0.15, -0.1}, {0.15, -0.1}, {0.15, 0.1}, {-0.15, 0.1}},
             {{0.02, -0.02}, {0.02, 0.02}, {0.08, 0.02}, {0.08, -0.02}}};
  auto& o = s.outline;
  o.header.seq = 7;
  o.header.frame_id = "camera";
  o.cloud_seq = 3;
  const double origin[3] = {0.02, -0.01, 1.49}, normal[3] = {0, 0, -1}, u[3] = {1, 0, 0}, v[3] = {0, -1, 0};
  for (int k = 0; k < 3; ++k)
    o.plane_origin[k] = origin[k], o.plane_normal[k] = normal[k], o.plane_u_axis[k] = u[k], o.plane_v_axis[k] = v[k];
  o.alpha_radius = 0.0027;
  o.compute_time = 0.25;
  o.mode = "dshi";
  o.order = "brio";
  for (std::size_t k = 0; k < s.rings.size(); ++k) {
    hullgrind::outline_loop_t l{};
    l.hole = k > 0;
    for (const auto& p : s.rings[k]) l.u.push_back(p.x()), l.v.push_back(p.y());
    l.n = std::int32_t(l.u.size());
    o.loops.push_back(l);
  }
  o.num_loops = std::int32_t(o.loops.size());
  s.input = pp::from_lcm(o);
  return s;
}

pp::PlannerConfig planner_config(const Eigen::Isometry3d& camera_to_base) {
  const auto file = hg::runtime::Config::load(kPlannerConfig);
  pp::PlannerConfig cfg = pp::config_from(pp::lookup_from({{"cell", kRunCell}}, file));
  cfg.camera_to_base = camera_to_base;
  // The scene's hole has sharp corners a 10 mm tool cannot reach (the coverage check fails such a job);
  // these tests are about the files, so the path is planned anyway.
  cfg.small_hole = pp::SmallHolePolicy::Skip;
  return cfg;
}

template <class T>
void log_event(lcm::LogFile& log, std::int64_t utime, const std::string& channel, const T& msg) {
  std::vector<std::uint8_t> buf(std::size_t(msg.getEncodedSize()));
  msg.encode(buf.data(), 0, int(buf.size()));
  lcm::LogEvent e{};
  e.timestamp = utime;
  e.channel = channel;
  e.datalen = std::int32_t(buf.size());
  e.data = buf.data();
  log.writeEvent(&e);
}

// A recorded job J1 planned with kRunCamera; returns the path message as it is in the log. `end`: the robot
// bridge's last word on it (DONE; INCOMPLETE with hole 1 unground), followed by a QUERY's DONE answer.
// With `copy_at`: the planner's copy of the path (the same message) logged then as well.
hullgrind::grind_path_t write_job_log(const std::string& file, std::int8_t end = hullgrind::job_status_t::STATE_DONE,
                                      std::int64_t copy_at = 0) {
  const Scene s = scene();
  const pp::PlanResult r = pp::plan(s.input, {}, planner_config(kRunCamera), std::nullopt);
  EXPECT_TRUE(r.ok) << r.reason;
  hullgrind::grind_path_t path = pp::to_lcm(r, "J1", s.outline.header.seq, "robot_base", 4000);
  lcm::LogFile log(file, "w");
  hullgrind::job_request_t req{};
  req.job_id = "J1";
  req.action = hullgrind::job_request_t::ACTION_START;
  log_event(log, 1000, "HG_JOB_REQUEST", req);
  hullgrind::plate_cloud_t cloud{};
  cloud.header.seq = 3;
  for (double u = -0.15; u <= 0.15; u += 0.01)
    for (double v = -0.1; v <= 0.1; v += 0.01)
      cloud.u.push_back(float(u)), cloud.v.push_back(float(v)), cloud.part.push_back(0);
  cloud.n = std::int32_t(cloud.u.size());
  cloud.num_parts = 1;
  log_event(log, 2000, "HG_PLATE_CLOUD", cloud);
  log_event(log, 3000, "HG_OUTLINE", s.outline);
  log_event(log, 4000, "HG_GRIND_PATH", path);
  if (copy_at) log_event(log, copy_at, "HG_GRIND_PATH", path);
  hullgrind::job_status_t done{};
  done.job_id = "J1";
  done.source = "hg-robot-bridge";
  done.state = end;
  done.progress = 1;
  done.message = end == hullgrind::job_status_t::STATE_DONE ? "path complete" : "path complete; edge not ground";
  if (end == hullgrind::job_status_t::STATE_INCOMPLETE) {
    hullgrind::edge_stretch_t u{};
    u.loop_index = 1;
    u.hole = true;
    u.length = 0.0314;
    u.cause = hullgrind::edge_stretch_t::CAUSE_TOO_SMALL;
    done.unground = {u};
    done.num_unground = 1;
  }
  log_event(log, 5000, "HG_JOB_STATUS", done);
  hullgrind::job_status_t answer = done;  // an answer never overrides how the job ended
  answer.state = hullgrind::job_status_t::STATE_DONE;
  answer.answer = true;
  answer.unground.clear();
  answer.num_unground = 0;
  log_event(log, 6000, "HG_JOB_STATUS", answer);
  return path;
}

void expect_same_path(const hullgrind::grind_path_t& a, const hullgrind::grind_path_t& b) {
  EXPECT_EQ(a.job_id, b.job_id);
  EXPECT_EQ(a.frame, b.frame);
  EXPECT_EQ(a.outline_seq, b.outline_seq);
  EXPECT_EQ(a.tool_radius, b.tool_radius);
  EXPECT_EQ(a.tilt, b.tilt);
  EXPECT_EQ(a.flipped, b.flipped);
  ASSERT_EQ(a.n, b.n);
  for (std::size_t i = 0; i < std::size_t(a.n); ++i) {
    for (int k = 0; k < 3; ++k) ASSERT_EQ(a.position[i][k], b.position[i][k]) << "waypoint " << i;
    for (int k = 0; k < 4; ++k) ASSERT_EQ(a.orientation[i][k], b.orientation[i][k]) << "waypoint " << i;
    ASSERT_EQ(a.speed[i], b.speed[i]) << "waypoint " << i;
    ASSERT_EQ(a.kind[i], b.kind[i]) << "waypoint " << i;
    ASSERT_EQ(a.loop_index[i], b.loop_index[i]) << "waypoint " << i;
  }
}

// Every reader takes the file and gets `expected` back (the export: one move per waypoint).
void every_reader_reads(const std::string& file, const hullgrind::grind_path_t& expected) {
  SCOPED_TRACE(file);
  expect_same_path(hg::path_file::read_file(file), expected);
  const hg::robot_bridge::Path p = hg::robot_bridge::read_path_json(file);
  ASSERT_EQ(p.size(), std::size_t(expected.n));
  for (std::size_t i = 0; i < p.size(); ++i) {
    EXPECT_EQ(p.position[i], Eigen::Vector3d(expected.position[i].data()));
    EXPECT_EQ(p.kind[i], expected.kind[i]);
  }
  std::string out;
  const std::string script = tmp("job.script");
  ASSERT_EQ(run("hg-robot-export --config " + std::string(HG_SOURCE_DIR) + "/config/robot_bridge.yaml --cell " +
                    kRunCell + " -o " + script + " " + file,
                &out),
            0)
      << out;
  const std::string s = slurp(script);
  int moves = 0;
  for (std::size_t at = s.find("  move"); at != std::string::npos; at = s.find("  move", at + 1)) ++moves;
  EXPECT_EQ(moves, expected.n);
}

double distance_to_rings(const Eigen::Vector2d& p, const std::vector<pp::Ring>& rings) {
  double best = INFINITY;
  for (const auto& r : rings)
    for (std::size_t i = 0; i < r.size(); ++i) {
      const Eigen::Vector2d a = r[i], d = r[(i + 1) % r.size()] - a;
      const double t = std::clamp((p - a).dot(d) / d.squaredNorm(), 0.0, 1.0);
      best = std::min(best, (a + t * d - p).norm());
    }
  return best;
}

}  // namespace

TEST(PathFiles, EveryWriterIsReadByEveryReader) {
  const hullgrind::grind_path_t logged = write_job_log(tmp("run.lcmlog"));
  ASSERT_GT(logged.n, 0);

  // 1. the path_file writer itself
  std::ofstream(tmp("lib.json")) << hg::path_file::to_text(logged);
  every_reader_reads(tmp("lib.json"), logged);

  // 2. hg-overview (make run's out/path.json)
  std::string out;
  ASSERT_EQ(run("hg-overview " + tmp("run.lcmlog") + " --out " + tmp("ov") + " --planner-config " + kPlannerConfig +
                    " --cell " + kRunCell,
                &out),
            0)
      << out;
  every_reader_reads(tmp("ov") + "/path.json", logged);

  // 3. hg-plan, on the outline hg-overview wrote ("frame": "camera"), with the run's camera pose
  EXPECT_EQ(nlohmann::json::parse(slurp(tmp("ov") + "/outline.json"))["frame"], "camera");
  ASSERT_EQ(run("hg-plan " + tmp("ov") + "/outline.json --config " + kPlannerConfig + " --cell " + kRunCell +
                    " --small-hole skip --job-id J1 -o " + tmp("plan.json"),
                &out),
            0)
      << out;
  hullgrind::grind_path_t planned = logged;
  planned.outline_seq = -1;  // an outline file has no bus sequence number
  // The outline file carries the loops and plane through JSON: the same doubles, so the same plan.
  every_reader_reads(tmp("plan.json"), planned);
}

TEST(PathFiles, OneSpellingOfTheKinds) {
  const hullgrind::grind_path_t logged = write_job_log(tmp("run.lcmlog"));
  nlohmann::json j = hg::path_file::to_json(logged);
  std::string kinds;
  for (const auto& w : j["waypoints"]) kinds += w["kind"].get<std::string>() + " ";
  EXPECT_NE(kinds.find("lead_in "), std::string::npos);
  EXPECT_NE(kinds.find("lead_out "), std::string::npos);
  EXPECT_EQ(kinds.find('-'), std::string::npos) << "kebab-case kind in a path file: " << kinds;
  j["waypoints"][1]["kind"] = "lead-in";
  try {
    hg::path_file::from_json_text(j.dump(), "bad.json");
    FAIL() << "a kind spelt lead-in must be refused";
  } catch (const std::runtime_error& e) {
    const std::string what = e.what();
    EXPECT_NE(what.find("bad.json: waypoint 1: kind: unknown kind \"lead-in\""), std::string::npos) << what;
    EXPECT_NE(what.find("lead_in"), std::string::npos) << "names the spelling it takes: " << what;
  }
  j["waypoints"][1]["kind"] = "lead_in";
  j["waypoints"][2].erase("speed");
  EXPECT_THROW(hg::path_file::from_json_text(j.dump(), "bad.json"), std::runtime_error);
}

// The run planned with the camera 1.5 m up (pipeline.toml's cell, config/cell-sim.yaml) while config/cell.yaml
// says 1.2 m: with the run's calibration the path lies on the plate, a tool radius from the outline's edges.
// hg-overview takes camera-to-base from the cell file it is given (--cell, or the planner's own --cell).
TEST(Overview, DrawsThePathOnThePlateWithTheRunsCalibration) {
  write_job_log(tmp("run.lcmlog"));
  const auto job = hg::overview::trace_job(hg::overview::read_run_log(tmp("run.lcmlog")));
  ASSERT_TRUE(job.path && job.outline);
  const double radius = job.path->msg.tool_radius;
  const auto on_plate = hg::overview::path_on_plate(job, kRunCamera);
  int grind = 0;
  for (std::size_t i = 0; i < on_plate.uv.size(); ++i) {
    if (on_plate.kind[i] != hullgrind::grind_path_t::KIND_GRIND) continue;
    ++grind;
    EXPECT_NEAR(distance_to_rings(on_plate.uv[i], scene().rings), radius, 1e-4) << "waypoint " << i;
    EXPECT_NEAR(on_plate.height[i], 0, 1e-9) << "waypoint " << i;
  }
  EXPECT_GT(grind, 100);
  EXPECT_LT(on_plate.grind_height_median(), hg::overview::kOffPlaneWarning);
  // config/cell.yaml's calibration puts it 300 mm off the plate.
  EXPECT_NEAR(hg::overview::path_on_plate(job, kConfigCamera).grind_height_median(), 0.3, 1e-9);

  // hg-overview with the planner's command line from the pipeline file (its --cell): that calibration, no
  // warning.
  std::string out;
  ASSERT_EQ(
      run("hg-overview " + tmp("run.lcmlog") + " --out " + tmp("ov") + " --planner-args --config " + kPlannerConfig +
              " --cell " + kRunCell + " --pixel-pitch 0.001342 --small-hole skip --lcm-url memq://",
          &out),
      0)
      << out;
  EXPECT_NE(out.find("(from the cell file " + kRunCell + "): [1 0 0 0.5; 0 -1 0 0; 0 0 -1 1.5; 0 0 0 1]"),
            std::string::npos)
      << out;
  EXPECT_EQ(out.find("warning"), std::string::npos) << out;
  // With config/cell.yaml instead: its 1.2 m, and a warning that the path is off the plate.
  ASSERT_EQ(run("hg-overview " + tmp("run.lcmlog") + " --out " + tmp("ov2") + " --planner-config " + kPlannerConfig +
                    " --cell " + kShippedCell,
                &out),
            0)
      << out;
  EXPECT_NE(out.find("(from the cell file " + kShippedCell + "): [1 0 0 0.5; 0 -1 0 0; 0 0 -1 1.2; 0 0 0 1]"),
            std::string::npos)
      << out;
  EXPECT_NE(out.find("warning: the grind path lies 300.0 mm off the outline's plane"), std::string::npos) << out;
  // An old key on its command line names the cell key; a broken cell file names the file and the key.
  EXPECT_EQ(run("hg-overview " + tmp("run.lcmlog") + " --out " + tmp("ov3") + " --cell " + kRunCell +
                    " --planner-config " + kPlannerConfig + " --camera-xyz 0.5,0,1.5",
                &out),
            2);
  EXPECT_NE(out.find("--camera-xyz moved: it lives in the cell file (--cell, default config/cell.yaml), key "
                     "calibration.camera-to-base"),
            std::string::npos)
      << out;
  std::ofstream(tmp("broken_cell.yaml")) << slurp(kRunCell).replace(slurp(kRunCell).find("home:"), 5, "hom:");
  EXPECT_EQ(run("hg-overview " + tmp("run.lcmlog") + " --out " + tmp("ov4") + " --cell " + tmp("broken_cell.yaml") +
                    " --planner-config " + kPlannerConfig,
                &out),
            2);
  EXPECT_NE(out.find(tmp("broken_cell.yaml") + ": hom: unknown key"), std::string::npos) << out;
}

// The end state as the bus said it: INCOMPLETE stays INCOMPLETE in the summary (exit 1), its unground stretch
// listed; DONE is DONE (exit 0).
TEST(Overview, TellsTheEndStateTruthfully) {
  for (std::int8_t end : {hullgrind::job_status_t::STATE_DONE, hullgrind::job_status_t::STATE_INCOMPLETE}) {
    write_job_log(tmp("end.lcmlog"), end);
    const auto job = hg::overview::trace_job(hg::overview::read_run_log(tmp("end.lcmlog")));
    ASSERT_TRUE(job.final_status);
    EXPECT_EQ(job.final_status->msg.state, end);
    EXPECT_FALSE(job.final_status->msg.answer);
    std::string out;
    const int rc = run("hg-overview " + tmp("end.lcmlog") + " --out " + tmp("end") + " --planner-config " +
                           kPlannerConfig + " --cell " + kRunCell,
                       &out);
    EXPECT_EQ(rc, end == hullgrind::job_status_t::STATE_DONE ? 0 : 1) << out;
    const std::string summary = slurp(tmp("end") + "/summary.json");
    if (end == hullgrind::job_status_t::STATE_INCOMPLETE) {
      EXPECT_NE(out.find("job J1: INCOMPLETE - path complete; edge not ground"), std::string::npos) << out;
      EXPECT_NE(summary.find("\"final_state\": \"INCOMPLETE\""), std::string::npos) << summary;
      EXPECT_NE(summary.find("\"length\": 0.0314"), std::string::npos) << summary;
    } else {
      EXPECT_NE(out.find("job J1: DONE - path complete"), std::string::npos) << out;
    }
  }
}

// The stages of summary.json from the log's receive times (write_job_log: request 1 ms, cloud 2 ms, outline 3 ms,
// path 4 ms, end 5 ms) and the two compute times the messages carry: the outline service's and the planner's.
TEST(Overview, StagesAreTheLogsTimesAndTheComputeTimesTheMessagesCarry) {
  hullgrind::grind_path_t path = write_job_log(tmp("stages.lcmlog"));
  const auto job = hg::overview::trace_job(hg::overview::read_run_log(tmp("stages.lcmlog")));
  ASSERT_TRUE(job.path && job.outline && job.request && job.final_status);
  const auto stages = hg::overview::summary_json(job)["stages"];
  EXPECT_DOUBLE_EQ(stages["cloud_to_outline_ms"].get<double>(), 1.0);
  EXPECT_DOUBLE_EQ(stages["plan_ms"].get<double>(), 1.0);  // from the outline (after the request) to the path
  EXPECT_DOUBLE_EQ(stages["robot_run_ms"].get<double>(), 1.0);
  EXPECT_DOUBLE_EQ(stages["request_to_end_ms"].get<double>(), 4.0);
  EXPECT_DOUBLE_EQ(stages["outline_compute_ms"].get<double>(), 250.0);  // scene(): 0.25 s
  // pp::plan timed itself.
  ASSERT_GT(path.compute_time, 0);
  EXPECT_DOUBLE_EQ(stages["plan_compute_ms"].get<double>(), path.compute_time * 1e3);
}

// A run whose camera sent `count` clouds of `points` points (seq 0, 1, ...; cloud k's u from k), the job's
// outline on cloud 17 logged after the last of them, then one more cloud with seq 17 (a restarted camera reuses
// seqs): not the outline's, which was logged before it.
void write_clouds_log(const std::string& file, int count, int points) {
  const Scene s = scene();
  const pp::PlanResult r = pp::plan(s.input, {}, planner_config(kRunCamera), std::nullopt);
  ASSERT_TRUE(r.ok) << r.reason;
  auto cloud = [points](std::int64_t seq, float shift) {
    hullgrind::plate_cloud_t c{};
    c.header.seq = seq;
    c.header.utime = 100 + seq;
    for (int i = 0; i < points; ++i) c.u.push_back(shift + float(i)), c.v.push_back(-float(i)), c.part.push_back(0);
    c.n = points;
    c.num_parts = 1;
    return c;
  };
  lcm::LogFile log(file, "w");
  hullgrind::job_request_t req{};
  req.job_id = "J1";
  req.action = hullgrind::job_request_t::ACTION_START;
  log_event(log, 1000, "HG_JOB_REQUEST", req);
  for (int seq = 0; seq < count; ++seq) log_event(log, 2000 + seq, "HG_PLATE_CLOUD", cloud(seq, float(seq)));
  hullgrind::outline_t outline = s.outline;
  outline.cloud_seq = 17;
  log_event(log, 2000 + count, "HG_OUTLINE", outline);
  log_event(log, 3000 + count, "HG_PLATE_CLOUD", cloud(17, 1e6f));
  log_event(log, 4000 + count, "HG_GRIND_PATH", pp::to_lcm(r, "J1", outline.header.seq, "robot_base", 4000));
}

// The job's cloud is read again from where the log holds it: the right one, its points as written.
TEST(Overview, ReadsTheJobsCloudAgainFromTheLog) {
  write_clouds_log(tmp("clouds.lcmlog"), 30, 50);
  const auto run = hg::overview::read_run_log(tmp("clouds.lcmlog"));
  EXPECT_EQ(run.clouds.size(), 31u);
  const auto job = hg::overview::trace_job(run);
  ASSERT_TRUE(job.cloud && job.outline && job.path);
  EXPECT_EQ(job.cloud->log_utime, 2017);
  EXPECT_EQ(job.cloud->msg.header.seq, 17);
  EXPECT_EQ(job.cloud->msg.header.utime, 117);
  ASSERT_EQ(job.cloud->msg.n, 50);
  EXPECT_EQ(job.cloud->msg.u[0], 17.0f);
  EXPECT_EQ(job.cloud->msg.u[49], 66.0f);
  EXPECT_EQ(job.cloud->msg.v[49], -49.0f);
}

// A long run's log holds more clouds than memory (5 Hz of 19 MB clouds is 95 MB a second): hg-overview keeps
// one cloud, not the log's. Here 300 MB of clouds, and the tool's peak RSS below a third of that.
TEST(Overview, KeepsOneCloudOfALongRun) {
  write_clouds_log(tmp("long.lcmlog"), 100, 300000);
  const auto bytes = std::filesystem::file_size(tmp("long.lcmlog"));
  ASSERT_GT(bytes, 300e6);
  std::string out;
  ASSERT_EQ(run("hg-overview " + tmp("long.lcmlog") + " --out " + tmp("long") + " --planner-config " + kPlannerConfig +
                    " --cell " + kRunCell,
                &out),
            1)  // no end state in this log
      << out;
  rusage use{};
  ASSERT_EQ(getrusage(RUSAGE_CHILDREN, &use), 0);
  EXPECT_LT(double(use.ru_maxrss) * 1024, double(bytes) / 3) << "peak RSS " << use.ru_maxrss << " KB";
  EXPECT_EQ(nlohmann::json::parse(slurp(tmp("long") + "/summary.json"))["cloud_points"], 300000);
}

// A copy of the path (the planner publishes one again until the robot bridge acknowledges it) is the same path:
// the plan still took 1 ms to the path's first arrival, and the run 1 ms from there.
TEST(Overview, ACopyOfThePathKeepsTheTimeItFirstCame) {
  write_job_log(tmp("copy.lcmlog"), hullgrind::job_status_t::STATE_DONE, 4500);
  const auto job = hg::overview::trace_job(hg::overview::read_run_log(tmp("copy.lcmlog")));
  ASSERT_TRUE(job.path && job.outline && job.request && job.final_status);
  EXPECT_EQ(job.path->log_utime, 4000);
  const auto stages = hg::overview::summary_json(job)["stages"];
  EXPECT_DOUBLE_EQ(stages["plan_ms"].get<double>(), 1.0);
  EXPECT_DOUBLE_EQ(stages["robot_run_ms"].get<double>(), 1.0);
}

// A path recorded with another version of grind_path_t (another fingerprint) is not read as a path, and
// hg-overview says so instead of reporting a job without one in silence.
TEST(Overview, SaysWhenAMessageDoesNotDecode) {
  const hullgrind::grind_path_t path = write_job_log(tmp("ok.lcmlog"));
  {
    lcm::LogFile log(tmp("other.lcmlog"), "w");
    hullgrind::job_request_t req{};
    req.job_id = "J1";
    log_event(log, 1000, "HG_JOB_REQUEST", req);
    std::vector<std::uint8_t> buf(std::size_t(path.getEncodedSize()));
    path.encode(buf.data(), 0, int(buf.size()));
    buf[0] ^= 0x5a;  // another type's fingerprint
    lcm::LogEvent e{};
    e.timestamp = 4000;
    e.channel = "HG_GRIND_PATH";
    e.datalen = std::int32_t(buf.size());
    e.data = buf.data();
    log.writeEvent(&e);
  }
  std::string out;
  run("hg-overview " + tmp("other.lcmlog") + " --out " + tmp("other") + " --planner-config " + kPlannerConfig +
          " --cell " + kRunCell,
      &out);
  EXPECT_NE(out.find("1 messages on the cloud, outline, path, request or status channel do not decode"),
            std::string::npos)
      << out;
  EXPECT_FALSE(std::filesystem::exists(tmp("other") + "/path.json"));
  ASSERT_EQ(run("hg-overview " + tmp("ok.lcmlog") + " --out " + tmp("ok") + " --planner-config " + kPlannerConfig +
                    " --cell " + kRunCell,
                &out),
            0);
  EXPECT_EQ(out.find("do not decode"), std::string::npos) << out;
}

TEST(Overview, ScaleBarIsARoundLengthOfAtMostAQuarterOfThePicture) {
  EXPECT_EQ(hg::overview::scale_bar_mm(0.5), 100);   // 125 mm allowed
  EXPECT_EQ(hg::overview::scale_bar_mm(0.3), 50);    // 75 mm allowed
  EXPECT_EQ(hg::overview::scale_bar_mm(0.79), 100);  // 197.5 mm allowed
  EXPECT_EQ(hg::overview::scale_bar_mm(0.8), 200);
  EXPECT_EQ(hg::overview::scale_bar_mm(3.0), 500);
  EXPECT_EQ(hg::overview::scale_bar_mm(0.01), 2);
}
