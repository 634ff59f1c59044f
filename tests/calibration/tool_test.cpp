// hg-calibrate as a program (own network namespace: touch reads HG_ROBOT_STATUS of a sim robot bridge):
// the fit lands in the cell file with a backup, degenerate data is refused with the reason, touch records
// the robot's TCP.
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <string>

#include <gtest/gtest.h>
#include <nlohmann/json.hpp>

#include "calibration/geometry.hpp"
#include "cell/cell.hpp"
#include "tests/common/cell_file.hpp"
#include "tests/common/child_process.hpp"

namespace fs = std::filesystem;
using nlohmann::json;

namespace {

const std::string kBin = HG_BIN_DIR;

fs::path scratch(const std::string& name) {
  const fs::path d = fs::temp_directory_path() / ("hg_calibrate_tool_" + std::to_string(::getpid())) / name;
  fs::remove_all(d);
  fs::create_directories(d);
  return d;
}

// Runs a command line; returns its exit status, stderr in *err.
int run(const std::string& cmd, std::string* err = nullptr) {
  const std::string log =
      (fs::temp_directory_path() / ("hg_calibrate_tool_err_" + std::to_string(::getpid()))).string();
  const int status = std::system((cmd + " 2>" + log + " >/dev/null").c_str());
  if (err) {
    std::ifstream f(log);
    *err = std::string((std::istreambuf_iterator<char>(f)), {});
  }
  return WIFEXITED(status) ? WEXITSTATUS(status) : -1;
}

Eigen::Isometry3d row_major(const json& v) {
  Eigen::Isometry3d t = Eigen::Isometry3d::Identity();
  for (int r = 0; r < 4; ++r)
    for (int c = 0; c < 4; ++c) t.matrix()(r, c) = v.at(4 * r + c).get<double>();
  return t;
}

}  // namespace

TEST(HgCalibrate, EyeToHandWritesTheCellFileAndKeepsABackup) {
  const fs::path d = scratch("e2h");
  const std::string cell = (d / "cell.yaml").string();
  fs::copy_file(std::string(HG_SOURCE_DIR) + "/config/cell.yaml", cell);
  ASSERT_EQ(
      run(kBin + "/hg-calibrate simulate --mode eye-to-hand --profile pm806 --seed 5 --session " + (d / "s").string()),
      0);
  std::string err;
  ASSERT_EQ(run(kBin + "/hg-calibrate eye-to-hand --session " + (d / "s").string() + " --cell " + cell, &err), 0)
      << err;
  const hg::cell::Cell c = hg::cell::read_cell(cell);
  json truth = json::parse(std::ifstream(d / "s" / "truth.json"));
  const Eigen::Isometry3d t = row_major(truth["camera_to_base"]);
  EXPECT_LT((c.calibration.camera_to_base.translation() - t.translation()).norm(), 0.0005);
  EXPECT_LT(hg::calibration::rotation_distance(c.calibration.camera_to_base.linear(), t.linear()), 0.05 * M_PI / 180);
  EXPECT_EQ(c.calibration.method, "eye-to-hand umeyama");
  EXPECT_EQ(c.calibration.features, 18);
  int backups = 0;
  for (const auto& e : fs::directory_iterator(d)) backups += e.path().filename().string().rfind("cell.yaml.", 0) == 0;
  EXPECT_EQ(backups, 1);
}

TEST(HgCalibrate, TooFewTouchedHolesAreRefusedWithTheReason) {
  const fs::path d = scratch("few");
  ASSERT_EQ(
      run(kBin + "/hg-calibrate simulate --mode eye-to-hand --profile pm806 --views 1 --session " + (d / "s").string()),
      0);
  json s = json::parse(std::ifstream(d / "s" / "session.json"));
  json kept = {{"H1", s["views"][0]["tcp_at_hole"]["H1"]}, {"H2", s["views"][0]["tcp_at_hole"]["H2"]}};
  s["views"][0]["tcp_at_hole"] = kept;
  std::ofstream(d / "s" / "session.json") << s.dump();
  std::string err;
  EXPECT_EQ(run(kBin + "/hg-calibrate eye-to-hand --dry-run --session " + (d / "s").string(), &err), 1);
  EXPECT_NE(err.find("2 features, need at least 3 non-collinear"), std::string::npos) << err;
  s["views"][0]["tcp_at_hole"]["H1"] = {1.0, 2.0};
  std::ofstream(d / "s" / "session.json") << s.dump();
  EXPECT_EQ(run(kBin + "/hg-calibrate eye-to-hand --dry-run --session " + (d / "s").string(), &err), 1);
  EXPECT_NE(err.find("session.json: views[0].tcp_at_hole.H1: expected [x, y, z]"), std::string::npos) << err;
}

TEST(HgCalibrate, TouchRecordsTheRobotsTcp) {
  const fs::path d = scratch("touch");
  ASSERT_EQ(
      run(kBin + "/hg-calibrate simulate --mode eye-to-hand --profile pm806 --views 1 --session " + (d / "s").string()),
      0);
  // The sim robot at rest where the test put it: the home of its cell file.
  const std::string cell = hg::test::write_test_cell(
      (d / "robot_cell.yaml").string(), [](hg::cell::Cell& c) { c.home = Eigen::Vector3d(0.41, -0.07, 0.23); });
  hg::test::ChildProcess robot(
      {kBin + "/hg-robot-bridge", "--driver", "sim", "--cell", cell, "--state-file", (d / "robot.state").string()},
      hg::test::ChildOptions().stderr_to((d / "robot.log").string()));
  std::string err;
  ASSERT_EQ(run(kBin + "/hg-calibrate touch --view 0 --hole H3 --session " + (d / "s").string(), &err), 0) << err;
  const json s = json::parse(std::ifstream(d / "s" / "session.json"));
  const auto p = s["views"][0]["tcp_at_hole"]["H3"].get<std::vector<double>>();
  EXPECT_EQ(p, (std::vector<double>{0.41, -0.07, 0.23}));
  EXPECT_EQ(run(kBin + "/hg-calibrate touch --view 0 --hole H9 --session " + (d / "s").string(), &err), 1);
  EXPECT_NE(err.find("'H9' is not a hole of the drawing"), std::string::npos) << err;
}
