// hg-camera-bridge on the bus, inside a private network namespace (hg_add_netns_gtest):
//  - the real process with --source synthetic: HG_PLATE_CLOUD decoded, status, labels, scan-line order
//    (recovered independently by projecting every (u, v) back into the image), HG_DEPTH decoded;
//  - job trigger: nothing without a request, one cloud per job id however often its START comes;
//  - --source files with corrupt files: counted as dropped in the heartbeat, skipped, the good ones
//    published (a table-only frame as NO_PART);
//  - device loss and recovery with a fault-injecting DepthSource in this process: heartbeat ERROR with the
//    reason, re-open attempts with back-off, OK again and clouds again when the device is back.
#include <gtest/gtest.h>

#include <algorithm>
#include <atomic>
#include <set>
#include <chrono>
#include <csignal>
#include <filesystem>
#include <fstream>
#include <optional>
#include <sys/wait.h>
#include <thread>
#include <unistd.h>

#include <lcm/lcm-cpp.hpp>
#include <opencv2/imgcodecs.hpp>

#include "camera_bridge/camera_bridge.hpp"
#include "sim/scene/scene.hpp"
#include "camera_bridge/sources.hpp"
#include "hullgrind/depth_frame_t.hpp"
#include "hullgrind/heartbeat_t.hpp"
#include "tests/common/child_process.hpp"
#include "hullgrind/job_request_t.hpp"
#include "hullgrind/plate_cloud_t.hpp"

using namespace std::chrono_literals;
using namespace hg::camera_bridge;
using namespace hg::camera;
using namespace hg::sim;
using Clock = std::chrono::steady_clock;
namespace fs = std::filesystem;

