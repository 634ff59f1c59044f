// The committed LCM log of the bridge on three parts (tests/data/camera_bridge_three_parts.lcmlog, recorded
// with tools/record from `hg-camera-bridge --source synthetic --scene three-parts --profile pm806 --parts
// all`), which later replay tests use: every event decodes as a plate_cloud_t with three labelled parts.
#include <gtest/gtest.h>

#include <set>

#include <lcm/lcm-cpp.hpp>

#include "sim/scene/scene.hpp"
#include "hullgrind/plate_cloud_t.hpp"

namespace {

TEST(CameraBridgeLog, ThreePartsLogDecodes) {
  lcm::LogFile log(std::string(HG_TEST_DATA) + "/camera_bridge_three_parts.lcmlog", "r");
  ASSERT_TRUE(log.good());
  int clouds = 0;
  std::int64_t last_seq = -1;
  while (const lcm::LogEvent* ev = log.readNextEvent()) {
    ASSERT_EQ(ev->channel, "HG_PLATE_CLOUD");
    hullgrind::plate_cloud_t m;
    ASSERT_EQ(m.decode(ev->data, 0, ev->datalen), ev->datalen) << "event " << ev->eventnum;
    EXPECT_EQ(m.status, +hullgrind::plate_cloud_t::STATUS_OK);
    EXPECT_EQ(m.num_parts, 3);
    EXPECT_GT(m.n, 100000);
    EXPECT_GT(m.source_frame_seq, last_seq);
    last_seq = m.source_frame_seq;
    std::set<int> labels(m.part.begin(), m.part.end());
    EXPECT_EQ(labels, (std::set<int>{0, 1, 2}));
    // The largest part's thickness: the scene's ring flange.
    EXPECT_NEAR(m.thickness, hg::partgen::make_shape("ring-flange").thickness, 0.0015);
    ++clouds;
  }
  EXPECT_EQ(clouds, 2);
}

}  // namespace
