// Shared pieces of the DdsGateway suites: the gateway as a child process (tests/common/child_process.hpp), LCM
// collectors, DDS readers that keep what they take, and waiting with a pump. Everything runs inside tests/netns.sh.
#pragma once

#include <gtest/gtest.h>

#include <chrono>
#include <csignal>
#include <atomic>
#include <functional>
#include <memory>
#include <string>
#include <thread>
#include <vector>

#include <lcm/lcm-cpp.hpp>

#include "dds_gateway/dds_support.hpp"
#include "runtime/node.hpp"
#include "tests/common/child_process.hpp"

namespace hgtest {

using namespace std::chrono_literals;
using Clock = std::chrono::steady_clock;

inline std::string cyclone_config() { return "file://" + hg::dds_gateway::shipped_cyclone_config(); }

// The gateway process; asked to stop (SIGTERM, then SIGKILL after 3 s) when it goes out of scope.
class GatewayProcess : public hg::test::ChildProcess {
 public:
  GatewayProcess(int domain, std::vector<std::string> extra = {}) : ChildProcess(arguments(domain, std::move(extra))) {}
  ~GatewayProcess() { stop(); }
  bool running() { return started() && !wait().has_value(); }
  // SIGTERM; returns the exit code (-1 if it had to be killed).
  int stop() { return ChildProcess::stop(SIGTERM, 3s); }

 private:
  static std::vector<std::string> arguments(int domain, std::vector<std::string> extra) {
    std::vector<std::string> args = {std::string(HG_BIN_DIR) + "/hg-dds-gateway",
                                     "--log-level",
                                     "warn",
                                     "--dds-domain",
                                     std::to_string(domain),
                                     "--dds-config",
                                     cyclone_config()};
    args.insert(args.end(), extra.begin(), extra.end());
    return args;
  }
};

// Keeps every message of type T received on a channel.
template <class T>
class Collector {
 public:
  Collector(lcm::LCM& lcm, const std::string& channel) { sub_ = lcm.subscribe(channel, &Collector::on, this); }
  void on(const lcm::ReceiveBuffer*, const std::string&, const T* m) { msgs.push_back(*m); }
  std::vector<T> msgs;

 private:
  lcm::Subscription* sub_ = nullptr;
};

// A DDS sample that owns what Cyclone allocated into it.
template <class T>
struct Owned {
  explicit Owned(const dds_topic_descriptor_t* d) : desc(d) {}
  ~Owned() { dds_sample_free(&s, desc, DDS_FREE_CONTENTS); }
  Owned(const Owned&) = delete;
  Owned& operator=(const Owned&) = delete;
  T s{};
  const dds_topic_descriptor_t* desc;
};

// A reader that keeps every valid sample it takes.
template <class T>
class Reader {
 public:
  Reader(dds_entity_t participant, const dds_topic_descriptor_t* desc, const std::string& topic_name,
         const dds_qos_t* qos)
      : desc_(desc) {
    reader_ =
        hg::dds_gateway::make_reader(participant, hg::dds_gateway::make_topic(participant, desc, topic_name), qos);
  }
  ~Reader() { dds_delete(reader_); }
  // Takes what has arrived; returns how many new samples.
  int take() {
    int got = 0;
    for (;;) {
      auto o = std::make_unique<Owned<T>>(desc_);
      void* p = &o->s;
      dds_sample_info_t info;
      dds_return_t n = dds_take(reader_, &p, &info, 1, 1);
      if (n <= 0) break;
      if (info.valid_data) {
        samples.push_back(std::move(o));
        ++got;
      }
    }
    return got;
  }
  int matched() const {
    dds_subscription_matched_status_t st{};
    dds_get_subscription_matched_status(reader_, &st);
    return int(st.current_count);
  }
  dds_entity_t get() const { return reader_; }
  std::vector<std::unique_ptr<Owned<T>>> samples;

 private:
  const dds_topic_descriptor_t* desc_;
  dds_entity_t reader_ = 0;
};

// Calls pump until pred holds or limit passes; returns pred().
inline bool wait_until(const std::function<bool()>& pred, const std::function<void()>& pump,
                       std::chrono::milliseconds limit) {
  auto end = Clock::now() + limit;
  while (!pred()) {
    if (Clock::now() >= end) return false;
    pump();
  }
  return true;
}

inline std::string str(const char* s) { return s ? s : ""; }

}  // namespace hgtest
