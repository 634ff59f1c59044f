// The cell file: round trip of random cells, dated backups, and errors that name the file and the key.
#include <cmath>
#include <filesystem>
#include <fstream>
#include <random>
#include <regex>
#include <string>

#include <gtest/gtest.h>

#include "cell/cell.hpp"
#include "runtime/quantities.hpp"

namespace fs = std::filesystem;
using hg::cell::Cell;
using hg::cell::CellError;

namespace {

fs::path scratch(const std::string& name) {
  const fs::path dir = fs::temp_directory_path() / ("hg_cell_test_" + std::to_string(::getpid()));
  fs::create_directories(dir);
  return dir / name;
}

Cell random_cell(std::mt19937_64& rng) {
  std::uniform_real_distribution<double> u(-1, 1);
  Cell c;
  const Eigen::Quaterniond q(Eigen::Vector4d(u(rng), u(rng), u(rng), u(rng)).normalized());
  c.calibration.camera_to_base.linear() = q.toRotationMatrix();
  c.calibration.camera_to_base.translation() = Eigen::Vector3d(u(rng), u(rng), 1 + u(rng));
  c.calibration.date = "2026-12-01T20:00:00Z";
  c.calibration.method = "eye-to-hand umeyama";
  c.calibration.rms_mm = 0.1 + 0.1 * std::abs(u(rng));
  c.calibration.worst_mm = c.calibration.rms_mm * (1 + std::abs(u(rng)));
  c.calibration.features = 6;
  if (rng() % 2) {
    Eigen::Isometry3d f = Eigen::Isometry3d::Identity();
    f.linear() = Eigen::Quaterniond(Eigen::Vector4d(u(rng), u(rng), u(rng), u(rng)).normalized()).toRotationMatrix();
    f.translation() = Eigen::Vector3d(0.1 * u(rng), 0.1 * u(rng), 0.1 * u(rng));
    c.calibration.camera_to_flange = f;
    if (rng() % 2) c.calibration.mounting = hg::cell::Mounting::EyeInHand;
  }
  c.workspace_min = Eigen::Vector3d(-1 + 0.1 * u(rng), -1 + 0.1 * u(rng), -0.2 + 0.1 * u(rng));
  c.workspace_max = Eigen::Vector3d(1 + 0.1 * u(rng), 1 + 0.1 * u(rng), 1 + 0.1 * u(rng));
  c.table_z = c.workspace_min.z() + 0.05;
  c.max_speed = 0.2 + 0.1 * std::abs(u(rng));
  c.max_accel = 1 + std::abs(u(rng));
  c.tool.radius = 0.01 + 0.005 * std::abs(u(rng));
  c.tool.tilt = 0.7 * std::abs(u(rng));  // tilts lean out over the air side: [0, 80 deg]
  c.frames.base = rng() % 2 ? "robot_base" : "ur10e/base_link." + std::to_string(rng() % 100);
  c.home = Eigen::Vector3d(0.5 * u(rng), 0.5 * u(rng), 0.3 + 0.1 * std::abs(u(rng)));
  c.approval = rng() % 2 ? hg::cell::Approval::Auto : hg::cell::Approval::Operator;
  return c;
}

std::string cell_text(const std::string& replace_from = "", const std::string& replace_to = "") {
  std::ifstream f(std::string(HG_SOURCE_DIR) + "/config/cell.yaml");
  std::stringstream s;
  s << f.rdbuf();
  std::string t = s.str();
  if (!replace_from.empty()) {
    const auto at = t.find(replace_from);
    EXPECT_NE(at, std::string::npos) << replace_from;
    if (at != std::string::npos) t.replace(at, replace_from.size(), replace_to);
  }
  return t;
}

// Writes text to a scratch file, reads it and returns the error message (empty: no error).
std::string error_of(const std::string& text, const fs::path& path) {
  std::ofstream(path) << text;
  try {
    hg::cell::read_cell(path.string());
  } catch (const CellError& e) {
    return e.what();
  }
  return "";
}

}  // namespace