namespace {

const std::string kExe = std::string(HG_BIN_DIR) + "/hg-camera-bridge";

// Clouds are up to a few MB: a kernel receive buffer of the default size drops their fragments.
const char* kBusUrl = "udpm://239.255.76.67:7667?ttl=0&recv_buf_size=4194304";

struct Bus {
  lcm::LCM lcm{kBusUrl};
  std::vector<hullgrind::plate_cloud_t> clouds;
  std::vector<hullgrind::depth_frame_t> depths;
  std::vector<hullgrind::heartbeat_t> beats;
  std::string process = "hg-camera-bridge";
  Bus() {
    lcm.subscribe("HG_PLATE_CLOUD", &Bus::on_cloud, this);
    lcm.subscribe("HG_DEPTH", &Bus::on_depth, this);
    lcm.subscribe("HG_HEARTBEAT", &Bus::on_beat, this);
  }
  void on_cloud(const lcm::ReceiveBuffer*, const std::string&, const hullgrind::plate_cloud_t* m) {
    clouds.push_back(*m);
  }
  void on_depth(const lcm::ReceiveBuffer*, const std::string&, const hullgrind::depth_frame_t* m) {
    depths.push_back(*m);
  }
  void on_beat(const lcm::ReceiveBuffer*, const std::string&, const hullgrind::heartbeat_t* m) {
    if (m->process == process) beats.push_back(*m);
  }
  // Pumps until pred() or the limit (a generous bound for failure only; nothing asserts on timing).
  template <class Pred>
  bool until(Pred pred, std::chrono::milliseconds limit = 30s) {
    const auto end = Clock::now() + limit;
    while (Clock::now() < end) {
      if (pred()) return true;
      lcm.handleTimeout(20);
    }
    return pred();
  }
  void pump(std::chrono::milliseconds d) {
    const auto end = Clock::now() + d;
    while (Clock::now() < end) lcm.handleTimeout(20);
  }
};

// The bridge with these arguments.
struct Process : hg::test::ChildProcess {
  explicit Process(std::vector<std::string> args)
      : ChildProcess([&] {
          args.insert(args.begin(), kExe);
          return args;
        }()) {}
};

// Image position (row, col, not rounded) of each cloud point, recomputed independently: (u, v) -> camera
// frame through the message's plane -> pinhole projection with the profile's intrinsics.
std::vector<std::pair<double, double>> image_positions(const hullgrind::plate_cloud_t& m, const CameraProfile& prof) {
  std::vector<std::pair<double, double>> px;
  for (int i = 0; i < m.n; ++i) {
    double p[3];
    for (int k = 0; k < 3; ++k) p[k] = m.plane_origin[k] + m.u[i] * m.plane_u_axis[k] + m.v[i] * m.plane_v_axis[k];
    px.emplace_back(prof.fy * p[1] / p[2] + prof.cy, prof.fx * p[0] / p[2] + prof.cx);
  }
  return px;
}

// Scan-line order of one part's points, from their recomputed image positions. Each position lies within
// a fraction of a pixel of its source pixel (the point is within 1 mm of the plane it is projected onto),
// so: rows never go back by half a pixel or more, and within a row (consecutive points less than half a
// pixel apart vertically) columns increase. Only the points that project back onto a pixel centre are
// checked: a mixed pixel at the edge kept as steel where the camera sees the side wall is placed straight
// down onto the top (camera_bridge/segment.cpp), off its own ray by up to the wall's height times the
// viewing angle's tangent, so its position says nothing of its source pixel.
void expect_scan_order(const std::vector<std::pair<double, double>>& pos) {
  double max_row = -1e9;
  for (size_t i = 0; i < pos.size(); ++i) {
    ASSERT_GT(pos[i].first, max_row - 0.5) << "row goes back at point " << i;
    max_row = std::max(max_row, pos[i].first);
    if (i > 0 && std::abs(pos[i].first - pos[i - 1].first) < 0.5) {
      ASSERT_GT(pos[i].second, pos[i - 1].second + 0.5) << "column goes back within a row at point " << i;
    }
  }
}

TEST(CameraBridgeProcess, SyntheticCloudsInScanOrder) {
  Bus bus;
  // Clean rendering (no noise): every point then sits within 1 mm of its pixel's depth, so projecting it
  // back lands within half a pixel of its source pixel and the source pixel is recovered exactly.
  Process proc({"--source", "synthetic", "--synthetic.scene", "three-parts", "--synthetic.profile", "pm806", "--parts",
                "all", "--synthetic.noise-scale", "0", "--rate", "5", "--depth-rate", "5", "--log-level", "warn"});
  ASSERT_TRUE(bus.until([&] { return bus.clouds.size() >= 2 && !bus.depths.empty(); })) << "no clouds from the bridge";
  const CameraProfile prof = camera_profile("pm806");
  for (const auto& m : bus.clouds) {
    ASSERT_EQ(m.status, +hullgrind::plate_cloud_t::STATUS_OK) << m.status_text;
    EXPECT_EQ(m.header.frame_id, "camera");
    EXPECT_EQ(m.num_parts, 3);
    ASSERT_GT(m.n, 10000);
    ASSERT_EQ(m.u.size(), size_t(m.n));
    ASSERT_EQ(m.v.size(), size_t(m.n));
    ASSERT_EQ(m.part.size(), size_t(m.n));
    std::set<int> labels(m.part.begin(), m.part.end());
    EXPECT_EQ(labels, (std::set<int>{0, 1, 2}));
    // Thickness of the largest part (the ring flange, 25 mm).
    EXPECT_NEAR(m.thickness, 0.025, 0.0015);
    // Scan order within the largest part (the plane's origin lies on its top face; the other parts are
    // thinner, so their points lie off that plane by a thickness difference and project elsewhere).
    std::vector<int> count(m.num_parts, 0);
    for (auto p : m.part) ++count[p];
    const int largest = int(std::max_element(count.begin(), count.end()) - count.begin());
    const auto all = image_positions(m, prof);
    std::vector<std::pair<double, double>> mine;
    for (int i = 0; i < m.n; ++i)
      if (m.part[i] == largest) mine.push_back(all[i]);
    std::vector<std::pair<double, double>> centred;
    for (const auto& q : mine)
      if (std::abs(q.first - std::round(q.first)) < 0.1 && std::abs(q.second - std::round(q.second)) < 0.1)
        centred.push_back(q);
    EXPECT_GT(centred.size(), 0.9 * mine.size()) << "the check would see too few points";
    ASSERT_NO_FATAL_FAILURE(expect_scan_order(centred));
  }
  EXPECT_LT(bus.clouds[0].source_frame_seq, bus.clouds[1].source_frame_seq);

  // The monitoring image: PNG decodes to the decimated size, intrinsics scaled to it.
  const auto& d = bus.depths.front();
  ASSERT_EQ(d.encoding, +hullgrind::depth_frame_t::ENCODING_PNG16);
  const cv::Mat img =
      cv::imdecode(cv::Mat(1, d.data_size, CV_8UC1, const_cast<std::uint8_t*>(d.data.data())), cv::IMREAD_UNCHANGED);
  ASSERT_EQ(img.type(), CV_16UC1);
  EXPECT_EQ(img.cols, 320);
  EXPECT_EQ(img.rows, 240);
  EXPECT_EQ(d.width, 320);
  EXPECT_NEAR(d.fx, prof.fx / 4, 1e-9);
  EXPECT_NEAR(d.cx, prof.cx / 4, 1e-9);
  // A corner pixel sees the table at about the mounting height.
  EXPECT_NEAR(img.at<std::uint16_t>(0, 0) * d.depth_unit, prof.mount_height, 0.05);
  EXPECT_EQ(proc.stop(), 0);
}

TEST(CameraBridgeProcess, JobTriggerCapturesOncePerJobId) {
  Bus bus;
  Process proc({"--source", "synthetic", "--synthetic.scene", "l-bracket", "--trigger", "job", "--log-level", "warn"});
  // Running (a heartbeat) but publishing no cloud until asked.
  ASSERT_TRUE(bus.until([&] { return bus.beats.size() >= 2; }));
  EXPECT_TRUE(bus.clouds.empty());
  auto request = [&](std::int8_t action, const std::string& id) {
    hullgrind::job_request_t j{};
    j.job_id = id;
    j.part_id = "test";
    j.action = action;
    bus.lcm.publish("HG_JOB_REQUEST", &j);
  };
  request(hullgrind::job_request_t::ACTION_START, "job-1");
  ASSERT_TRUE(bus.until([&] { return bus.clouds.size() >= 1; }));
  EXPECT_EQ(bus.clouds[0].status, +hullgrind::plate_cloud_t::STATUS_OK) << bus.clouds[0].status_text;
  request(hullgrind::job_request_t::ACTION_ABORT, "job-1");
  bus.pump(1500ms);
  EXPECT_EQ(bus.clouds.size(), 1u) << "ABORT must not capture";
  // A retrying writer repeats START with the same job id: one capture per job id.
  for (int i = 0; i < 5; ++i) request(hullgrind::job_request_t::ACTION_START, "job-1");
  bus.pump(1500ms);
  EXPECT_EQ(bus.clouds.size(), 1u) << "a repeated START of job-1 captured again";
  for (int i = 0; i < 5; ++i) request(hullgrind::job_request_t::ACTION_START, "job-2");
  ASSERT_TRUE(bus.until([&] { return bus.clouds.size() >= 2; }));
  bus.pump(1500ms);
  EXPECT_EQ(bus.clouds.size(), 2u);
  EXPECT_EQ(proc.stop(), 0);
}

TEST(CameraBridgeProcess, CorruptFilesAreCountedAndSkipped) {
  const fs::path dir = fs::temp_directory_path() / ("hg_cam_files_" + std::to_string(getpid()));
  fs::create_directories(dir);
  const CameraProfile prof = camera_profile("pm806");
  const RenderedFrame good = render(scene_preset("plate-hole-slot"), prof, 0);
  const RenderedFrame empty = render(scene_preset("empty"), prof, 0);
  write_intrinsics(good.intrinsics, (dir / "intrinsics.yaml").string());
  ASSERT_TRUE(cv::imwrite((dir / "a_good.png").string(), good.depth));
  ASSERT_TRUE(cv::imwrite((dir / "b_zero.png").string(), cv::Mat::zeros(good.depth.size(), CV_16UC1)));
  ASSERT_TRUE(cv::imwrite((dir / "c_small.png").string(), good.depth(cv::Rect(0, 0, 640, 480))));
  std::ofstream(dir / "d_garbage.png") << "this is not a PNG";
  ASSERT_TRUE(cv::imwrite((dir / "e_eight_bit.png").string(), cv::Mat(good.depth.size(), CV_8UC1, cv::Scalar(7))));
  ASSERT_TRUE(cv::imwrite((dir / "f_table_only.png").string(), empty.depth));

  Bus bus;
  Process proc({"--source", "files", "--files.path", dir.string(), "--rate", "0", "--log-level", "error"});
  ASSERT_TRUE(bus.until([&] { return bus.clouds.size() >= 2 && !bus.beats.empty() && bus.beats.back().dropped >= 4; }))
      << "clouds " << bus.clouds.size() << ", beats " << bus.beats.size();
  bus.pump(1200ms);  // nothing more comes: the files are used up and --loop is off
  ASSERT_EQ(bus.clouds.size(), 2u);
  EXPECT_EQ(bus.clouds[0].status, +hullgrind::plate_cloud_t::STATUS_OK) << bus.clouds[0].status_text;
  EXPECT_EQ(bus.clouds[0].num_parts, 1);
  EXPECT_EQ(bus.clouds[1].status, +hullgrind::plate_cloud_t::STATUS_NO_PART);
  EXPECT_EQ(bus.clouds[1].n, 0);
  EXPECT_FALSE(bus.clouds[1].status_text.empty());
  EXPECT_EQ(bus.beats.back().dropped, 4);
  EXPECT_NE(bus.beats.back().state, +hullgrind::heartbeat_t::STATE_ERROR);
  EXPECT_EQ(proc.stop(), 0);
  fs::remove_all(dir);
}

TEST(CameraBridgeProcess, MissingInputIsAnErrorStateNotACrash) {
  Bus bus;
  Process proc({"--source", "files", "--files.path", "/nonexistent/hg-depth", "--retry-min", "0.2", "--retry-max",
                "0.4", "--log-level", "error"});
  ASSERT_TRUE(
      bus.until([&] { return !bus.beats.empty() && bus.beats.back().state == hullgrind::heartbeat_t::STATE_ERROR; }));
  EXPECT_NE(bus.beats.back().state_text.find("/nonexistent/hg-depth"), std::string::npos)
      << bus.beats.back().state_text;
  EXPECT_EQ(proc.stop(), 0);  // still alive, stops cleanly
}

// ---- device loss and recovery, in this process ----

// A synthetic camera that can be unplugged: open() and grab() fail while it is away.
class UnpluggableSource : public DepthSource {
 public:
  UnpluggableSource() : inner_(scene_preset("plate-hole-slot"), camera_profile("pm806"), 5.0) {}
  std::atomic<bool> present{true};
  std::atomic<int> opens{0}, failed_opens{0};
  std::string describe() const override { return "unpluggable test camera"; }
  void open() override {
    ++opens;
    if (!present) {
      ++failed_opens;
      throw SourceError("no device on the bus");
    }
    inner_.open();
  }
  bool is_open() const override { return inner_.is_open(); }
  std::optional<DepthFrame> grab(std::chrono::milliseconds timeout) override {
    if (!present) throw SourceError("device unplugged");
    return inner_.grab(timeout);
  }
  void close() override { inner_.close(); }

