// hg-calibrate: camera-to-robot calibration from the drilled calibration plate (docs/calibration.md).
#include <cmath>
#include <cstdio>
#include <fstream>
#include <limits>
#include <random>
#include <memory>
#include <string>

#include <nlohmann/json.hpp>

#include "calibration/sim.hpp"
#include "calibration/target.hpp"
#include "cell/cell.hpp"
#include "runtime/config.hpp"
#include "runtime/lcm_url.hpp"
#include "runtime/params.hpp"
#include "tools/calibrate/bus_capture.hpp"
#include "camera_bridge/sources.hpp"
#include "tools/calibrate/robot_moves.hpp"
#include "tools/calibrate/session.hpp"

using namespace hg;
using nlohmann::json;

namespace {

const char* kUsage = R"(usage: hg-calibrate MODE --session DIR [options]
Camera-to-robot calibration from the drilled calibration plate (docs/calibration.md).
modes:
  eye-to-hand   camera fixed over the table: hole centres seen in each view are fitted to the TCP positions
                touched at them (session views carry tcp_at_hole); writes calibration.camera-to-base
  eye-in-hand   camera on the flange: plate pose per view + robot pose per view, OpenCV calibrateHandEye
                (Tsai and Park, their disagreement); writes calibration.camera-to-flange
  verify        the TCP targets above each predicted hole centre from the cell's calibration; with a
                simulated session (DIR/truth.json) the distance of each prediction from the true centre
  capture       --from-bus: one view from the product's pipeline on the bus: the camera bridge's next plate
                cloud (HG_PLATE_CLOUD) and the outline service's outline of it (HG_OUTLINE; --local-outline:
                the outline core run here on the cloud); circle fit on the hole loops at fit time. With
                --trigger a job_request_t START asks the bridge for the frame (--trigger job bridges). The
                view replaces view --view (keeping its TCP readings) or is appended; eye-in-hand sessions take
                the robot pose of the next HG_ROBOT_STATUS as the view's flange pose
  touch         records the robot's TCP (next HG_ROBOT_STATUS) as the position of hole --hole in view --view
                of the session (eye-to-hand: bring the pointer to the hole centre, then run this)
  simulate      writes a simulated session (virtual camera, renderer's truth in DIR/truth.json); eye-in-hand
                with --move: the simulated robot is moved to each view pose over HG_ROBOT_MOVE and the view is
                rendered from the flange pose HG_ROBOT_STATUS reports
A view is a 16-bit depth PNG ("depth"), a .pcd/.ply cloud in the camera frame ("cloud", rendered into a depth
image through the view's intrinsics as the camera bridge's files source does) or a captured outline
("outline"); see docs/calibration.md. Exit status: 0 done, 1 refused (the reason on stderr), 2 usage.
)";

// The options, declared once (runtime::Params: types, ranges, --help, --help-markdown, nearest key).
std::vector<runtime::Param> calibrate_params() {
  using namespace runtime;
  const double inf = std::numeric_limits<double>::infinity();
  return {
      text_param("session", "", "session folder: DIR/session.json (+ the views' files)"),
      text_param("cell", "config/cell.yaml", "cell file to update / read; a dated backup is kept"),
      text_param("report", "", "JSON report of the fit (transform, residuals per feature and per view)"),
      flag_param("dry-run", "do not write the cell file"),
      number_param("above", "0.01", "verify: height of the TCP target above the hole centre, m", 0, inf),
      flag_param("move",
                 "verify: move the TCP to each target over HG_ROBOT_MOVE and report where HG_ROBOT_STATUS says it "
                 "got; simulate eye-in-hand: move the sim robot to each view pose and render from its reported pose"),
      text_param(
          "lcm-url", runtime::default_lcm_url(),
          "LCM provider for --move, touch, capture [$LCM_DEFAULT_URL, else " + std::string(kDefaultLcmUrl) + "]"),
      number_param("speed", "0.1", "with --move: TCP speed, m/s", 0, inf, true),
      integer_param("view", "", "touch: view index (default 0); capture: view to replace (default: append)", 0),
      text_param("hole", "", "touch: drawing hole id H1..H6"),
      flag_param("from-bus", "capture: take the view from HG_PLATE_CLOUD / HG_OUTLINE (the only capture source)"),
      flag_param("trigger", "capture: send a job_request_t START to make a --trigger job camera bridge capture"),
      flag_param("local-outline", "capture: run the outline core here on the plate cloud instead of HG_OUTLINE"),
      number_param("timeout", "10", "capture, touch: seconds to wait for the bus", 0, inf, true),
      text_param("mode", "eye-to-hand", "simulate, capture of a new session: the mount",
                 {"eye-to-hand", "eye-in-hand"}),
      text_param("profile", "pm806", "simulate: camera profile", {"pm806", "lsr-l"}),
      integer_param("views", "", "simulate: views (default 3 eye-to-hand, 8 eye-in-hand)", 1, 64),
      integer_param("seed", "1", "simulate: seed of the scene noise and the view poses", 0),
      number_param("tcp-noise", "0.00005",
                   "simulate: robot reading error per axis, m (eye-in-hand: a tenth of it in rad)", 0, inf)};
}

