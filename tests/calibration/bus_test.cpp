// hg-calibrate capture --from-bus (own network namespace): a session recorded from the product's pipeline on
// a live bus (hg-camera-bridge with the files source, hg-outline-service, hg-robot-bridge --driver sim) gives
// the transform of the PNG session of the same scene, and an eye-in-hand capture takes the robot's pose.
#include <cmath>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <string>

#include <gtest/gtest.h>
#include <nlohmann/json.hpp>

#include "calibration/geometry.hpp"
#include "calibration/target.hpp"
#include "tests/calibration/calibrate_cli.hpp"
#include "tests/common/cell_file.hpp"
#include "tests/common/child_process.hpp"

namespace fs = std::filesystem;
using nlohmann::json;

namespace {

const std::string kBin = HG_BIN_DIR;

fs::path scratch(const std::string& name) { return hg::test::scratch_dir("hg_calibrate_bus", name); }
int run(const std::string& cmd, std::string* err = nullptr) {
  return hg::test::run_command("hg_calibrate_bus", cmd, err);
}
Eigen::Isometry3d row_major(const json& v) { return hg::test::row_major_4x4(v); }

hg::test::ChildProcess start(const std::vector<std::string>& argv, const fs::path& log) {
  return hg::test::ChildProcess(argv, hg::test::ChildOptions().stderr_to(log.string()));
}

// RMS distance of the drawing's hole centres from their centroid: the lever arm of the rotation estimate.
double hole_spread() {
  const auto d = hg::calibration::calibration_plate_drawing();
  Eigen::Vector3d c = Eigen::Vector3d::Zero();
  for (const auto& h : d.holes) c += h.centre / d.holes.size();
  double ss = 0;
  for (const auto& h : d.holes) ss += (h.centre - c).squaredNorm() / d.holes.size();
  return std::sqrt(ss);
}

}  // namespace

// The scene's three depth frames go through the camera bridge (files source, one capture per START) and the
// outline service; hg-calibrate takes the plate clouds and outlines off the bus (views 0 and 1: HG_OUTLINE;
// view 2: the outline core run in hg-calibrate on the cloud) and keeps the session's TCP readings. Both paths
// run the same segmentation, outline core and circle fit, so the bus session must agree with the PNG session
// far inside the fit's own statistical error: within a fifth of the standard error the residuals imply
// (translation rms / sqrt(N); rotation rms / (sqrt(N) x the holes' spread)).
TEST(HgCalibrateBus, SessionFromTheBusGivesThePngSessionsTransform) {
  const fs::path d = scratch("e2h");
  ASSERT_EQ(run(kBin + "/hg-calibrate simulate --mode eye-to-hand --profile pm806 --seed 5 --session " +
                (d / "png").string()),
            0);
  fs::copy(d / "png", d / "bus");
  for (const auto& e : fs::directory_iterator(d / "bus"))
    if (e.path().extension() == ".png") fs::remove(e.path());  // the bus session keeps no frame
  auto camera =
      start({kBin + "/hg-camera-bridge", "--source", "files", "--files.path", (d / "png").string(), "--trigger", "job"},
            d / "camera.log");
  auto outline = start({kBin + "/hg-outline-service"}, d / "outline.log");
  std::string err;
  for (int k = 0; k < 3; ++k)
    ASSERT_EQ(run(kBin + "/hg-calibrate capture --from-bus --trigger --timeout 30 --view " + std::to_string(k) +
                      (k == 2 ? " --local-outline" : "") + " --session " + (d / "bus").string(),
                  &err),
              0)
        << err;
  const json session = json::parse(std::ifstream(d / "bus" / "session.json"));
  for (const auto& v : session["views"]) {
    ASSERT_TRUE(v.contains("outline")) << v.dump();
    EXPECT_EQ(v["tcp_at_hole"].size(), 6u);  // the TCP readings of the view were kept
  }
  const json rec0 = json::parse(std::ifstream(d / "bus" / "view_000.outline.json"));
  const json rec2 = json::parse(std::ifstream(d / "bus" / "view_002.outline.json"));
  EXPECT_EQ(rec0["source"], "HG_PLATE_CLOUD + HG_OUTLINE");
  EXPECT_EQ(rec2["source"], "HG_PLATE_CLOUD + outline core in hg-calibrate");
  // The outline file (docs/outline_file.md): the six drilled holes, in the camera frame.
  EXPECT_EQ(rec0["frame"], "camera");
  std::size_t holes = 0;
  for (const auto& loop : rec0["loops"]) holes += loop["hole"].get<bool>();
  EXPECT_EQ(holes, 6u);
  ASSERT_EQ(run(kBin + "/hg-calibrate eye-to-hand --dry-run --session " + (d / "png").string() + " --report " +
                    (d / "png.json").string(),
                &err),
            0)
      << err;
  ASSERT_EQ(run(kBin + "/hg-calibrate eye-to-hand --dry-run --session " + (d / "bus").string() + " --report " +
                    (d / "bus.json").string(),
                &err),
            0)
      << err;
  const json png = json::parse(std::ifstream(d / "png.json")), bus = json::parse(std::ifstream(d / "bus.json"));
  ASSERT_EQ(bus["per_feature"].size(), png["per_feature"].size());
  const double n = png["per_feature"].size(), rms = png["rms_mm"].get<double>() * 1e-3;
  const double sigma_t = rms / std::sqrt(n), sigma_r = rms / (std::sqrt(n) * hole_spread());
  const Eigen::Isometry3d a = row_major(png["camera_to_base"]), b = row_major(bus["camera_to_base"]);
  EXPECT_LT((a.translation() - b.translation()).norm(), 0.2 * sigma_t) << "sigma_t " << sigma_t;
  EXPECT_LT(hg::calibration::rotation_distance(a.linear(), b.linear()), 0.2 * sigma_r) << "sigma_r " << sigma_r;
  // And against the renderer's truth, the eye-to-hand target.
  const json truth = json::parse(std::ifstream(d / "png" / "truth.json"));
  EXPECT_LT((b.translation() - row_major(truth["camera_to_base"]).translation()).norm(), 0.0005);
}