 private:
  SyntheticSource inner_;
};

TEST(CameraBridgeProcess, DeviceLossAndRecovery) {
  std::vector<std::string> args{"hg-camera-bridge-test", "--retry-min", "0.2", "--retry-max", "0.8",
                                "--log-level",           "error"};
  std::vector<char*> argv;
  for (auto& a : args) argv.push_back(a.data());
  hg::runtime::ProcessInfo info = process_info();
  info.name = "hg-camera-bridge-test";
  hg::runtime::Node node(info, int(argv.size()), argv.data());
  auto src = std::make_unique<UnpluggableSource>();
  UnpluggableSource* dev = src.get();
  BridgeOptions opt = options_from(node);
  opt.rate = 5;
  Bridge bridge(node, std::move(src), opt);
  bridge.start();
  std::thread loop([&] { node.run(); });

  Bus bus;
  bus.process = "hg-camera-bridge-test";
  auto state_is = [&](std::int8_t s) { return !bus.beats.empty() && bus.beats.back().state == s; };
  ASSERT_TRUE(bus.until([&] { return bus.clouds.size() >= 1 && state_is(hullgrind::heartbeat_t::STATE_OK); }));

  dev->present = false;
  ASSERT_TRUE(bus.until([&] { return state_is(hullgrind::heartbeat_t::STATE_ERROR); }));
  const std::string why = bus.beats.back().state_text;
  EXPECT_TRUE(why.find("unplugged") != std::string::npos || why.find("no device") != std::string::npos) << why;
  // Re-open attempts keep coming (back-off capped at 0.8 s), each failing while the device is away.
  ASSERT_TRUE(bus.until([&] { return dev->failed_opens >= 3; }));
  const size_t clouds_while_away = bus.clouds.size();
  bus.pump(500ms);
  EXPECT_EQ(bus.clouds.size(), clouds_while_away);

  dev->present = true;
  ASSERT_TRUE(bus.until(
      [&] { return state_is(hullgrind::heartbeat_t::STATE_OK) && bus.clouds.size() >= clouds_while_away + 2; }));
  EXPECT_EQ(bus.clouds.back().status, +hullgrind::plate_cloud_t::STATUS_OK);

  node.stop();
  loop.join();
  bridge.stop();
}

}  // namespace