struct Args {
  std::string mode, session, cell, report, sim_mode, profile, lcm_url, hole;
  bool dry_run = false, move = false, from_bus = false, trigger = false, local_outline = false;
  double speed = 0.1, above = 0.01, tcp_noise = 0.00005, timeout = 10;
  int views = 0, view = -1;
  std::uint64_t seed = 1;
};

Args args_from(const runtime::Params& p) {
  if (p.positional().size() != 1)
    throw runtime::ConfigError(p.positional().empty() ? "command line: no MODE given"
                                                      : "command line: one MODE, not '" + p.positional()[1] + "' too");
  Args a;
  a.mode = p.positional()[0];
  a.session = p.text("session"), a.cell = p.given("cell") ? p.text("cell") : hg::runtime::default_file(p.text("cell")),
  a.report = p.text("report");
  a.sim_mode = p.text("mode"), a.profile = p.text("profile"), a.lcm_url = p.text("lcm-url"), a.hole = p.text("hole");
  a.dry_run = p.flag("dry-run"), a.move = p.flag("move"), a.from_bus = p.flag("from-bus");
  a.trigger = p.flag("trigger"), a.local_outline = p.flag("local-outline");
  a.speed = p.number("speed"), a.above = p.number("above"), a.tcp_noise = p.number("tcp-noise");
  a.timeout = p.number("timeout");
  if (p.given("views")) a.views = static_cast<int>(p.integer("views"));
  if (p.given("view")) a.view = static_cast<int>(p.integer("view"));
  a.seed = static_cast<std::uint64_t>(p.integer("seed"));
  if (a.session.empty()) throw runtime::ConfigError("command line: --session DIR is required");
  return a;
}

json transform_json(const Eigen::Isometry3d& t) { return calibrate::to_row_major(t); }

void write_json(const std::string& path, const json& j) {
  if (path.empty()) return;
  std::ofstream f(path);
  f << j.dump(1) << "\n";
  if (!f) throw std::runtime_error(path + ": cannot write");
}

std::vector<calibration::PlateView> detect_all(const calibrate::Session& s, const calibration::Drawing& d) {
  std::vector<calibration::PlateView> out;
  for (std::size_t i = 0; i < s.views.size(); ++i) {
    try {
      out.push_back(calibrate::detect_view(s.views[i], d));
    } catch (const calibration::CalibrationError& e) {
      throw calibration::CalibrationError("view " + std::to_string(i) + " (" + s.views[i].file + "): " + e.what());
    }
    std::fprintf(stderr, "hg-calibrate: view %zu: %s\n", i, out.back().text.c_str());
  }
  return out;
}

void store(const Args& a, const std::string& method, const Eigen::Isometry3d* to_base,
           const Eigen::Isometry3d* to_flange, double rms, double worst, int features) {
  if (a.dry_run) return;
  cell::Cell c = cell::read_cell(a.cell);
  if (to_base) c.calibration.camera_to_base = *to_base;
  c.calibration.camera_to_flange.reset();
  if (to_flange) c.calibration.camera_to_flange = *to_flange;
  c.calibration.mounting = to_flange ? cell::Mounting::EyeInHand : cell::Mounting::EyeToHand;  // what was measured
  c.calibration.date = cell::utc_now_iso();
  c.calibration.method = method;
  c.calibration.rms_mm = rms * 1e3;
  c.calibration.worst_mm = worst * 1e3;
  c.calibration.features = features;
  const std::string backup = cell::write_cell(a.cell, c);
  std::fprintf(stderr, "hg-calibrate: wrote %s%s%s\n", a.cell.c_str(), backup.empty() ? "" : ", previous kept as ",
               backup.c_str());
}

