// hg-calibrate as a program (own network namespace: touch reads HG_ROBOT_STATUS of a sim robot bridge):
// the fit lands in the cell file with a backup, degenerate data is refused with the reason, touch records
// the robot's TCP.
#include <array>
#include <cstdio>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <string>

#include <gtest/gtest.h>
#include <nlohmann/json.hpp>
#include <opencv2/imgcodecs.hpp>

#include "calibration/geometry.hpp"
#include "cell/cell.hpp"
#include "tests/calibration/calibrate_cli.hpp"
#include "tests/common/cell_file.hpp"
#include "tests/common/child_process.hpp"

namespace fs = std::filesystem;
using nlohmann::json;

namespace {

const std::string kBin = HG_BIN_DIR;

fs::path scratch(const std::string& name) { return hg::test::scratch_dir("hg_calibrate_tool", name); }
int run(const std::string& cmd, std::string* err = nullptr) {
  return hg::test::run_command("hg_calibrate_tool", cmd, err);
}
Eigen::Isometry3d row_major(const json& v) { return hg::test::row_major_4x4(v); }

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

namespace {

// The depth PNG of a view as the camera-frame cloud it measures (every valid pixel deprojected, full-precision
// doubles), an ASCII .pcd.
void write_view_as_pcd(const fs::path& png, const json& in, const fs::path& pcd) {
  const cv::Mat depth = cv::imread(png.string(), cv::IMREAD_UNCHANGED);
  ASSERT_EQ(depth.type(), CV_16UC1);
  const double fx = in["fx"], fy = in["fy"], cx = in["cx"], cy = in["cy"], unit = in["depth_unit"];
  std::vector<std::array<double, 3>> pts;
  for (int r = 0; r < depth.rows; ++r)
    for (int c = 0; c < depth.cols; ++c)
      if (const auto d = depth.at<std::uint16_t>(r, c); d > 0) {
        const double z = d * unit;
        pts.push_back({(c - cx) / fx * z, (r - cy) / fy * z, z});
      }
  std::FILE* f = std::fopen(pcd.string().c_str(), "w");
  ASSERT_NE(f, nullptr);
  std::fprintf(f,
               "VERSION .7\nFIELDS x y z\nSIZE 8 8 8\nTYPE F F F\nCOUNT 1 1 1\nWIDTH %zu\nHEIGHT 1\n"
               "VIEWPOINT 0 0 0 1 0 0 0\nPOINTS %zu\nDATA ascii\n",
               pts.size(), pts.size());
  for (const auto& p : pts) std::fprintf(f, "%.17g %.17g %.17g\n", p[0], p[1], p[2]);
  std::fclose(f);
}

json fit_report(const fs::path& session, const fs::path& report, std::string* err) {
  const int rc = run(
      kBin + "/hg-calibrate eye-to-hand --dry-run --session " + session.string() + " --report " + report.string(), err);
  EXPECT_EQ(rc, 0) << *err;
  return rc == 0 ? json::parse(std::ifstream(report)) : json();
}

}  // namespace

// A view given as the .pcd cloud of the frame (deprojected through its intrinsics) is the same frame to the
// camera bridge's files source (nearest point per pixel, no resampling): the same transform, to rounding.
TEST(HgCalibrate, PcdViewsGiveThePngViewsTransform) {
  const fs::path d = scratch("pcd");
  ASSERT_EQ(run(kBin + "/hg-calibrate simulate --mode eye-to-hand --profile lsr-l --seed 3 --session " +
                (d / "png").string()),
            0);
  fs::copy(d / "png", d / "pcd");
  json s = json::parse(std::ifstream(d / "pcd" / "session.json"));
  for (std::size_t k = 0; k < s["views"].size(); ++k) {
    json& v = s["views"][k];
    const std::string name = "view_" + std::to_string(k) + ".pcd";
    write_view_as_pcd(d / "pcd" / v["depth"].get<std::string>(), v["intrinsics"], d / "pcd" / name);
    fs::remove(d / "pcd" / v["depth"].get<std::string>());
    v.erase("depth");
    v["cloud"] = name;
  }
  std::ofstream(d / "pcd" / "session.json") << s.dump();
  std::string err;
  const json png = fit_report(d / "png", d / "png.json", &err), pcd = fit_report(d / "pcd", d / "pcd.json", &err);
  ASSERT_FALSE(pcd.is_null());
  const Eigen::Isometry3d a = row_major(png["camera_to_base"]), b = row_major(pcd["camera_to_base"]);
  EXPECT_LT((a.translation() - b.translation()).norm(), 1e-9);
  EXPECT_LT(hg::calibration::rotation_distance(a.linear(), b.linear()), 1e-9);
  EXPECT_EQ(pcd["per_feature"].size(), 18u);
  // A cloud file that is not one: refused naming the session key and the file.
  std::ofstream(d / "pcd" / "view_1.pcd") << "VERSION .7\nFIELDS x y z\nPOINTS 3\n";
  EXPECT_EQ(run(kBin + "/hg-calibrate eye-to-hand --dry-run --session " + (d / "pcd").string(), &err), 1);
  EXPECT_NE(err.find("session.json: views[1].cloud: "), std::string::npos) << err;
  EXPECT_NE(err.find("view_1.pcd"), std::string::npos) << err;
}

// Three touched holes on a line (in the robot frame) are not enough: refused with the reason, nothing written.
TEST(HgCalibrate, CollinearTouchedHolesAreRefused) {
  const fs::path d = scratch("collinear");
  ASSERT_EQ(
      run(kBin + "/hg-calibrate simulate --mode eye-to-hand --profile pm806 --views 1 --session " + (d / "s").string()),
      0);
  json s = json::parse(std::ifstream(d / "s" / "session.json"));
  json& t = s["views"][0]["tcp_at_hole"];
  const auto h1 = t["H1"].get<std::vector<double>>(), h2 = t["H2"].get<std::vector<double>>();
  json line = {{"H1", h1}, {"H2", h2}, {"H3", {(h1[0] + h2[0]) / 2, (h1[1] + h2[1]) / 2, (h1[2] + h2[2]) / 2}}};
  t = line;
  std::ofstream(d / "s" / "session.json") << s.dump();
  const std::string cell = (d / "cell.yaml").string();
  fs::copy_file(std::string(HG_SOURCE_DIR) + "/config/cell.yaml", cell);
  std::string err;
  EXPECT_EQ(run(kBin + "/hg-calibrate eye-to-hand --session " + (d / "s").string() + " --cell " + cell, &err), 1);
  EXPECT_NE(err.find("the robot features are collinear"), std::string::npos) << err;
  EXPECT_NE(err.find("need 3 non-collinear"), std::string::npos) << err;
  int files = 0;
  for (const auto& e : fs::directory_iterator(d)) files += e.path().filename().string().rfind("cell.yaml", 0) == 0;
  EXPECT_EQ(files, 1);  // no backup: the cell file was not touched
}

// Eye-in-hand views that do not turn the camera (the same view four times) or too few views: refused.
TEST(HgCalibrate, EyeInHandViewsWithoutEnoughRotationAreRefused) {
  const fs::path d = scratch("norotation");
  ASSERT_EQ(
      run(kBin + "/hg-calibrate simulate --mode eye-in-hand --profile pm806 --views 4 --session " + (d / "s").string()),
      0);
  json s = json::parse(std::ifstream(d / "s" / "session.json"));
  const json all = s["views"];
  for (auto& v : s["views"]) v = all[0];
  std::ofstream(d / "s" / "session.json") << s.dump();
  std::string err;
  EXPECT_EQ(run(kBin + "/hg-calibrate eye-in-hand --dry-run --session " + (d / "s").string(), &err), 1);
  EXPECT_NE(err.find("hand-eye: views without enough rotation: the largest rotation between two views is 0"),
            std::string::npos)
      << err;
  s["views"] = json::array({all[0], all[1]});
  std::ofstream(d / "s" / "session.json") << s.dump();
  EXPECT_EQ(run(kBin + "/hg-calibrate eye-in-hand --dry-run --session " + (d / "s").string(), &err), 1);
  EXPECT_NE(err.find("hand-eye: 2 views, need at least 3"), std::string::npos) << err;
}
