// The scan-quality verdict end to end (issue 23 §2), inside tests/netns.sh: a rendered frame with an outer
// edge in shadow, through the camera bridge's segmentation onto HG_PLATE_CLOUD; hg-outline-service judges
// it against its --cell (outline.max-edge-gap) and hg-path-planner ends the job NEEDS_RESCAN with the
// reason, and plans nothing. The same frame without the shadow gives an outline of quality OK.
#include <gtest/gtest.h>

#include <algorithm>
#include <chrono>
#include <filesystem>
#include <unistd.h>

#include <lcm/lcm-cpp.hpp>

#include "hullgrind/grind_path_t.hpp"
#include "hullgrind/heartbeat_t.hpp"
#include "hullgrind/job_request_t.hpp"
#include "hullgrind/job_status_t.hpp"
#include "runtime/node.hpp"
#include "scan_frames.hpp"
#include "tests/common/cell_file.hpp"
#include "tests/common/child_process.hpp"

using namespace std::chrono_literals;
using Clock = std::chrono::steady_clock;

namespace {

struct Bus {
  std::vector<hullgrind::outline_t> outlines;
  std::vector<hullgrind::job_status_t> statuses;
  std::vector<std::string> beating;
  int paths = 0;
  void on_outline(const lcm::ReceiveBuffer*, const std::string&, const hullgrind::outline_t* m) {
    outlines.push_back(*m);
  }
  void on_status(const lcm::ReceiveBuffer*, const std::string&, const hullgrind::job_status_t* m) {
    statuses.push_back(*m);
  }
  void on_beat(const lcm::ReceiveBuffer*, const std::string&, const hullgrind::heartbeat_t* m) {
    beating.push_back(m->process);
  }
  void on_path(const lcm::ReceiveBuffer*, const std::string&, const hullgrind::grind_path_t*) { ++paths; }
};

// The plate-hole-slot part under the pm806 camera; with `shadow`, 60 % of its longest edge in shadow.
hullgrind::plate_cloud_t cloud_of(bool shadow, int seq) {
  const hg::test::Pose pose{0.03, -0.02, 0.15};
  hg::sim::RenderedFrame f = hg::test::rendered_frame("plate-hole-slot", "pm806", pose, 21);
  if (shadow) {
    const hg::test::Edge e = hg::test::longest_outer_edge(f.part_polygons.at(0));
    const double len = (e.b - e.a).norm();
    hg::test::shadow_beside(f, hg::test::unmixed_frame("plate-hole-slot", "pm806", pose, 21), e, 0.2 * len, 0.6 * len,
                            0.005);
  }
  hullgrind::plate_cloud_t c{};
  c.header.frame_id = "camera";
  c.header.seq = seq;
  hg::camera_bridge::fill_plate_cloud(hg::camera_bridge::segment(f.depth, f.intrinsics, {}), c);
  return c;
}

class Rescan : public testing::Test {
 protected:
  void SetUp() override {
    ASSERT_TRUE(lcm.good()) << "no LCM: the test must run inside tests/netns.sh";
    lcm.subscribe("HG_OUTLINE", &Bus::on_outline, &bus);
    lcm.subscribe("HG_JOB_STATUS", &Bus::on_status, &bus);
    lcm.subscribe("HG_HEARTBEAT", &Bus::on_beat, &bus);
    lcm.subscribe("HG_GRIND_PATH", &Bus::on_path, &bus);
    cell = hg::test::write_test_cell(
        (std::filesystem::temp_directory_path() / ("rescan-cell-" + std::to_string(getpid()) + ".yaml")).string(),
        [](hg::cell::Cell& c) { c.outline.max_edge_gap = 0.1; });
    const std::string bin = HG_BIN_DIR;
    service = hg::test::ChildProcess({bin + "/hg-outline-service", "--cell", cell, "--log-level", "warn"});
    planner = hg::test::ChildProcess(
        {bin + "/hg-path-planner", "--cell", cell, "--outline-max-age", "30", "--log-level", "warn"});
    ASSERT_TRUE(wait_for([&] { return beats("hg-outline-service") && beats("hg-path-planner"); }, 10s));
  }
  void TearDown() override {
    EXPECT_EQ(service.stop(), 0);
    EXPECT_EQ(planner.stop(), 0);
    std::filesystem::remove(cell);
  }
  bool beats(const std::string& who) { return std::count(bus.beating.begin(), bus.beating.end(), who) > 0; }
  template <class Pred>
  bool wait_for(Pred pred, std::chrono::milliseconds limit) {
    const auto end = Clock::now() + limit;
    while (Clock::now() < end) {
      if (pred()) return true;
      lcm.handleTimeout(20);
    }
    return pred();
  }
  lcm::LCM lcm{hg::runtime::default_lcm_url()};
  Bus bus;
  std::string cell;
  hg::test::ChildProcess service, planner;
};

TEST_F(Rescan, AnEdgeInShadowEndsTheJobNeedsRescanWithTheReason) {
  const hullgrind::plate_cloud_t clean = cloud_of(false, 1);
  lcm.publish("HG_PLATE_CLOUD", &clean);
  ASSERT_TRUE(wait_for([&] { return !bus.outlines.empty(); }, 20s));
  EXPECT_EQ(bus.outlines.back().quality, +hullgrind::outline_t::QUALITY_OK) << bus.outlines.back().quality_text;

  const hullgrind::plate_cloud_t shadowed = cloud_of(true, 2);
  ASSERT_GT(shadowed.largest_edge_gap, 0.1);
  lcm.publish("HG_PLATE_CLOUD", &shadowed);
  ASSERT_TRUE(wait_for([&] { return bus.outlines.size() >= 2; }, 20s));
  const hullgrind::outline_t& o = bus.outlines.back();
  EXPECT_EQ(o.quality, +hullgrind::outline_t::QUALITY_POOR);
  EXPECT_NE(o.quality_text.find("along the edge (" + cell + " outline.max-edge-gap 0.1 m)"), std::string::npos)
      << o.quality_text;

  hullgrind::job_request_t r{};
  r.job_id = "job-shadow";
  r.part_id = "plate";
  r.action = +hullgrind::job_request_t::ACTION_START;
  lcm.publish("HG_JOB_REQUEST", &r);
  auto ended = [&]() -> const hullgrind::job_status_t* {
    for (const auto& s : bus.statuses)
      if (s.job_id == "job-shadow" && s.state == +hullgrind::job_status_t::STATE_NEEDS_RESCAN) return &s;
    return nullptr;
  };
  ASSERT_TRUE(wait_for([&] { return ended() != nullptr; }, 10s)) << "no NEEDS_RESCAN";
  const std::string& why = ended()->message;
  EXPECT_NE(why.find("scan quality poor, rescan: a gap of"), std::string::npos) << why;
  EXPECT_NE(why.find("outline.max-edge-gap 0.1 m"), std::string::npos) << why;
  lcm.handleTimeout(300);
  EXPECT_EQ(bus.paths, 0) << "no path on a guessed edge";
}

}  // namespace