int eye_to_hand(const Args& a) {
  const calibrate::Session s = calibrate::read_session(a.session);
  const calibration::Drawing d = calibration::calibration_plate_drawing();
  const auto seen = detect_all(s, d);
  std::vector<Eigen::Vector3d> cam, base;
  json features = json::array();
  for (std::size_t v = 0; v < seen.size(); ++v)
    for (const auto& h : seen[v].holes) {
      const std::string& id = d.holes[h.drawing_index].id;
      const auto tcp = s.views[v].tcp_at_hole.find(id);
      if (tcp == s.views[v].tcp_at_hole.end()) continue;  // seen but not touched
      cam.push_back(h.centre_camera);
      base.push_back(tcp->second);
      features.push_back({{"view", v}, {"hole", id}});
    }
  const calibration::RigidFit fit = calibration::fit_rigid(cam, base);
  for (std::size_t i = 0; i < features.size(); ++i) features[i]["residual_mm"] = fit.residuals[i] * 1e3;
  json per_view = json::array();
  for (std::size_t v = 0; v < seen.size(); ++v) {
    double ss = 0, worst = 0;
    int n = 0;
    for (std::size_t i = 0; i < features.size(); ++i)
      if (features[i]["view"] == v)
        ss += fit.residuals[i] * fit.residuals[i], worst = std::max(worst, fit.residuals[i]), ++n;
    per_view.push_back(
        {{"view", v}, {"features", n}, {"rms_mm", n ? std::sqrt(ss / n) * 1e3 : 0}, {"worst_mm", worst * 1e3}});
  }
  std::printf("eye-to-hand: %zu features, rms %.3f mm, worst %.3f mm (%s)\n", cam.size(), fit.rms * 1e3,
              fit.worst * 1e3, features[fit.worst_index]["hole"].get<std::string>().c_str());
  write_json(a.report, {{"mode", "eye-to-hand"},
                        {"method", "umeyama"},
                        {"camera_to_base", transform_json(fit.transform)},
                        {"rms_mm", fit.rms * 1e3},
                        {"worst_mm", fit.worst * 1e3},
                        {"per_feature", features},
                        {"per_view", per_view}});
  store(a, "eye-to-hand umeyama", &fit.transform, nullptr, fit.rms, fit.worst, static_cast<int>(cam.size()));
  return 0;
}