TEST(Cell, RandomCellsSurviveAWriteAndARead) {
  for (std::uint64_t seed = 1; seed <= 50; ++seed) {
    SCOPED_TRACE(seed);
    std::mt19937_64 rng(seed);
    const Cell c = random_cell(rng);
    const fs::path p = scratch("round_trip.yaml");
    fs::remove(p);
    hg::cell::write_cell(p.string(), c);
    const Cell r = hg::cell::read_cell(p.string());
    EXPECT_EQ(r.calibration.mounting, c.calibration.mounting);
    EXPECT_EQ(r.calibration.camera_to_base.matrix(), c.calibration.camera_to_base.matrix());  // 17 digits: exact
    ASSERT_EQ(r.calibration.camera_to_flange.has_value(), c.calibration.camera_to_flange.has_value());
    if (c.calibration.camera_to_flange) {
      EXPECT_EQ(r.calibration.camera_to_flange->matrix(), c.calibration.camera_to_flange->matrix());
    }
    EXPECT_EQ(r.calibration.date, c.calibration.date);
    EXPECT_EQ(r.calibration.method, c.calibration.method);
    EXPECT_EQ(r.calibration.rms_mm, c.calibration.rms_mm);
    EXPECT_EQ(r.calibration.worst_mm, c.calibration.worst_mm);
    EXPECT_EQ(r.calibration.features, c.calibration.features);
    EXPECT_EQ(r.table_z, c.table_z);
    EXPECT_EQ(r.workspace_min, c.workspace_min);
    EXPECT_EQ(r.workspace_max, c.workspace_max);
    EXPECT_EQ(r.max_speed, c.max_speed);
    EXPECT_EQ(r.max_accel, c.max_accel);
    EXPECT_EQ(r.tool.radius, c.tool.radius);
    EXPECT_EQ(r.tool.tilt, c.tool.tilt);
    EXPECT_EQ(r.frames.base, c.frames.base);
    EXPECT_EQ(r.home, c.home);
    EXPECT_EQ(r.approval, c.approval);
  }
}

TEST(Cell, WritingKeepsThePreviousFileAsADatedBackup) {
  std::mt19937_64 rng(7);
  const fs::path p = scratch("backup.yaml");
  for (const auto& e : fs::directory_iterator(p.parent_path()))
    if (e.path().filename().string().rfind("backup.yaml.", 0) == 0) fs::remove(e.path());
  fs::remove(p);
  EXPECT_EQ(hg::cell::write_cell(p.string(), random_cell(rng)), "");  // nothing to keep the first time
  std::ifstream first(p);
  const std::string first_text((std::istreambuf_iterator<char>(first)), {});
  const std::string backup = hg::cell::write_cell(p.string(), random_cell(rng));
  ASSERT_FALSE(backup.empty());
  EXPECT_TRUE(std::regex_match(fs::path(backup).filename().string(), std::regex(R"(backup\.yaml\.\d{8}T\d{6}Z\.bak)")));
  std::ifstream kept(backup);
  EXPECT_EQ(std::string((std::istreambuf_iterator<char>(kept)), {}), first_text);
}

TEST(Cell, TheShippedCellFileHoldsThePlannersValues) {
  // Values of config/path_planner.yaml (camera_xyz [0.5, 0, 1.2], rpy [pi, 0, 0], table_z 0, workspace).
  const Cell c = hg::cell::read_cell(std::string(HG_SOURCE_DIR) + "/config/cell.yaml");
  const Eigen::Vector3d cam_in_base = c.calibration.camera_to_base * Eigen::Vector3d::Zero();
  EXPECT_EQ(cam_in_base, Eigen::Vector3d(0.5, 0, 1.2));
  EXPECT_EQ(c.calibration.camera_to_base.linear() * Eigen::Vector3d::UnitZ(), -Eigen::Vector3d::UnitZ());
  EXPECT_EQ(c.table_z, 0.0);
  EXPECT_EQ(c.workspace_min, Eigen::Vector3d(-1, -1, 0));
  EXPECT_EQ(c.workspace_max, Eigen::Vector3d(1.5, 1, 1));
  EXPECT_EQ(c.max_speed, 0.25);
  EXPECT_EQ(c.max_accel, 2.0);
  EXPECT_EQ(c.home, Eigen::Vector3d(0.5, 0, 0.3));
  EXPECT_EQ(c.approval, hg::cell::Approval::Operator);  // a plan waits for an operator
  // The simulated cell of make run approves a plan that reaches every edge by itself.
  EXPECT_EQ(hg::cell::read_cell(std::string(HG_SOURCE_DIR) + "/config/cell-sim.yaml").approval,
            hg::cell::Approval::Auto);
}

