// hg-calibrate: camera-to-robot calibration from the drilled calibration plate (docs/calibration.md).
#include <cmath>
#include <cstdio>
#include <fstream>
#include <memory>
#include <string>

#include <nlohmann/json.hpp>

#include "calibration/sim.hpp"
#include "calibration/target.hpp"
#include "cell/cell.hpp"
#include "runtime/lcm_url.hpp"
#include "runtime/version.hpp"
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
  touch         records the robot's TCP (next HG_ROBOT_STATUS) as the position of hole --hole in view --view
                of the session (eye-to-hand: bring the pointer to the hole centre, then run this)
  simulate      writes a simulated session (virtual camera, renderer's truth in DIR/truth.json)
options:
  --session DIR     session folder: DIR/session.json (+ depth PNGs)
  --cell FILE       cell file to update / read (default config/cell.yaml); a dated backup is kept
  --report FILE     JSON report of the fit (transform, residuals per feature and per view)
  --dry-run         do not write the cell file
  --above M         verify: height of the TCP target above the hole centre (default 0.01)
  --move            verify: move the robot's TCP to each target over the bus (HG_ROBOT_MOVE, answered on
                    HG_JOB_STATUS; docs/CHANNELS.md) and report where HG_ROBOT_STATUS says it got
  --lcm-url URL     with --move [default: $LCM_DEFAULT_URL, else udpm://239.255.76.67:7667?ttl=0]
  --speed V         with --move: m/s (default 0.1)
touch only:  --view K (default 0)  --hole H1..H6
simulate only:
  --mode eye-to-hand|eye-in-hand  --profile pm806|lsr-l  --views N (default 3 / 8)  --seed N
  --tcp-noise M     robot reading error per axis, metres (default 0.00005)
Exit status: 0 done, 1 refused (the reason on stderr), 2 usage.
)";

struct Args {
  std::string mode, session, cell = "config/cell.yaml", report, sim_mode = "eye-to-hand", profile = "pm806";
  bool dry_run = false, move = false;
  std::string lcm_url = runtime::default_lcm_url();
  double speed = 0.1;
  double above = 0.01, tcp_noise = 0.00005;
  int views = 0, view = 0;
  std::string hole;
  std::uint64_t seed = 1;
};

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
      out.push_back(calibration::detect_plate(s.views[i].depth, s.views[i].intrinsics, d));
    } catch (const calibration::CalibrationError& e) {
      throw calibration::CalibrationError("view " + std::to_string(i) + " (" + s.views[i].depth_file +
                                          "): " + e.what());
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
  for (std::size_t v = 0; v < seen.size(); ++v) {
    flange.push_back(*s.views[v].flange_to_base);
    plate.push_back(seen[v].plate_to_camera);
  }
  const calibration::HandEyeResult r = calibration::solve_eye_in_hand(flange, plate);
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
  const calibrate::Session s = calibrate::read_session(a.session);
  const cell::Cell c = cell::read_cell(a.cell);
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
  sv.depth_file = name;
  sv.depth = v.frame.depth;
  sv.intrinsics = v.frame.intrinsics;
  return sv;
}

int simulate(const Args& a) {
  calibrate::Session s;
  s.mode = a.sim_mode;
  json truth{{"source", "scene renderer ground truth (camera_from_table and the plate's placement)"},
             {"profile", a.profile},
             {"seed", a.seed},
             {"plate_to_base", json::array()}};
  const calibration::Drawing d = calibration::calibration_plate_drawing();
  if (a.sim_mode == "eye-to-hand") {
    const auto sim = calibration::sim::eye_to_hand(a.profile, a.views > 0 ? a.views : 3, a.tcp_noise, a.seed);
    for (std::size_t k = 0; k < sim.views.size(); ++k) {
      calibrate::SessionView sv = session_view(sim.views[k], k);
      for (std::size_t h = 0; h < d.holes.size(); ++h) sv.tcp_at_hole[d.holes[h].id] = sim.tcp_at_hole[k][h];
      s.views.push_back(std::move(sv));
      truth["plate_to_base"].push_back(transform_json(sim.plate_to_base_true[k]));
    }
    truth["camera_to_base"] = transform_json(sim.camera_to_base_true);
  } else if (a.sim_mode == "eye-in-hand") {
    const auto sim = calibration::sim::eye_in_hand(a.profile, a.views > 0 ? a.views : 8, a.tcp_noise, a.seed);
    for (std::size_t k = 0; k < sim.views.size(); ++k) {
      calibrate::SessionView sv = session_view(sim.views[k], k);
      sv.flange_to_base = sim.flange_to_base[k];
      s.views.push_back(std::move(sv));
      truth["plate_to_base"].push_back(transform_json(sim.plate_to_base_true));
    }
    truth["camera_to_flange"] = transform_json(sim.camera_to_flange_true);
  } else {
    throw std::runtime_error("--mode: unknown '" + a.sim_mode + "' (eye-to-hand, eye-in-hand)");
  }
  calibrate::write_session(a.session, s);
  write_json(a.session + "/truth.json", truth);
  std::printf("simulate: %s session, %zu views (%s, seed %llu) in %s\n", a.sim_mode.c_str(), s.views.size(),
              a.profile.c_str(), static_cast<unsigned long long>(a.seed), a.session.c_str());
  return 0;
}