int eye_in_hand(const Args& a) {
  const calibrate::Session s = calibrate::read_session(a.session);
  const calibration::Drawing d = calibration::calibration_plate_drawing();
  const auto seen = detect_all(s, d);
  std::vector<Eigen::Isometry3d> flange, plate;
  std::vector<std::vector<Eigen::Vector3d>> centres;
  for (std::size_t v = 0; v < seen.size(); ++v) {
    flange.push_back(*s.views[v].flange_to_base);
    plate.push_back(seen[v].plate_to_camera);
    centres.emplace_back();
    for (const auto& h : seen[v].holes) centres.back().push_back(h.centre_camera);
  }
  calibration::HandEyeResult r = calibration::solve_eye_in_hand(flange, plate);
  // The plate lies on the cell's table: its hole centres are at table-z + thickness in the base frame, which
  // fixes the camera's distance along its optical axis that the views leave weakly determined.
  const double centre_height = cell::read_cell(a.cell).table_z + d.thickness;
  for (auto& m : r.methods)
    std::printf("eye-in-hand %s: moved %.3f mm along the optical axis to put the holes at the table's height\n",
                m.name.c_str(),
                calibration::fit_camera_height(m.camera_to_flange, flange, centres, centre_height) * 1e3);
  r.disagreement_translation =
      (r.methods[0].camera_to_flange.translation() - r.methods[1].camera_to_flange.translation()).norm();
  json methods = json::array();
  for (const auto& m : r.methods) {
    json views = json::array();
    for (std::size_t v = 0; v < m.view_translation.size(); ++v)
      views.push_back({{"view", v},
                       {"translation_mm", m.view_translation[v] * 1e3},
                       {"rotation_deg", m.view_rotation[v] * 180 / M_PI},
                       {"pattern_rms_mm", seen[v].pattern_fit.rms * 1e3},
                       {"pattern_worst_mm", seen[v].pattern_fit.worst * 1e3}});
    methods.push_back({{"name", m.name},
                       {"camera_to_flange", transform_json(m.camera_to_flange)},
                       {"rms_mm", m.rms_translation * 1e3},
                       {"worst_mm", m.worst_translation * 1e3},
                       {"worst_deg", m.worst_rotation * 180 / M_PI},
                       {"per_view", views}});
    std::printf("eye-in-hand %s: %zu views, rms %.3f mm, worst %.3f mm / %.4f deg\n", m.name.c_str(), flange.size(),
                m.rms_translation * 1e3, m.worst_translation * 1e3, m.worst_rotation * 180 / M_PI);
  }
  std::printf("tsai vs park: %.3f mm, %.4f deg\n", r.disagreement_translation * 1e3,
              r.disagreement_rotation * 180 / M_PI);
  const auto& best = r.methods[1];  // Park: the cell file takes one; the report keeps both
  write_json(a.report, {{"mode", "eye-in-hand"},
                        {"methods", methods},
                        {"camera_to_flange", transform_json(best.camera_to_flange)},
                        {"disagreement_mm", r.disagreement_translation * 1e3},
                        {"disagreement_deg", r.disagreement_rotation * 180 / M_PI}});
  store(a, "eye-in-hand park (tsai within " + std::to_string(r.disagreement_translation * 1e3) + " mm)", nullptr,
        &best.camera_to_flange, best.rms_translation, best.worst_translation, static_cast<int>(flange.size()));
  return 0;
}

// Predicted hole centres in the base frame from the cell's calibration; against the truth when simulated.
int verify(const Args& a) {
  const cell::Cell c = cell::read_cell(a.cell);  // the configuration first, then the input
  const calibrate::Session s = calibrate::read_session(a.session);
  const calibration::Drawing d = calibration::calibration_plate_drawing();
  json truth;
  if (std::ifstream t(a.session + "/truth.json"); t) truth = json::parse(t);
  if (s.mode == "eye-in-hand" && !c.calibration.camera_to_flange)
    throw std::runtime_error(a.cell + ": calibration.camera-to-flange: missing (run eye-in-hand first)");
  const auto seen = detect_all(s, d);
  std::unique_ptr<calibrate::RobotMoves> robot;
  if (a.move) robot = std::make_unique<calibrate::RobotMoves>(a.lcm_url);
  json holes = json::array();
  double worst = 0, ss = 0;
  for (std::size_t v = 0; v < seen.size(); ++v) {
    const Eigen::Isometry3d cam_to_base =
        s.mode == "eye-in-hand" ? Eigen::Isometry3d(*s.views[v].flange_to_base * *c.calibration.camera_to_flange)
                                : c.calibration.camera_to_base;
    for (const auto& h : seen[v].holes) {
      const Eigen::Vector3d predicted = cam_to_base * h.centre_camera;
      const Eigen::Vector3d target = predicted + a.above * Eigen::Vector3d::UnitZ();
      const std::string& id = d.holes[h.drawing_index].id;
      json row{{"view", v}, {"hole", id}, {"tcp_target", {target.x(), target.y(), target.z()}}};
      Eigen::Vector3d pointed = predicted;  // where the TCP points at the plate: the reached pose, down by `above`
      if (robot) {
        const calibrate::MoveResult r =
            robot->move_to("verify-" + cell::utc_now_iso() + "-" + std::to_string(v) + "-" + id, target,
                           Eigen::Quaterniond(0, 1, 0, 0), a.speed, 120);
        if (!r.done) throw std::runtime_error("move over " + id + " of view " + std::to_string(v) + ": " + r.message);
        row["tcp_reached"] = {r.tcp.x(), r.tcp.y(), r.tcp.z()};
        pointed = r.tcp - a.above * Eigen::Vector3d::UnitZ();
      }
      if (!truth.is_null()) {
        const auto plate =
            calibrate::from_row_major(truth.at("plate_to_base").at(v).get<std::vector<double>>(), "truth.json");
        const double dist = (pointed - plate * d.holes[h.drawing_index].centre).norm();
        row["distance_mm"] = dist * 1e3;
        worst = std::max(worst, dist);
        ss += dist * dist;
      }
      holes.push_back(row);
    }
  }
  if (!truth.is_null())
    std::printf("verify: %zu holes%s, distance to the true centres rms %.3f mm, worst %.3f mm\n", holes.size(),
                robot ? " (TCP moved over each)" : "", std::sqrt(ss / holes.size()) * 1e3, worst * 1e3);
  else
    std::printf("verify: %zu TCP targets %.0f mm above the predicted centres (measure each distance)\n", holes.size(),
                a.above * 1e3);
  json report{{"mode", "verify"}, {"moved", a.move}, {"holes", holes}};
  if (!truth.is_null()) report["rms_mm"] = std::sqrt(ss / holes.size()) * 1e3, report["worst_mm"] = worst * 1e3;
  write_json(a.report, report);
  return 0;
}

