// Shared helpers of the OpenNI2 suites: the independent expectation (the scene renderer called directly)
// and the check that libOpenNI2 was loaded from the private folder holding our driver.
#pragma once

#include <dlfcn.h>

#include <OpenNI.h>
#include <gtest/gtest.h>

#include <cstdint>
#include <optional>
#include <string>

#include "sim/scene/scene.hpp"

namespace hg::camera_bridge::testing {

inline cv::Mat expected_depth(const std::string& scene, const std::string& profile, std::optional<std::uint64_t> seed,
                              std::uint64_t frame_index) {
  sim::SceneSpec spec = sim::scene_preset(scene);
  if (seed) spec.seed = *seed;
  return sim::render(spec, sim::camera_profile(profile), frame_index).depth;
}

inline std::int64_t differing_pixels(const cv::Mat& a, const cv::Mat& b) {
  if (a.size() != b.size() || a.type() != b.type()) return -1;
  return cv::countNonZero(a != b);
}

// Where the process's libOpenNI2 came from (dladdr on one of its C entry points).
inline std::string loaded_openni_path() {
  Dl_info info{};
  if (dladdr(reinterpret_cast<void*>(&oniInitialize), &info) == 0 || info.dli_fname == nullptr) return {};
  return info.dli_fname;
}

inline void init_openni_from_private_folder() {
  ASSERT_EQ(loaded_openni_path(), std::string(HG_OPENNI2_PRIVATE_DIR) + "/libOpenNI2.so.0")
      << "libOpenNI2 must be loaded from the private folder, else our driver is not found";
  ASSERT_EQ(openni::OpenNI::initialize(), openni::STATUS_OK) << openni::OpenNI::getExtendedError();
}

}  // namespace hg::camera_bridge::testing