// Eye-in-hand: the view's flange pose is the pose of the next HG_ROBOT_STATUS after the plate cloud (the sim
// robot at rest where the test put it); no plate cloud on the bus is refused with the reason.
TEST(HgCalibrateBus, EyeInHandCaptureTakesTheRobotPose) {
  const fs::path d = scratch("e2f");
  ASSERT_EQ(run(kBin + "/hg-calibrate simulate --mode eye-in-hand --profile lsr-l --views 1 --session " +
                (d / "png").string()),
            0);
  std::string err;
  EXPECT_EQ(
      run(kBin + "/hg-calibrate capture --from-bus --mode eye-in-hand --timeout 1 --session " + (d / "bus").string(),
          &err),
      1);
  EXPECT_NE(err.find("no HG_PLATE_CLOUD within 1"), std::string::npos) << err;
  // The sim robot at rest where the test put it: the home of its cell file, turned by --sim-home-orientation.
  const std::string cell = hg::test::write_test_cell(
      (d / "robot_cell.yaml").string(), [](hg::cell::Cell& c) { c.home = Eigen::Vector3d(0.52, -0.11, 0.74); });
  auto robot = start({kBin + "/hg-robot-bridge", "--driver", "sim", "--cell", cell, "--sim-home-orientation",
                      "0,0.6,0.8,0", "--state-file", (d / "robot.state").string()},
                     d / "robot.log");
  auto camera = start({kBin + "/hg-camera-bridge", "--source", "files", "--files.path",
                       (d / "png" / "view_000.png").string(), "--trigger", "job"},
                      d / "camera.log");
  ASSERT_EQ(run(kBin +
                    "/hg-calibrate capture --from-bus --trigger --local-outline --mode eye-in-hand --timeout 30 "
                    "--session " +
                    (d / "bus").string(),
                &err),
            0)
      << err;
  const json s = json::parse(std::ifstream(d / "bus" / "session.json"));
  ASSERT_EQ(s["mode"], "eye-in-hand");
  ASSERT_EQ(s["views"].size(), 1u);
  const Eigen::Isometry3d f = row_major(s["views"][0]["flange_to_base"]);
  EXPECT_LT((f.translation() - Eigen::Vector3d(0.52, -0.11, 0.74)).norm(), 1e-12);
  const Eigen::Matrix3d want = Eigen::Quaterniond(0, 0.6, 0.8, 0).toRotationMatrix();
  EXPECT_LT(hg::calibration::rotation_distance(f.linear(), want), 1e-9);
}
