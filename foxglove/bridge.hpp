// What the bus looks like in Foxglove: one place that turns an LCM message into Foxglove topics, shared by
// the live server (hg-foxglove) and the recorder (hg-mcap), so a recording and a live cell show the same
// topics with the same schemas.
//   - every LCM channel is a topic of the same name, its JSON Schema generated from the .lcm files
//     (lcm_json.hpp), encoding json; a channel whose fingerprint is no hullgrind type is a topic with
//     encoding "lcm" and no schema (the raw bytes), counted as unknown;
//   - the 3-D picture in Foxglove's well-known schemas (JSON encoding):
//       /hg/plate/points   foxglove.PointCloud     HG_PLATE_CLOUD, x y z float32, decimated to max_points
//       /hg/outline        foxglove.SceneUpdate    HG_OUTLINE: one line loop per outline loop (holes red)
//       /hg/grind_path     foxglove.SceneUpdate    HG_GRIND_PATH: entity grind_path, line segments coloured
//                                                  by segment kind; entity smoothed_edge, one cyan line loop
//                                                  per outline loop of the edge the tool grinds
//       /hg/log            foxglove.Log            the processes' log lines (HG_LOG) and HG_JOB_STATUS as
//                                                  log lines
//       /tf/camera         foxglove.FrameTransform base <- camera (the cell's calibration; eye-in-hand:
//                                                  with the flange pose of the capture) with every plate
//                                                  cloud
//       /tf                foxglove.FrameTransform base <- tcp with every HG_ROBOT_STATUS
#pragma once

#include <Eigen/Geometry>

#include <atomic>
#include <cstdint>
#include <functional>
#include <map>
#include <memory>
#include <optional>
#include <string>
#include <vector>

#include "cell/cell.hpp"
#include "tools/lcm_tools/lcm_schema.hpp"

namespace hullgrind {
class plate_cloud_t;
}

namespace hg::foxglove {

struct Topic {
  std::string name;
  std::string schema_name;      // "hullgrind.plate_cloud_t", "foxglove.PointCloud"; "" for a raw channel
  std::string schema_encoding;  // "jsonschema", or "" with no schema
  std::string schema;           // the JSON Schema text
  std::string encoding;         // "json", or "lcm" for a raw channel
  bool active = true;           // false once its channel changed type (the live server unadvertises it)
};

struct BridgeOptions {
  std::size_t max_points = 200000;  // PointCloud decimation: every k-th point so that at most this many remain
  std::string tcp_frame = "tcp";
  // The cell's calibration (config/cell.yaml): p_base = camera_to_base * p_camera; eye-in-hand: camera ->
  // flange, composed with the capture's flange pose. Without either, no base <- camera transform is sent.
  std::optional<Eigen::Isometry3d> camera_to_base, camera_to_flange;
  std::string base_frame = cell::Frames{}.base;  // the cell's frames.base
  std::string camera_frame = "camera";           // until a plate cloud names its frame
  // Set (by the live server when it stops): a conversion under way gives up, its error "cancelled".
  const std::atomic<bool>* cancel = nullptr;
};

struct Output {
  int topic;              // index into Bridge::topics()
  std::string payload;    // JSON text (or the raw LCM bytes for a raw channel)
  bool in_place = false;  // the payload was appended to convert's `in_place` buffer instead (payload empty)
};

struct Converted {
  std::vector<Output> outputs;
  std::vector<int> new_topics;      // topics created by this message (advertise them)
  std::vector<int> retired_topics;  // topics of the channel's previous type (unadvertise them)
  bool unknown_type = false;        // the fingerprint is no hullgrind type: sent raw
  std::string error;                // a known type that did not decode: nothing sent, say why
};

class Bridge {
 public:
  Bridge(lcmtools::Schema schema, BridgeOptions options);
  ~Bridge();

  const std::vector<Topic>& topics() const { return topics_; }
  const lcmtools::Schema& schema() const { return schema_; }

  // One LCM message. wanted(topic) says whether the payload of that topic is needed (the live server
  // builds only what someone subscribed to; nullptr: everything). Never throws on bad bytes. in_place (hg-mcap:
  // the MCAP writer's open chunk): the JSON of the channel's own topic is appended there, as the first
  // output, marked in_place; after an error it may hold part of a text the caller drops.
  Converted convert(const std::string& channel, const std::uint8_t* data, std::size_t size,
                    const std::function<bool(int)>& wanted = nullptr, std::string* in_place = nullptr);
  // The base <- camera transform of an eye-to-hand cell on /tf/camera at utime (the live server sends it every
  // second, so a client that connects between jobs has the camera too); nothing without a calibration or
  // for an eye-in-hand cell (its camera moves: the transform comes with each cloud).
  Converted camera_transform(std::int64_t utime);
  // Gives an output's payload back once it is written, so that the next message's JSON text goes into
  // memory already in use (a cloud's text is 40 MB: a fresh buffer is page faults and a munmap each time).
  void recycle(std::string&& payload);

 private:
  struct ChannelState {
    std::int64_t fingerprint = 0;
    int topic = -1;
    std::vector<int> derived;
  };
  int add_topic(Topic t, Converted& c);
  std::string spare_buffer(std::size_t expected);
  int well_known(const std::string& name, const std::string& schema_name, Converted& c);
  void derive(const lcmtools::Struct& type, const std::uint8_t* data, std::size_t size,
              const std::function<bool(int)>& wanted, Converted& c);

  lcmtools::Schema schema_;
  BridgeOptions opt_;
  std::vector<Topic> topics_;
  std::map<std::string, ChannelState> channels_;
  std::map<std::string, int> well_known_;            // derived topic name -> index
  std::vector<std::string> spare_;                   // recycled payload buffers
  std::unique_ptr<hullgrind::plate_cloud_t> cloud_;  // the last plate cloud decoded (its arrays reused)
};

// The JSON Schema of each Foxglove well-known message this bridge writes ("foxglove.PointCloud", ...):
// only the fields it fills, every one required.
std::string well_known_schema(const std::string& schema_name);

}  // namespace hg::foxglove
