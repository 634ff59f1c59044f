// The files source: intrinsics files, PNG directories, and .pcd/.ply clouds projected back to depth.
#include <gtest/gtest.h>

#include <cstdio>
#include <filesystem>
#include <fstream>

#include <opencv2/imgcodecs.hpp>

#include "sim/scene/scene.hpp"
#include "camera_bridge/segment.hpp"
#include "camera_bridge/sources.hpp"

using namespace hg::camera_bridge;
using namespace hg::camera;
using namespace hg::sim;
namespace fs = std::filesystem;

namespace {

struct TempDir {
  fs::path path;
  TempDir()
      : path(fs::temp_directory_path() / ("hg_cam_src_" + std::to_string(getpid()) + "_" +
                                          ::testing::UnitTest::GetInstance()->current_test_info()->name())) {
    fs::create_directories(path);
  }
  ~TempDir() { fs::remove_all(path); }
  std::string operator/(const std::string& f) const { return (path / f).string(); }
};

TEST(CameraBridgeSources, IntrinsicsRoundTripAndErrors) {
  TempDir d;
  const Intrinsics in = camera_profile("lsr-l").intrinsics();
  write_intrinsics(in, d / "i.yaml");
  const Intrinsics back = read_intrinsics(d / "i.yaml");
  EXPECT_EQ(back.width, 2048);
  EXPECT_EQ(back.height, 1536);
  EXPECT_DOUBLE_EQ(back.fx, in.fx);
  EXPECT_DOUBLE_EQ(back.cy, in.cy);
  EXPECT_DOUBLE_EQ(back.depth_unit, 0.0001);

  std::ofstream(d / "missing.yaml") << "%YAML:1.0\nwidth: 640\nheight: 480\nfx: 500\nfy: 500\ncx: 320\n";
  try {
    read_intrinsics(d / "missing.yaml");
    FAIL() << "no error for a missing key";
  } catch (const SourceError& e) {
    EXPECT_NE(std::string(e.what()).find("'cy' missing"), std::string::npos) << e.what();
    EXPECT_NE(std::string(e.what()).find("missing.yaml"), std::string::npos) << e.what();
  }
  std::ofstream(d / "bad.yaml") << "%YAML:1.0\nwidth: 640\nheight: -3\nfx: 500\nfy: 500\ncx: 320\ncy: 240\n";
  EXPECT_THROW(read_intrinsics(d / "bad.yaml"), SourceError);
  EXPECT_THROW(read_intrinsics(d / "nope.yaml"), SourceError);
}

TEST(CameraBridgeSources, PngDirectoryInNameOrderThenEnd) {
  TempDir d;
  const CameraProfile prof = camera_profile("pm806");
  write_intrinsics(prof.intrinsics(), d / "intrinsics.yaml");
  const RenderedFrame f0 = render(scene_preset("l-bracket"), prof, 0), f1 = render(scene_preset("l-bracket"), prof, 1);
  ASSERT_TRUE(cv::imwrite(d / "depth_000001.png", f1.depth));
  ASSERT_TRUE(cv::imwrite(d / "depth_000000.png", f0.depth));
  FilesSource src(d.path.string(), "", 0, false);
  src.open();
  ASSERT_EQ(src.files().size(), 2u);
  auto a = src.grab(std::chrono::milliseconds(100));
  auto b = src.grab(std::chrono::milliseconds(100));
  ASSERT_TRUE(a && b);
  EXPECT_EQ(cv::countNonZero(a->depth != f0.depth), 0);
  EXPECT_EQ(cv::countNonZero(b->depth != f1.depth), 0);
  EXPECT_EQ(a->intrinsics.width, 1280);
  EXPECT_FALSE(src.grab(std::chrono::milliseconds(10)).has_value());
  EXPECT_TRUE(src.finished());

  FilesSource looping(d.path.string(), "", 0, true);
  looping.open();
  for (int i = 0; i < 5; ++i) EXPECT_TRUE(looping.grab(std::chrono::milliseconds(100)).has_value());

  FilesSource none((d.path / "empty-subdir").string(), d / "intrinsics.yaml", 0, false);
  EXPECT_THROW(none.open(), SourceError);
}

TEST(CameraBridgeSources, CloudFileBecomesTheSameDepthImage) {
  if (!can_read_clouds()) FAIL() << "this build cannot read .pcd/.ply (hg_outline_io missing)";
  TempDir d;
  const CameraProfile prof = camera_profile("pm806");
  const RenderedFrame f = render(scene_preset("ring-flange"), prof, 2);
  write_intrinsics(f.intrinsics, d / "intrinsics.yaml");
  // Every valid pixel as a camera-frame point, in an ASCII PCD written here by hand.
  std::vector<std::string> lines;
  for (int r = 0; r < f.depth.rows; ++r)
    for (int c = 0; c < f.depth.cols; ++c)
      if (const auto z = f.depth.at<std::uint16_t>(r, c)) {
        const Eigen::Vector3d p = deproject(f.intrinsics, c, r, z * prof.depth_unit);
        char buf[96];
        std::snprintf(buf, sizeof buf, "%.9g %.9g %.9g", p.x(), p.y(), p.z());
        lines.emplace_back(buf);
      }
  {
    std::ofstream o(d / "cloud.pcd");
    o << "# .PCD v0.7\nVERSION 0.7\nFIELDS x y z\nSIZE 4 4 4\nTYPE F F F\nCOUNT 1 1 1\nWIDTH " << lines.size()
      << "\nHEIGHT 1\nVIEWPOINT 0 0 0 1 0 0 0\nPOINTS " << lines.size() << "\nDATA ascii\n";
    for (const auto& l : lines) o << l << "\n";
  }
  FilesSource src(d / "cloud.pcd", "", 0, false);
  src.open();
  auto fr = src.grab(std::chrono::milliseconds(100));
  ASSERT_TRUE(fr.has_value());
  ASSERT_EQ(fr->depth.type(), CV_16UC1);
  ASSERT_EQ(fr->depth.size(), f.depth.size());
  const int differ = cv::countNonZero(fr->depth != f.depth);
  EXPECT_LE(differ, f.depth.total() / 1000) << differ << " pixels differ";
  // And it segments like the original.
  SegmentParams p;
  const Segmentation s = segment(fr->depth, fr->intrinsics, p);
  ASSERT_EQ(s.status, SegmentStatus::Ok) << s.text;
  const cv::Mat truth = f.truth_mask();
  const double inter = cv::countNonZero((s.labels > 0) & truth), uni = cv::countNonZero((s.labels > 0) | truth);
  EXPECT_GE(inter / uni, 0.98);
}

TEST(CameraBridgeSources, SyntheticSourceCountsFrames) {
  SyntheticSource s(scene_preset("empty"), camera_profile("pm806"), 0);
  EXPECT_THROW(s.grab(std::chrono::milliseconds(10)), SourceError);  // not open
  s.open();
  auto a = s.grab(std::chrono::milliseconds(10)), b = s.grab(std::chrono::milliseconds(10));
  ASSERT_TRUE(a && b);
  EXPECT_EQ(a->seq, 0);
  EXPECT_EQ(b->seq, 1);
  EXPECT_EQ(cv::countNonZero(a->depth != render(scene_preset("empty"), camera_profile("pm806"), 0).depth), 0);
}

}  // namespace