calibrate::SessionView session_view(const calibration::sim::View& v, std::size_t k) {
  calibrate::SessionView sv;
  char name[32];
  std::snprintf(name, sizeof name, "view_%03zu.png", k);
  sv.file = name;
  sv.depth = v.frame.depth;
  sv.intrinsics = v.frame.intrinsics;
  return sv;
}

void simulate_eye_to_hand(const Args& a, calibrate::Session& s, json& truth) {
  const calibration::Drawing d = calibration::calibration_plate_drawing();
  const auto sim = calibration::sim::eye_to_hand(a.profile, a.views > 0 ? a.views : 3, a.tcp_noise, a.seed);
  for (std::size_t k = 0; k < sim.views.size(); ++k) {
    calibrate::SessionView sv = session_view(sim.views[k], k);
    for (std::size_t h = 0; h < d.holes.size(); ++h) sv.tcp_at_hole[d.holes[h].id] = sim.tcp_at_hole[k][h];
    s.views.push_back(std::move(sv));
    truth["plate_to_base"].push_back(transform_json(sim.plate_to_base_true[k]));
  }
  truth["camera_to_base"] = transform_json(sim.camera_to_base_true);
}

Eigen::Isometry3d isometry(const Eigen::Vector3d& p, const Eigen::Quaterniond& q) {
  Eigen::Isometry3d t = Eigen::Isometry3d::Identity();
  t.linear() = q.normalized().toRotationMatrix();
  t.translation() = p;
  return t;
}

// Eye-in-hand with the simulated robot: each view pose is commanded over HG_ROBOT_MOVE; the camera renders
// from the pose HG_ROBOT_STATUS reports, off by the robot's repeatability (--tcp-noise): the reported pose is
// what the session keeps, as a real robot's reading.
void simulate_eye_in_hand_moved(const Args& a, const calibration::sim::EyeInHandPlan& plan, calibrate::Session& s,
                                json& truth) {
  calibrate::RobotMoves robot(a.lcm_url);
  std::mt19937_64 rng(a.seed ^ 0x5851f42d4c957f2dull);
  std::normal_distribution<double> n(0, a.tcp_noise), w(0, 0.1 * a.tcp_noise);
  const std::string stamp = cell::utc_now_iso();
  for (std::size_t k = 0; k < plan.flange_to_base.size(); ++k) {
    const Eigen::Isometry3d& commanded = plan.flange_to_base[k];
    const calibrate::MoveResult r =
        robot.move_to("calibrate-view-" + stamp + "-" + std::to_string(k), commanded.translation(),
                      Eigen::Quaterniond(commanded.linear()).normalized(), a.speed, 120);
    if (!r.done) throw std::runtime_error("move to view " + std::to_string(k) + ": " + r.message);
    const Eigen::Isometry3d reported = isometry(r.tcp, r.orientation);
    Eigen::Isometry3d actual = reported;  // where the robot really is
    const Eigen::Vector3d rot(w(rng), w(rng), w(rng));
    if (rot.norm() > 0)
      actual.linear() = reported.linear() * Eigen::AngleAxisd(rot.norm(), rot.normalized()).toRotationMatrix();
    actual.translation() += Eigen::Vector3d(n(rng), n(rng), n(rng));
    Eigen::Isometry3d rendered;  // the flange pose the renderer's truth implies: `actual`, to its placement rounding
    const calibration::sim::View v =
        calibration::sim::render_from_flange(a.profile, plan, actual, a.seed, k, &rendered);
    calibrate::SessionView sv = session_view(v, k);
    sv.flange_to_base = reported;
    s.views.push_back(std::move(sv));
    truth["plate_to_base"].push_back(transform_json(plan.plate_to_base_true));
    truth["commanded_flange"].push_back(transform_json(commanded));
    truth["reported_flange"].push_back(transform_json(reported));
    std::fprintf(stderr,
                 "hg-calibrate: view %zu: robot at (%.4f, %.4f, %.4f), %.3f mm from the commanded pose; rendered "
                 "%.2e m, %.2e rad from the reported one\n",
                 k, r.tcp.x(), r.tcp.y(), r.tcp.z(), (r.tcp - commanded.translation()).norm() * 1e3,
                 (rendered.translation() - reported.translation()).norm(),
                 calibration::rotation_distance(rendered.linear(), reported.linear()));
  }
}

