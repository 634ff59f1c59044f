// Every LCM channel of hullgrind, in one place. docs/CHANNELS.md is the same table with publishers and
// subscribers; change both together.
#pragma once

namespace hg::channels {

inline constexpr const char* kDepth = "HG_DEPTH";             // depth_frame_t     camera_bridge -> monitoring
inline constexpr const char* kPlateCloud = "HG_PLATE_CLOUD";  // plate_cloud_t     camera_bridge -> outline_service
inline constexpr const char* kOutline =
    "HG_OUTLINE";  // outline_t         outline_service -> path_planner, dds_gateway, job_recorder
inline constexpr const char* kPartPose = "HG_PART_POSE";  // part_pose_t       outline_service -> dds_gateway
inline constexpr const char* kGrindPath =
    "HG_GRIND_PATH";  // grind_path_t      path_planner -> robot_bridge, dds_gateway, job_recorder
inline constexpr const char* kJobRequest = "HG_JOB_REQUEST";  // job_request_t     operator, dds_gateway ->
                                                              // camera_bridge, path_planner, robot_bridge, job_recorder
inline constexpr const char* kJobStatus =
    "HG_JOB_STATUS";  // job_status_t      path_planner, robot_bridge, dds_gateway -> all
inline constexpr const char* kRobotStatus =
    "HG_ROBOT_STATUS";  // robot_status_t    robot_bridge -> path_planner, dds_gateway
inline constexpr const char* kRobotMove = "HG_ROBOT_MOVE";  // robot_move_t      hg-calibrate -> robot_bridge
inline constexpr const char* kHeartbeat = "HG_HEARTBEAT";  // heartbeat_t       every process -> supervisor, dds_gateway
inline constexpr const char* kLog = "HG_LOG";              // log_line_t        every process -> foxglove, record

}  // namespace hg::channels
