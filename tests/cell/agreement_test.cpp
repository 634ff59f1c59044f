// The planner and the robot bridge configured from one cell file agree on every limit: both read the same
// table, workspace, speed and acceleration (the cell's values, as written), and every path the planner
// validates on generated jobs is accepted by the bridge's own path check, from the robot's position. A
// control shows the check has teeth: a bridge whose cell allows less refuses some of those paths.
#include <algorithm>
#include <cmath>
#include <cstdio>
#include <filesystem>
#include <random>
#include <string>

#include <gtest/gtest.h>

#include "cell/cell.hpp"
#include "path_planner/io.hpp"
#include "robot_bridge/path.hpp"
#include "robot_bridge/robot_bridge.hpp"

namespace pp = hg::path_planner;
namespace rb = hg::robot_bridge;
using Eigen::Vector3d;
using hg::cell::Cell;

namespace {

std::string scratch(const std::string& name) {
  const auto dir = std::filesystem::temp_directory_path() / ("hg_cell_agree_" + std::to_string(::getpid()));
  std::filesystem::create_directories(dir);
  std::filesystem::remove(dir / name);
  return (dir / name).string();
}

// A cell with the camera `height` above the table looking down, random limits and box (full-precision
// doubles), home inside the box above the table.
Cell random_cell(std::mt19937_64& rng, double& height) {
  std::uniform_real_distribution<double> u(0, 1);
  Cell c;
  c.table_z = -0.2 + 0.4 * u(rng);
  height = c.table_z + 1.0 + 0.6 * u(rng);
  Eigen::Isometry3d T = Eigen::Isometry3d::Identity();
  T.linear() = Eigen::AngleAxisd(M_PI, Vector3d::UnitX()).toRotationMatrix() *
               Eigen::AngleAxisd(0.3 * (u(rng) - 0.5), Vector3d::UnitZ()).toRotationMatrix();
  T.translation() = Vector3d(0.3 + 0.4 * u(rng), 0.2 * (u(rng) - 0.5), height);
  c.calibration.camera_to_base = T;
  c.calibration.date = "2026-12-01T00:00:00Z";
  c.calibration.method = "manual";
  c.workspace_min = Vector3d(-0.6 - u(rng), -0.6 - u(rng), c.table_z - 0.1 * u(rng));
  c.workspace_max = Vector3d(1.2 + u(rng), 0.6 + u(rng), c.table_z + 0.5 + u(rng));
  c.max_speed = 0.05 + 0.3 * u(rng);
  c.max_accel = 0.2 + 3 * u(rng);
  c.tool.radius = 0.004 + 0.01 * u(rng);
  c.tool.tilt = 0.9 * u(rng);
  c.home = Vector3d(0.5, 0, c.table_z + 0.3);
  return c;
}

// A rectangular plate with a rectangular hole, turned, as the outline of the camera's view: plane `distance`
// in front of the camera (the plate's top surface).
pp::OutlineInput random_plate(std::mt19937_64& rng, double distance) {
  std::uniform_real_distribution<double> u(0, 1);
  const double w = 0.15 + 0.25 * u(rng), h = 0.1 + 0.15 * u(rng), a = M_PI * u(rng);
  const Eigen::Rotation2Dd R(a);
  auto ring = [&](double x0, double y0, double x1, double y1, bool hole) {
    pp::Loop l;
    l.hole = hole;
    for (const Eigen::Vector2d& p :
         {Eigen::Vector2d(x0, y0), Eigen::Vector2d(x1, y0), Eigen::Vector2d(x1, y1), Eigen::Vector2d(x0, y1)})
      l.points.push_back(R * p);
    if (hole) std::reverse(l.points.begin(), l.points.end());
    return l;
  };
  pp::OutlineInput in;
  in.loops.push_back(ring(-w / 2, -h / 2, w / 2, h / 2, false));
  in.loops.push_back(ring(-w / 6, -h / 6, w / 6 + 0.02 * u(rng), h / 6, true));
  in.plane = {Vector3d(0.05 * (u(rng) - 0.5), 0.05 * (u(rng) - 0.5), distance), Vector3d(1, 0, 0), Vector3d(0, -1, 0),
              Vector3d(0, 0, -1)};
  in.plane_given = true;
  return in;
}

std::string exact(double v) {  // all 17 digits: a rounded-up speed would contradict the cell
  char buf[32];
  std::snprintf(buf, sizeof buf, "%.17g", v);
  return buf;
}

rb::Limits bridge_limits(const std::string& cell_file) {
  hg::runtime::Params params(rb::process_info().params);
  params.set("cell", cell_file);
  return rb::limits_from(params);
}

}  // namespace

