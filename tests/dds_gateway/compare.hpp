// Field-by-field equality of an LCM message and the DDS sample the gateway made of it, written from the
// two type definitions (lcmtypes/*.lcm, dds_gateway/idl/hullgrind.idl), not from the gateway's code.
#pragma once

#include <gtest/gtest.h>

#include <string>

#include "helpers.hpp"
#include "hullgrind.h"
#include "hullgrind/grind_path_t.hpp"
#include "hullgrind/heartbeat_t.hpp"
#include "hullgrind/job_status_t.hpp"
#include "hullgrind/outline_t.hpp"
#include "hullgrind/part_pose_t.hpp"
#include "hullgrind/robot_status_t.hpp"

namespace hgtest {

inline void expect_header(const hullgrind::header_t& m, const hgdds_Header& d) {
  EXPECT_EQ(m.seq, d.seq);
  EXPECT_EQ(m.utime, d.utime);
  EXPECT_EQ(m.frame_id, str(d.frame_id));
}

template <std::size_t N>
void expect_array(const double (&m)[N], const double (&d)[N], const char* what) {
  for (std::size_t i = 0; i < N; ++i) EXPECT_EQ(m[i], d[i]) << what << "[" << i << "]";
}

template <class V, class S>
void expect_seq(const V& m, const S& d, const char* what) {
  ASSERT_EQ(m.size(), d._length) << what;
  for (std::size_t i = 0; i < m.size(); ++i) EXPECT_EQ(m[i], d._buffer[i]) << what << "[" << i << "]";
}

inline void expect_same(const hullgrind::outline_t& m, const hgdds_Outline& d) {
  SCOPED_TRACE("outline seq " + std::to_string(m.header.seq));
  expect_header(m.header, d.header);
  EXPECT_EQ(m.cloud_seq, d.cloud_seq);
  expect_array(m.plane_origin, d.plane_origin, "plane_origin");
  expect_array(m.plane_normal, d.plane_normal, "plane_normal");
  expect_array(m.plane_u_axis, d.plane_u_axis, "plane_u_axis");
  expect_array(m.plane_v_axis, d.plane_v_axis, "plane_v_axis");
  EXPECT_EQ(m.thickness, d.thickness);
  EXPECT_EQ(m.status, d.status);
  EXPECT_EQ(m.error_text, str(d.error_text));
  EXPECT_EQ(m.alpha_radius, d.alpha_radius);
  ASSERT_EQ(std::size_t(m.num_loops), d.loops._length);
  for (int i = 0; i < m.num_loops; ++i) {
    const auto& ml = m.loops[i];
    const auto& dl = d.loops._buffer[i];
    EXPECT_EQ(ml.hole, dl.hole);
    ASSERT_EQ(std::size_t(ml.n), ml.u.size());
    expect_seq(ml.u, dl.u, "u");
    expect_seq(ml.v, dl.v, "v");
    EXPECT_EQ(ml.area, dl.area);
    EXPECT_EQ(ml.perimeter, dl.perimeter);
  }
  EXPECT_EQ(m.points_read, d.points_read);
  EXPECT_EQ(m.points_used, d.points_used);
  EXPECT_EQ(m.duplicates_merged, d.duplicates_merged);
  EXPECT_EQ(m.mode, str(d.mode));
  EXPECT_EQ(m.order, str(d.order));
  EXPECT_EQ(m.triangles, d.triangles);
  EXPECT_EQ(m.search_cost, d.search_cost);
  EXPECT_EQ(m.time_triangulate, d.time_triangulate);
  EXPECT_EQ(m.time_alpha, d.time_alpha);
  EXPECT_EQ(m.time_loops, d.time_loops);
  EXPECT_EQ(m.compute_time, d.compute_time);
}

inline void expect_same(const hullgrind::part_pose_t& m, const hgdds_PartPose& d) {
  SCOPED_TRACE("part pose seq " + std::to_string(m.header.seq));
  expect_header(m.header, d.header);
  EXPECT_EQ(m.cloud_seq, d.cloud_seq);
  EXPECT_EQ(m.part_index, d.part_index);
  EXPECT_EQ(m.num_parts, d.num_parts);
  expect_array(m.centroid_uv, d.centroid_uv, "centroid_uv");
  expect_array(m.centroid_xyz, d.centroid_xyz, "centroid_xyz");
  EXPECT_EQ(m.principal_axis_angle, d.principal_axis_angle);
  EXPECT_EQ(m.area, d.area);
  expect_array(m.bbox_min_uv, d.bbox_min_uv, "bbox_min_uv");
  expect_array(m.bbox_max_uv, d.bbox_max_uv, "bbox_max_uv");
  expect_array(m.obb_size, d.obb_size, "obb_size");
}

inline void expect_same(const hullgrind::grind_path_t& m, const hgdds_GrindPath& d) {
  SCOPED_TRACE("grind path seq " + std::to_string(m.header.seq));
  expect_header(m.header, d.header);
  EXPECT_EQ(m.job_id, str(d.job_id));
  EXPECT_EQ(m.outline_seq, d.outline_seq);
  EXPECT_EQ(m.frame, str(d.frame));
  ASSERT_EQ(std::size_t(m.n) * 3, d.position._length);
  ASSERT_EQ(std::size_t(m.n) * 4, d.orientation._length);
  for (int i = 0; i < m.n; ++i) {
    for (int k = 0; k < 3; ++k) EXPECT_EQ(m.position[i][k], d.position._buffer[3 * i + k]);
    for (int k = 0; k < 4; ++k) EXPECT_EQ(m.orientation[i][k], d.orientation._buffer[4 * i + k]);
  }
  expect_seq(m.speed, d.speed, "speed");
  expect_seq(m.kind, d.kind, "kind");
  expect_seq(m.loop_index, d.loop_index, "loop_index");
  EXPECT_EQ(m.tool_radius, d.tool_radius);
  EXPECT_EQ(m.tilt, d.tilt);
  EXPECT_EQ(m.flipped, d.flipped);
  EXPECT_EQ(m.revision, d.revision);
  ASSERT_EQ(m.coverage.size(), d.coverage._length);
  for (std::size_t i = 0; i < m.coverage.size(); ++i) {
    EXPECT_EQ(m.coverage[i].loop_index, d.coverage._buffer[i].loop_index);
    EXPECT_EQ(m.coverage[i].planned, d.coverage._buffer[i].planned);
    EXPECT_EQ(m.coverage[i].reached_length, d.coverage._buffer[i].reached_length);
    EXPECT_EQ(m.coverage[i].reason, str(d.coverage._buffer[i].reason));
  }
  ASSERT_EQ(m.unreached.size(), d.unreached._length);
  for (std::size_t i = 0; i < m.unreached.size(); ++i) {
    EXPECT_EQ(m.unreached[i].length, d.unreached._buffer[i].length);
    EXPECT_EQ(m.unreached[i].cause, d.unreached._buffer[i].cause);
  }
}

inline void expect_same(const hullgrind::job_status_t& m, const hgdds_JobStatus& d) {
  SCOPED_TRACE("job status seq " + std::to_string(m.header.seq));
  expect_header(m.header, d.header);
  EXPECT_EQ(m.job_id, str(d.job_id));
  EXPECT_EQ(m.part_id, str(d.part_id));
  EXPECT_EQ(m.source, str(d.source));
  EXPECT_EQ(m.state, d.state);
  EXPECT_EQ(m.progress, d.progress);
  EXPECT_EQ(m.message, str(d.message));
  EXPECT_EQ(m.answer, d.answer);
  EXPECT_EQ(m.plan_revision, d.plan_revision);
  EXPECT_EQ(m.actor, str(d.actor));
  expect_seq(m.excluded_loops, d.excluded_loops, "excluded_loops");
  ASSERT_EQ(m.unground.size(), d.unground._length);
  for (std::size_t i = 0; i < m.unground.size(); ++i) {
    EXPECT_EQ(m.unground[i].loop_index, d.unground._buffer[i].loop_index);
    EXPECT_EQ(m.unground[i].start, d.unground._buffer[i].start);
    EXPECT_EQ(m.unground[i].length, d.unground._buffer[i].length);
    EXPECT_EQ(m.unground[i].cause, d.unground._buffer[i].cause);
    EXPECT_EQ(m.unground[i].reason, str(d.unground._buffer[i].reason));
  }
}

inline void expect_same(const hullgrind::robot_status_t& m, const hgdds_RobotStatus& d) {
  SCOPED_TRACE("robot status seq " + std::to_string(m.header.seq));
  expect_header(m.header, d.header);
  EXPECT_EQ(m.mode, d.mode);
  expect_array(m.tcp_position, d.tcp_position, "tcp_position");
  expect_array(m.tcp_orientation, d.tcp_orientation, "tcp_orientation");
  EXPECT_EQ(m.job_id, str(d.job_id));
  EXPECT_EQ(m.path_index, d.path_index);
  EXPECT_EQ(m.fault_code, d.fault_code);
  EXPECT_EQ(m.fault_text, str(d.fault_text));
}

inline void expect_same(const hullgrind::heartbeat_t& m, const hgdds_Health& d) {
  SCOPED_TRACE("heartbeat seq " + std::to_string(m.header.seq));
  expect_header(m.header, d.header);
  EXPECT_EQ(m.process, str(d.process));
  EXPECT_EQ(m.pid, d.pid);
  EXPECT_EQ(m.state, d.state);
  EXPECT_EQ(m.state_text, str(d.state_text));
  EXPECT_EQ(m.uptime, d.uptime);
  EXPECT_EQ(m.received, d.received);
  EXPECT_EQ(m.published, d.published);
  EXPECT_EQ(m.dropped, d.dropped);
  EXPECT_EQ(m.decode_errors, d.decode_errors);
  EXPECT_EQ(m.last_latency, d.last_latency);
  EXPECT_EQ(d.thinned, 0) << "thinned is the gateway's own counter";
}

}  // namespace hgtest