TEST(Cell, ApprovalIsOperatorUnlessTheFileSaysAuto) {
  const fs::path p = scratch("approval.yaml");
  std::ifstream in(std::string(HG_SOURCE_DIR) + "/config/cell.yaml");
  std::string text((std::istreambuf_iterator<char>(in)), std::istreambuf_iterator<char>());
  const std::size_t at = text.find("approval:");
  ASSERT_NE(at, std::string::npos);
  const std::string without = text.substr(0, at);
  std::ofstream(p) << without;
  EXPECT_EQ(hg::cell::read_cell(p.string()).approval, hg::cell::Approval::Operator);
  std::ofstream(p) << without << "approval: auto\n";
  EXPECT_EQ(hg::cell::read_cell(p.string()).approval, hg::cell::Approval::Auto);
  EXPECT_EQ(error_of(without + "approval: sometimes\n", p),
            p.string() + ": approval: 'sometimes' is not one of auto | operator");
  EXPECT_EQ(error_of(without + "approval: [auto]\n", p), p.string() + ": approval: expected a string");
}

TEST(Cell, ErrorsNameTheFileAndTheKey) {
  const fs::path p = scratch("bad.yaml");
  const std::string f = p.string() + ": ";
  struct Case {
    std::string from, to, expect;
  };
  const Case cases[] = {
      {"max-speed: 0.25", "max-sped: 0.25", f + "max-sped: unknown key"},
      {"max-speed: 0.25", "", f + "max-speed: missing"},
      {"max-accel: 2.0", "max-accel: fast", f + "max-accel: expected a number, got 'fast'"},
      {"max-accel: 2.0", "max-accel: .nan", f + "max-accel: not a finite number"},
      {"max-accel: 2.0", "max-accel: -2.0", f + "max-accel: must be > 0"},
      {"  radius: 0.01", "  radius: 0.01\n  diameter: 0.02", f + "tool.diameter: unknown key"},
      {"  rms-mm: 0", "  rms-mm: [1]", f + "calibration.rms-mm: expected a number"},
      {"    - [0, -1, 0, 0]", "    - [0, -1, 0]", f + "calibration.camera-to-base[1]: expected a row of 4"},
      {"    - [0, -1, 0, 0]", "    - [0, -2, 0, 0]", f + "calibration.camera-to-base: rotation part"},
      {"  min: [-1.0, -1.0, 0.0]", "  min: [-1.0, 2.0, 0.0]", f + "workspace.min: must be below"},
      {"  min: [-1.0, -1.0, 0.0]", "  min: [-1.0, -1.0]", f + "workspace.min: expected a list of 3"},
      {"home: [0.5, 0.0, 0.3]", "home: [0.5, 0.0, 3.0]", f + "home: must lie inside"},
      {"table-z: 0.0", "table-z: 0.0\ntable-z: 1.0", f + "table-z: given twice"},
      {"  mounting: eye-to-hand", "  mounting: on-the-wall",
       f + "calibration.mounting: 'on-the-wall' is neither eye-to-hand nor eye-in-hand"},
      {"  mounting: eye-to-hand", "  mounting: eye-in-hand",
       f + "calibration.camera-to-flange: missing: calibration.mounting eye-in-hand needs it"},
      {"  radius: 0.01", "  radius: 0.25", f + "tool.radius: must be within [0.001, 0.2] m"},
      {"  radius: 0.01", "  radius: 0", f + "tool.radius: must be within [0.001, 0.2] m"},
      {"  tilt: 0.7853981633974483", "  tilt: -0.1", f + "tool.tilt: must be within [0, 1.3962634015954636] rad"},
      {"  tilt: 0.7853981633974483", "  tilt: 1.4", f + "tool.tilt: must be within [0, 1.3962634015954636] rad"},
      {"  base: robot_base", "  base: robot base", f + "frames.base: 'robot base' is no frame name"},
      {"  base: robot_base", "  base: ''", f + "frames.base: '' is no frame name"},
      {"  base: robot_base", "  base: robot_base\n  tool: tcp", f + "frames.tool: unknown key"},
  };
  for (const Case& c : cases) {
    SCOPED_TRACE(c.to);
    const std::string err = error_of(cell_text(c.from, c.to), p);
    ASSERT_FALSE(err.empty());
    EXPECT_EQ(err.rfind(c.expect, 0), 0u) << err;
  }
  EXPECT_EQ(error_of(cell_text(), p), "");  // the unchanged file is fine
  // Without the key, a cell is eye-to-hand (the files written before it existed).
  EXPECT_EQ(error_of(cell_text("  mounting: eye-to-hand", ""), p), "");
  EXPECT_EQ(hg::cell::read_cell(p.string()).calibration.mounting, hg::cell::Mounting::EyeToHand);
  try {
    hg::cell::read_cell("/nonexistent/cell.yaml");
    ADD_FAILURE() << "no error";
  } catch (const CellError& e) {
    EXPECT_STREQ(e.what(), "/nonexistent/cell.yaml: cannot open");
  }
}

