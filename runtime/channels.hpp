// Every LCM channel of hullgrind, in one table: name, message type, who publishes, who subscribes, what it
// carries. Every publish and subscribe of the tree names its channel by a constant below (lint_channels:
// no channel name as a string literal elsewhere, and every publish/subscribe of a process is in its row);
// the table of docs/CHANNELS.md is generated from kTable (runtime_channels_test; HG_WRITE_DOC=1 rewrites it).
#pragma once

namespace hg::channels {

inline constexpr const char* kDepth = "HG_DEPTH";
inline constexpr const char* kPlateCloud = "HG_PLATE_CLOUD";
inline constexpr const char* kOutline = "HG_OUTLINE";
inline constexpr const char* kPartPose = "HG_PART_POSE";
inline constexpr const char* kGrindPath = "HG_GRIND_PATH";
inline constexpr const char* kJobRequest = "HG_JOB_REQUEST";
inline constexpr const char* kJobStatus = "HG_JOB_STATUS";
inline constexpr const char* kRobotStatus = "HG_ROBOT_STATUS";
inline constexpr const char* kRobotMove = "HG_ROBOT_MOVE";
inline constexpr const char* kHeartbeat = "HG_HEARTBEAT";
inline constexpr const char* kLog = "HG_LOG";

struct Channel {
  const char* name;
  const char* type;         // the message type, package hullgrind (lcmtypes/TYPE.lcm)
  const char* publishers;   // process folders (camera_bridge, ...) and tools (hg-calibrate, ...)
  const char* subscribers;  // the same
  const char* what;         // Markdown, for docs/CHANNELS.md
};

inline constexpr Channel kTable[] = {
    {kDepth, "depth_frame_t", "camera_bridge", "monitoring (spy, record)",
     "decimated, PNG-compressed depth image, rate-limited"},
    {kPlateCloud, "plate_cloud_t", "camera_bridge", "outline_service, station, hg-calibrate (capture)",
     "the plate's top-surface points in plate-plane coordinates, scan-line order; the robot's flange pose at "
     "capture (eye-in-hand)"},
    {kOutline, "outline_t", "outline_service",
     "path_planner, dds_gateway, job_recorder, station, hg-calibrate (capture)",
     "outer loops and holes (`outline_loop_t`), or an error status with the reason; the cloud's flange pose "
     "(eye-in-hand)"},
    {kPartPose, "part_pose_t", "outline_service", "dds_gateway (carrying robot)",
     "area centroid and principal axis, holes subtracted"},
    {kGrindPath, "grind_path_t", "path_planner", "robot_bridge, dds_gateway, job_recorder, station",
     "waypoints in the robot base frame with speed and segment kind, the coverage of every loop, the unreached "
     "stretches and the smoothed edge the tool grinds; published again, identical (same `header.seq`), until the "
     "robot bridge acknowledges it (docs/path_planner.md, \"Path delivery\")"},
    {kJobRequest, "job_request_t",
     "operator (`hg-lcm-send job`, hg-station), dds_gateway, hg-foxglove (a client's publish, `--client-publish`), "
     "job_recorder (QUERY at start), hg-calibrate (capture --trigger: a START that makes a `--trigger job` camera "
     "bridge capture)",
     "camera_bridge, path_planner, robot_bridge, job_recorder",
     "start, approve, reject, re-plan, abort, reset or query a job; job parameters"},
    {kJobStatus, "job_status_t", "path_planner, robot_bridge, dds_gateway",
     "path_planner, robot_bridge, dds_gateway, job_recorder, station, hg-calibrate (moves), operator",
     "the job's state (table below) with progress, reason, plan revision, who approved, excluded loops, unground "
     "stretches; `answer` true for an answer to a repeat or QUERY"},
    {kRobotStatus, "robot_status_t", "robot_bridge",
     "path_planner (robot position), camera_bridge (the flange pose at capture, eye-in-hand), dds_gateway, "
     "station, hg-calibrate (touch, capture, moves)",
     "mode, TCP pose, path index, fault"},
    {kRobotMove, "robot_move_t", "hg-calibrate (verify --move, simulate --move: the eye-in-hand view poses), operator",
     "robot_bridge",
     "one straight TCP move to a pose, answered on HG_JOB_STATUS under `move_id` like a job (RUNNING, DONE when "
     "there; REFUSED when busy, in FAULT or outside the limits)"},
    {kHeartbeat, "heartbeat_t", "every process, 1 Hz", "supervisor, dds_gateway, station",
     "state, uptime, counters (received, published, dropped, decode errors), latency"},
    {kLog, "log_line_t", "every process (runtime's logger, once LCM is open)",
     "hg-foxglove (`/hg/log`), hg-mcap, record",
     "each line the process logs at its `--log-level` or above: process, pid, level, text, time (the same line as "
     "on its stderr, `out/logs/`)"},
};

}  // namespace hg::channels
