// hg-outline's JSON (outline_writers.hpp) for an outline message off the bus, optionally with the plate
// cloud it came from as the points: the job recorder's outline.json and hg-overview's.
#pragma once

#include <nlohmann/json.hpp>

#include "hullgrind/outline_t.hpp"
#include "hullgrind/plate_cloud_t.hpp"

namespace hg::outline_io {

// `cloud`: the plate cloud (its u, v become the points), or nullptr for none. The frame is "camera": the
// outline service places HG_OUTLINE's plane in the camera frame.
nlohmann::ordered_json outline_message_json(const hullgrind::outline_t& outline, const hullgrind::plate_cloud_t* cloud);

}  // namespace hg::outline_io