// Eye-to-hand by hand: the pointer is on a hole centre; its TCP from HG_ROBOT_STATUS goes into the session.
int touch(const Args& a) {
  calibrate::Session s = calibrate::read_session(a.session);
  const calibration::Drawing d = calibration::calibration_plate_drawing();
  bool known = false;
  for (const auto& h : d.holes) known |= h.id == a.hole;
  if (!known) throw std::runtime_error("--hole: '" + a.hole + "' is not a hole of the drawing (H1..H6)");
  if (a.view < 0 || a.view >= static_cast<int>(s.views.size()))
    throw std::runtime_error("--view: " + std::to_string(a.view) + " not in the session (" +
                             std::to_string(s.views.size()) + " views)");
  calibrate::RobotMoves robot(a.lcm_url);
  const auto tcp = robot.current_tcp(5.0);
  if (!tcp) throw std::runtime_error("no HG_ROBOT_STATUS within 5 s on " + a.lcm_url);
  s.views[a.view].tcp_at_hole[a.hole] = *tcp;
  calibrate::write_session(a.session, s);
  std::printf("touch: view %d hole %s at TCP (%.5f, %.5f, %.5f)\n", a.view, a.hole.c_str(), tcp->x(), tcp->y(),
              tcp->z());
  return 0;
}

bool parse(int argc, char** argv, Args& a) {
  if (argc < 2) return false;
  a.mode = argv[1];
  for (int i = 2; i < argc; ++i) {
    const std::string o = argv[i];
    auto value = [&]() -> std::string {
      if (i + 1 >= argc) throw std::runtime_error(o + ": needs a value");
      return argv[++i];
    };
    if (o == "--session") a.session = value();
    else if (o == "--cell")
      a.cell = value();
    else if (o == "--report")
      a.report = value();
    else if (o == "--dry-run")
      a.dry_run = true;
    else if (o == "--move")
      a.move = true;
    else if (o == "--view")
      a.view = std::stoi(value());
    else if (o == "--hole")
      a.hole = value();
    else if (o == "--lcm-url")
      a.lcm_url = value();
    else if (o == "--speed")
      a.speed = std::stod(value());
    else if (o == "--above")
      a.above = std::stod(value());
    else if (o == "--mode")
      a.sim_mode = value();
    else if (o == "--profile")
      a.profile = value();
    else if (o == "--views")
      a.views = std::stoi(value());
    else if (o == "--seed")
      a.seed = std::stoull(value());
    else if (o == "--tcp-noise")
      a.tcp_noise = std::stod(value());
    else
      throw std::runtime_error("unknown option " + o);
  }
  return !a.session.empty();
}

}  // namespace

int main(int argc, char** argv) {
  Args a;
  if (hg::runtime::answer_version(argc, argv, "hg-calibrate")) return 0;
  try {
    if (argc >= 2 && std::string(argv[1]) == "--help") {
      std::fputs(kUsage, stdout);
      return 0;
    }
    if (!parse(argc, argv, a)) {
      std::fputs(kUsage, stderr);
      return 2;
    }
  } catch (const std::exception& e) {
    std::fprintf(stderr, "hg-calibrate: %s\n", e.what());
    return 2;
  }
  try {
    if (a.mode == "eye-to-hand") return eye_to_hand(a);
    if (a.mode == "eye-in-hand") return eye_in_hand(a);
    if (a.mode == "verify") return verify(a);
    if (a.mode == "simulate") return simulate(a);
    if (a.mode == "touch") return touch(a);
    std::fprintf(stderr, "hg-calibrate: unknown mode '%s'\n%s", a.mode.c_str(), kUsage);
    return 2;
  } catch (const std::exception& e) {
    std::fprintf(stderr, "hg-calibrate: refused: %s\n", e.what());
    return 1;
  }
}
