// What a camera-bridge process test hears on the bus: every plate cloud and the bridge's heartbeats.
// Used inside a test's own network namespace (tests/netns.sh); ttl=0, and a receive buffer large enough
// for whole plate clouds.
#pragma once

#include <chrono>
#include <string>
#include <vector>

#include <lcm/lcm-cpp.hpp>

#include "hullgrind/heartbeat_t.hpp"
#include "hullgrind/plate_cloud_t.hpp"

namespace hg::test {

struct CameraBus {
  lcm::LCM lcm{"udpm://239.255.76.67:7667?ttl=0&recv_buf_size=4194304"};
  std::vector<hullgrind::plate_cloud_t> clouds;
  std::vector<hullgrind::heartbeat_t> beats;  // of hg-camera-bridge only
  CameraBus() {
    lcm.subscribe("HG_PLATE_CLOUD", &CameraBus::on_cloud, this);
    lcm.subscribe("HG_HEARTBEAT", &CameraBus::on_beat, this);
  }
  void on_cloud(const lcm::ReceiveBuffer*, const std::string&, const hullgrind::plate_cloud_t* m) {
    clouds.push_back(*m);
  }
  void on_beat(const lcm::ReceiveBuffer*, const std::string&, const hullgrind::heartbeat_t* m) {
    if (m->process == "hg-camera-bridge") beats.push_back(*m);
  }
  // Pumps until pred() or the limit (a bound for failure only; nothing asserts on timing).
  template <class Pred>
  bool until(Pred pred, std::chrono::milliseconds limit = std::chrono::seconds(60)) {
    const auto end = std::chrono::steady_clock::now() + limit;
    while (std::chrono::steady_clock::now() < end && !pred()) lcm.handleTimeout(20);
    return pred();
  }
  bool last_state_is(int state) const { return !beats.empty() && beats.back().state == state; }
};

}  // namespace hg::test