// The tool's keys take the job quantities' ranges (runtime/quantities.hpp), the ones the planner, the DDS
// gateway and hg-lcm-send check: both ends in, the next double beyond either end out (below 0: -1e-9), naming
// the key.
TEST(Cell, TheToolKeysTakeTheJobQuantitiesRanges) {
  namespace qn = hg::quantity;
  const fs::path p = scratch("tool_range.yaml");
  struct Key {
    std::string line, key;
    const qn::Quantity& q;
  } keys[] = {{"  radius: 0.01", "radius", qn::kToolRadius}, {"  tilt: 0.7853981633974483", "tilt", qn::kTilt}};
  auto yaml = [](double v) { return qn::number_text(v); };
  for (const Key& k : keys) {
    SCOPED_TRACE(k.key);
    for (double v : {k.q.min, k.q.max, 0.5 * (k.q.min + k.q.max)}) {
      EXPECT_EQ(error_of(cell_text(k.line, "  " + k.key + ": " + yaml(v)), p), "") << v;
      const Cell c = hg::cell::read_cell(p.string());
      EXPECT_EQ(k.key == "radius" ? c.tool.radius : c.tool.tilt, v);
    }
    for (double v : {k.q.min > 0 ? std::nextafter(k.q.min, -1.0) : -1e-9, std::nextafter(k.q.max, 10.0)})
      EXPECT_EQ(error_of(cell_text(k.line, "  " + k.key + ": " + yaml(v)), p),
                p.string() + ": tool." + k.key + ": must be within " + qn::range_text(k.q))
          << v;
  }
}

// Without a frames section the base frame is robot_base, the name every shipped file and message used.
TEST(Cell, TheBaseFrameDefaultsToRobotBase) {
  const fs::path p = scratch("frames.yaml");
  EXPECT_EQ(error_of(cell_text("frames:\n  base: robot_base", ""), p), "");
  EXPECT_EQ(hg::cell::read_cell(p.string()).frames.base, "robot_base");
  EXPECT_EQ(error_of(cell_text("  base: robot_base", "  base: ur/base_link"), p), "");
  EXPECT_EQ(hg::cell::read_cell(p.string()).frames.base, "ur/base_link");
}