TEST(CellAgreement, PlannerAndBridgeReadTheSameLimits) {
  for (std::uint64_t seed = 1; seed <= 20; ++seed) {
    SCOPED_TRACE(seed);
    std::mt19937_64 rng(seed);
    double height = 0;
    const Cell c = random_cell(rng, height);
    const std::string file = scratch("limits.yaml");
    hg::cell::write_cell(file, c);
    const pp::PlannerConfig cfg =
        pp::config_from(pp::lookup_from({{"cell", file}, {"travel-speed", exact(c.max_speed)}}, hg::runtime::Config()));
    const rb::Limits b = bridge_limits(file);
    for (const auto* L : {&cfg.limits, &b}) {  // both equal to the values written
      EXPECT_EQ(L->table_z, c.table_z);
      EXPECT_EQ(L->workspace_min, c.workspace_min);
      EXPECT_EQ(L->workspace_max, c.workspace_max);
      EXPECT_EQ(L->max_speed, c.max_speed);
      EXPECT_EQ(L->max_accel, c.max_accel);
    }
    EXPECT_EQ(cfg.camera_to_base.matrix(), c.calibration.camera_to_base.matrix());
    EXPECT_EQ(cfg.home, c.home);
    EXPECT_EQ(cfg.defaults.tool_radius, c.tool.radius);
    EXPECT_EQ(cfg.defaults.tilt, c.tool.tilt);
  }
}

TEST(CellAgreement, TheBridgeAcceptsEveryPathThePlannerValidates) {
  int planned = 0, refused_by_stricter = 0;
  for (std::uint64_t seed = 1; seed <= 40; ++seed) {
    SCOPED_TRACE(seed);
    std::mt19937_64 rng(seed);
    std::uniform_real_distribution<double> u(0, 1);
    double height = 0;
    Cell c = random_cell(rng, height);
    const std::string file = scratch("cell.yaml");
    hg::cell::write_cell(file, c);
    c.max_accel /= 4;  // the control: a cell that allows less
    const std::string stricter = scratch("stricter.yaml");
    hg::cell::write_cell(stricter, c);
    const pp::PlannerConfig cfg = pp::config_from(pp::lookup_from(
        {{"cell", file}, {"small-hole", "skip"}, {"travel-speed", exact(c.max_speed)}}, hg::runtime::Config()));
    const rb::Limits limits = bridge_limits(file), strict = bridge_limits(stricter);
    for (int job = 0; job < 3; ++job) {
      const pp::OutlineInput in = random_plate(rng, height - c.table_z - 0.01);
      pp::JobParams jp;  // as a job request: zeros take the defaults (the cell's tool); a fast feed
      jp.tool_radius = jp.tilt = jp.travel_speed = jp.step = jp.safe_height = 0;
      jp.grind_speed = c.max_speed * (0.2 + 0.8 * u(rng));
      const Vector3d robot(c.workspace_min.x() + 0.2 + u(rng), 0.4 * (u(rng) - 0.5), c.table_z + 0.1 + 0.3 * u(rng));
      const pp::PlanResult r = pp::plan(in, jp, cfg, robot);
      if (!r.ok) {
        std::printf("  seed %llu job %d not planned: %s\n", (unsigned long long)seed, job, r.reason.c_str());
        continue;
      }
      ++planned;
      const rb::Path path = rb::from_lcm(pp::to_lcm(r, "agree", 0, "robot_base", 0));
      const rb::Pose start{robot, Eigen::Quaterniond::Identity()};
      EXPECT_EQ(rb::check_path(path, start, limits), "") << "job " << job;
      refused_by_stricter += !rb::check_path(path, start, strict).empty();
    }
  }
  std::printf("  %d jobs planned and accepted; a cell with a quarter of the acceleration refused %d of them\n", planned,
              refused_by_stricter);
  EXPECT_GE(planned, 80) << "too few generated jobs planned for the property to mean much";
  EXPECT_GT(refused_by_stricter, 0) << "the control: a stricter cell must refuse some of these paths";
}
