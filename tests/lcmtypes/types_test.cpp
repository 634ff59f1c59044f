// Encode/decode round trip of every hullgrind type: decoded fields equal the ones set, re-encoding gives
// the same bytes, and truncated or foreign buffers are refused.
#include <gtest/gtest.h>

#include <cmath>
#include <vector>

#include "hullgrind/depth_frame_t.hpp"
#include "hullgrind/grind_path_t.hpp"
#include "hullgrind/heartbeat_t.hpp"
#include "hullgrind/job_request_t.hpp"
#include "hullgrind/job_status_t.hpp"
#include "hullgrind/outline_t.hpp"
#include "hullgrind/part_pose_t.hpp"
#include "hullgrind/plate_cloud_t.hpp"
#include "hullgrind/robot_status_t.hpp"

namespace {

template <class T>
std::vector<uint8_t> encode(const T& m) {
  std::vector<uint8_t> buf(m.getEncodedSize());
  EXPECT_EQ(m.encode(buf.data(), 0, int(buf.size())), int(buf.size()));
  return buf;
}

template <class T>
T round_trip(const T& m) {
  std::vector<uint8_t> buf = encode(m);
  T out;
  EXPECT_EQ(out.decode(buf.data(), 0, int(buf.size())), int(buf.size()));
  EXPECT_EQ(encode(out), buf) << "re-encoding differs";
  // Every strict prefix must be refused, never read past the end.
  for (std::size_t cut : {std::size_t(0), std::size_t(7), buf.size() / 2, buf.size() - 1}) {
    T partial;
    EXPECT_LT(partial.decode(buf.data(), 0, int(cut)), 0) << "accepted a buffer cut at " << cut;
  }
  return out;
}

hullgrind::header_t header(int64_t seq, const char* frame) {
  hullgrind::header_t h;
  h.seq = seq;
  h.utime = 1'700'000'000'000'000 + seq;
  h.frame_id = frame;
  return h;
}

TEST(LcmTypes, DepthFrame) {
  hullgrind::depth_frame_t m;
  m.header = header(3, "camera");
  m.width = 4;
  m.height = 2;
  m.fx = 1000.5, m.fy = 1001.5, m.cx = 2.25, m.cy = 0.75, m.depth_unit = 0.001;
  m.encoding = hullgrind::depth_frame_t::ENCODING_RAW16;
  m.data = {1, 2, 3, 4, 5, 6, 7, 8, 9, 10, 11, 12, 13, 14, 15, 16};
  m.data_size = int32_t(m.data.size());
  auto o = round_trip(m);
  EXPECT_EQ(o.header.seq, 3);
  EXPECT_EQ(o.header.frame_id, "camera");
  EXPECT_EQ(o.width, 4);
  EXPECT_EQ(o.fx, 1000.5);
  EXPECT_EQ(o.data, m.data);
}

TEST(LcmTypes, PlateCloud) {
  hullgrind::plate_cloud_t m;
  m.header = header(9, "camera");
  m.source_frame_seq = 8;
  m.status = hullgrind::plate_cloud_t::STATUS_OK;
  m.status_text = "";
  for (int i = 0; i < 3; ++i) {
    m.plane_origin[i] = 0.1 * i;
    m.plane_normal[i] = i == 2 ? -1 : 0;
    m.plane_u_axis[i] = i == 0;
    m.plane_v_axis[i] = i == 1;
  }
  m.thickness = 0.012;
  m.n = 5;
  for (int i = 0; i < m.n; ++i) {
    m.u.push_back(0.5f * i);
    m.v.push_back(-0.25f * i);
    m.part.push_back(int16_t(i % 2));
  }
  m.num_parts = 2;
  auto o = round_trip(m);
  EXPECT_EQ(o.n, 5);
  EXPECT_EQ(o.u, m.u);
  EXPECT_EQ(o.v, m.v);
  EXPECT_EQ(o.part, m.part);
  EXPECT_EQ(o.plane_normal[2], -1);
  EXPECT_EQ(o.thickness, 0.012);
}

TEST(LcmTypes, OutlineWithLoops) {
  hullgrind::outline_t m;
  m.header = header(1, "camera");
  m.cloud_seq = 9;
  for (int i = 0; i < 3; ++i) m.plane_origin[i] = m.plane_normal[i] = m.plane_u_axis[i] = m.plane_v_axis[i] = i;
  m.thickness = 0.01;
  m.status = hullgrind::outline_t::STATUS_OK;
  m.alpha_radius = 0.004;
  for (int k = 0; k < 2; ++k) {
    hullgrind::outline_loop_t l;
    l.hole = k == 1;
    l.n = 3 + k;
    for (int i = 0; i < l.n; ++i) {
      l.u.push_back(i * 0.1);
      l.v.push_back(k + i * 0.2);
    }
    l.area = 1.5 + k;
    l.perimeter = 4.5 + k;
    m.loops.push_back(l);
  }
  m.num_loops = 2;
  m.points_read = 1300;
  m.points_used = 1234;
  m.duplicates_merged = 66;
  m.mode = "dshi";
  m.order = "hilbert";
  m.time_triangulate = 0.01, m.time_alpha = 0.002, m.time_loops = 0.001;
  m.triangles = 2400;
  m.search_cost = 5'000'000'000LL;
  m.compute_time = 0.02;
  auto o = round_trip(m);
  ASSERT_EQ(o.num_loops, 2);
  EXPECT_FALSE(o.loops[0].hole);
  EXPECT_TRUE(o.loops[1].hole);
  EXPECT_EQ(o.loops[1].n, 4);
  EXPECT_EQ(o.loops[1].v, m.loops[1].v);
  EXPECT_EQ(o.search_cost, 5'000'000'000LL);
  EXPECT_EQ(o.points_read, 1300);
  EXPECT_EQ(o.duplicates_merged, 66);
  EXPECT_EQ(o.order, "hilbert");
  EXPECT_EQ(o.time_alpha, 0.002);
}

TEST(LcmTypes, PartPose) {
  hullgrind::part_pose_t m;
  m.header = header(2, "camera");
  m.cloud_seq = 4;
  m.centroid_uv[0] = 0.3, m.centroid_uv[1] = 0.2;
  for (int i = 0; i < 3; ++i) m.centroid_xyz[i] = i + 0.5;
  m.principal_axis_angle = 0.7;
  m.area = 0.25;
  m.bbox_min_uv[0] = -1, m.bbox_min_uv[1] = -2, m.bbox_max_uv[0] = 1, m.bbox_max_uv[1] = 2;
  m.obb_size[0] = 4, m.obb_size[1] = 2;
  auto o = round_trip(m);
  EXPECT_EQ(o.principal_axis_angle, 0.7);
  EXPECT_EQ(o.centroid_xyz[2], 2.5);
  EXPECT_EQ(o.bbox_max_uv[1], 2);
}

TEST(LcmTypes, GrindPath) {
  hullgrind::grind_path_t m{};  // every count zero: what is not set below encodes as an empty list
  m.header = header(5, "robot_base");
  m.job_id = "job-42";
  m.outline_seq = 1;
  m.frame = "robot_base";
  m.n = 3;
  for (int i = 0; i < m.n; ++i) {
    m.position.push_back({0.1 * i, 0.2, 0.3});
    m.orientation.push_back({1, 0, 0, 0});
    m.speed.push_back(0.05);
    m.kind.push_back(int8_t(i));
    m.loop_index.push_back(int16_t(i - 1));
  }
  m.tool_radius = 0.025;
  m.tilt = 0.785;
  m.flipped = true;
  m.revision = 2;
  hullgrind::loop_coverage_t c{};
  c.loop_index = 2, c.hole = true, c.planned = false, c.edge_length = 0.3007, c.reached_length = 0;
  c.reason = "hole too small for the tool";
  m.coverage.push_back(c);
  m.num_loops = 1;
  hullgrind::edge_stretch_t u{};
  u.loop_index = 2, u.hole = true, u.start = 0, u.length = 0.3007, u.cause = hullgrind::edge_stretch_t::CAUSE_TOO_SMALL;
  m.unreached.push_back(u);
  m.num_unreached = 1;
  auto o = round_trip(m);
  EXPECT_EQ(o.revision, 2);
  ASSERT_EQ(o.coverage.size(), 1u);
  EXPECT_EQ(o.coverage[0].reason, c.reason);
  EXPECT_FALSE(o.coverage[0].planned);
  ASSERT_EQ(o.unreached.size(), 1u);
  EXPECT_EQ(o.unreached[0].cause, +hullgrind::edge_stretch_t::CAUSE_TOO_SMALL);
  EXPECT_EQ(o.unreached[0].length, 0.3007);
  EXPECT_EQ(o.job_id, "job-42");
  EXPECT_EQ(o.position[2][0], m.position[2][0]);
  EXPECT_EQ(o.kind[2], +hullgrind::grind_path_t::KIND_GRIND);
  EXPECT_EQ(o.loop_index[0], -1);
  EXPECT_TRUE(o.flipped);
}

TEST(LcmTypes, JobRequestAndStatus) {
  hullgrind::job_request_t r{};
  r.header = header(0, "");
  r.job_id = "j1";
  r.part_id = "bracket";
  r.action = hullgrind::job_request_t::ACTION_START;
  r.tool_radius = 0.02, r.tilt = 0.5, r.grind_speed = 0.03, r.travel_speed = 0.2, r.step = 0.002;
  r.safe_height = 0.05;
  r.direction = hullgrind::job_request_t::DIRECTION_CONVENTIONAL;
  r.flipped = false;
  r.actor = "operator anna";
  r.excluded_loops = {3, 5};
  r.num_excluded = 2;
  auto ro = round_trip(r);
  EXPECT_EQ(ro.excluded_loops, (std::vector<int16_t>{3, 5}));
  EXPECT_EQ(ro.actor, "operator anna");
  EXPECT_EQ(ro.part_id, "bracket");
  EXPECT_EQ(ro.direction, +hullgrind::job_request_t::DIRECTION_CONVENTIONAL);
  EXPECT_EQ(ro.step, 0.002);

  hullgrind::job_status_t s{};
  s.header = header(1, "");
  s.job_id = "j1";
  s.part_id = "bracket";
  s.source = "hg-path-planner";
  s.state = hullgrind::job_status_t::STATE_FAILED;
  s.progress = 0.5;
  s.message = "waypoint 12 outside the workspace";
  auto so = round_trip(s);
  EXPECT_EQ(so.state, +hullgrind::job_status_t::STATE_FAILED);
  EXPECT_EQ(so.message, s.message);
}

TEST(LcmTypes, RobotStatusAndHeartbeat) {
  hullgrind::robot_status_t r;
  r.header = header(7, "robot_base");
  r.mode = hullgrind::robot_status_t::MODE_FAULT;
  for (int i = 0; i < 3; ++i) r.tcp_position[i] = i * 0.1;
  for (int i = 0; i < 4; ++i) r.tcp_orientation[i] = i == 0;
  r.job_id = "j1";
  r.path_index = 17;
  r.fault_code = hullgrind::robot_status_t::FAULT_PROTECTIVE_STOP;
  r.fault_text = "protective stop";
  auto ro = round_trip(r);
  EXPECT_EQ(ro.fault_code, +hullgrind::robot_status_t::FAULT_PROTECTIVE_STOP);
  EXPECT_EQ(ro.path_index, 17);

  hullgrind::heartbeat_t h;
  h.header = header(11, "");
  h.process = "hg-outline-service";
  h.pid = 1234;
  h.state = hullgrind::heartbeat_t::STATE_DEGRADED;
  h.state_text = "camera lost";
  h.uptime = 12.5;
  h.received = 10, h.published = 9, h.dropped = 1, h.decode_errors = 2;
  h.last_latency = 0.015;
  auto ho = round_trip(h);
  EXPECT_EQ(ho.process, "hg-outline-service");
  EXPECT_EQ(ho.decode_errors, 2);
  EXPECT_EQ(ho.last_latency, 0.015);
}

TEST(LcmTypes, ForeignFingerprintIsRefused) {
  hullgrind::heartbeat_t h{};
  h.process = "x";
  std::vector<uint8_t> buf = encode(h);
  hullgrind::job_request_t other;
  EXPECT_LT(other.decode(buf.data(), 0, int(buf.size())), 0);
  buf[0] ^= 0x5a;  // corrupt the fingerprint itself
  hullgrind::heartbeat_t same;
  EXPECT_LT(same.decode(buf.data(), 0, int(buf.size())), 0);
}

}  // namespace