void simulate_eye_in_hand(const Args& a, calibrate::Session& s, json& truth) {
  const int views = a.views > 0 ? a.views : 8;
  if (a.move) {
    const auto plan = calibration::sim::eye_in_hand_plan(a.profile, views, a.seed);
    simulate_eye_in_hand_moved(a, plan, s, truth);
    truth["robot"] = "moved over HG_ROBOT_MOVE; rendered from the reported pose + repeatability noise";
    truth["camera_to_flange"] = transform_json(plan.camera_to_flange_true);
    return;
  }
  const auto sim = calibration::sim::eye_in_hand(a.profile, views, a.tcp_noise, a.seed);
  for (std::size_t k = 0; k < sim.views.size(); ++k) {
    calibrate::SessionView sv = session_view(sim.views[k], k);
    sv.flange_to_base = sim.flange_to_base[k];
    s.views.push_back(std::move(sv));
    truth["plate_to_base"].push_back(transform_json(sim.plate_to_base_true));
  }
  truth["camera_to_flange"] = transform_json(sim.camera_to_flange_true);
}

int simulate(const Args& a) {
  calibrate::Session s;
  s.mode = a.sim_mode;
  json truth{{"source", "scene renderer ground truth (camera_from_table and the plate's placement)"},
             {"profile", a.profile},
             {"seed", a.seed},
             {"plate_to_base", json::array()}};
  if (a.sim_mode == "eye-to-hand") simulate_eye_to_hand(a, s, truth);
  else
    simulate_eye_in_hand(a, s, truth);
  calibrate::write_session(a.session, s);
  // The views' intrinsics beside the PNGs: the folder is also input for the camera bridge's files source.
  camera_bridge::write_intrinsics(s.views.front().intrinsics, a.session + "/intrinsics.yaml");
  write_json(a.session + "/truth.json", truth);
  std::printf("simulate: %s session, %zu views (%s, seed %llu%s) in %s\n", a.sim_mode.c_str(), s.views.size(),
              a.profile.c_str(), static_cast<unsigned long long>(a.seed),
              a.move && a.sim_mode == "eye-in-hand" ? ", robot moved" : "", a.session.c_str());
  return 0;
}

// Eye-to-hand by hand: the pointer is on a hole centre; its TCP from HG_ROBOT_STATUS goes into the session.
int touch(const Args& a) {
  calibrate::Session s = calibrate::read_session(a.session, false);
  const calibration::Drawing d = calibration::calibration_plate_drawing();
  bool known = false;
  for (const auto& h : d.holes) known |= h.id == a.hole;
  if (!known) throw std::runtime_error("--hole: '" + a.hole + "' is not a hole of the drawing (H1..H6)");
  const int view = a.view < 0 ? 0 : a.view;
  if (view >= static_cast<int>(s.views.size()))
    throw std::runtime_error("--view: " + std::to_string(view) + " not in the session (" +
                             std::to_string(s.views.size()) + " views)");
  calibrate::RobotMoves robot(a.lcm_url);
  const auto tcp = robot.current_tcp(a.timeout);
  if (!tcp) throw std::runtime_error("no HG_ROBOT_STATUS within " + std::to_string(a.timeout) + " s on " + a.lcm_url);
  s.views[view].tcp_at_hole[a.hole] = *tcp;
  calibrate::write_session(a.session, s);
  std::printf("touch: view %d hole %s at TCP (%.5f, %.5f, %.5f)\n", view, a.hole.c_str(), tcp->x(), tcp->y(), tcp->z());
  return 0;
}

// One view from the bus into the session (a new session takes --mode).
int capture(const Args& a) {
  if (!a.from_bus) throw std::runtime_error("capture: only --from-bus is a capture source (see --help)");
  calibrate::Session s;
  if (std::ifstream(a.session + "/session.json")) s = calibrate::read_session(a.session, false);
  else
    s.mode = a.sim_mode;
  const std::size_t k = a.view < 0 ? s.views.size() : static_cast<std::size_t>(a.view);
  if (k > s.views.size())
    throw std::runtime_error("--view: " + std::to_string(k) + " is past the session's end (" +
                             std::to_string(s.views.size()) + " views; the next is appended)");
  calibrate::CaptureOptions o;
  o.lcm_url = a.lcm_url;
  o.local_outline = a.local_outline;
  o.robot_pose = s.mode == "eye-in-hand";
  o.timeout_s = a.timeout;
  if (a.trigger) o.job_id = "calibrate-capture-" + cell::utc_now_iso() + "-" + std::to_string(k);
  const calibrate::Captured c = calibrate::capture_from_bus(o);
  // Refuse a view the fit could not use now, not at fit time.
  const calibration::PlateView seen =
      calibration::plate_from_loops(c.plane, c.loops, calibration::calibration_plate_drawing());
  if (k == s.views.size()) s.views.emplace_back();
  calibrate::SessionView& v = s.views[k];
  char name[40];
  std::snprintf(name, sizeof name, "view_%03zu.outline.json", k);
  v.kind = "outline", v.file = name, v.depth.release();
  v.plane = c.plane, v.loops = c.loops, v.outline_record = c.record;
  if (c.tcp_to_base) v.flange_to_base = c.tcp_to_base;
  calibrate::write_session(a.session, s);
  std::printf("capture: view %zu: %s; %s\n", k, c.text.c_str(), seen.text.c_str());
  return 0;
}

}  // namespace

int main(int argc, char** argv) {
  Args a;
  try {
    runtime::Params params(calibrate_params());
    const auto action = params.parse(argc, argv);
    if (action != runtime::Params::Action::Run)
      return runtime::answer(action, "hg-calibrate", params, [](std::FILE* f, const runtime::Params& p) {
        std::fputs(kUsage, f);
        std::fputs("options:\n", f);
        p.print_options(f);
      });
    a = args_from(params);
  } catch (const std::exception& e) {  // runtime::ConfigError
    std::fprintf(stderr, "hg-calibrate: %s (see --help)\n", e.what());
    return 2;
  }
  try {
    if (a.mode == "eye-to-hand") return eye_to_hand(a);
    if (a.mode == "eye-in-hand") return eye_in_hand(a);
    if (a.mode == "verify") return verify(a);
    if (a.mode == "simulate") return simulate(a);
    if (a.mode == "touch") return touch(a);
    if (a.mode == "capture") return capture(a);
    std::fprintf(stderr,
                 "hg-calibrate: unknown mode '%s' (eye-to-hand, eye-in-hand, verify, capture, touch, simulate)\n",
                 a.mode.c_str());
    return 2;
  } catch (const runtime::ConfigError& e) {  // a bad session or input file (the failure contract: exit 2)
    std::fprintf(stderr, "hg-calibrate: %s\n", e.what());
    return runtime::kExitBadInput;
  } catch (const cell::CellError& e) {  // a bad cell file
    std::fprintf(stderr, "hg-calibrate: cell file %s\n", e.what());
    return runtime::kExitBadInput;
  } catch (const std::exception& e) {
    std::fprintf(stderr, "hg-calibrate: refused: %s\n", e.what());
    return runtime::kExitFailed;
  }
}
