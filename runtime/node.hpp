// The one process runtime every hullgrind process runs on:
//  - command line: --lcm-url, --config FILE, --log-level, --help, plus the process's own parameters;
//    a parameter's value comes from the command line, else the config file, else its default;
//  - an LCM main loop with timers; SIGINT/SIGTERM end it cleanly within a second;
//  - heartbeat_t on HG_HEARTBEAT at 1 Hz with state and counters;
//  - typed subscriptions that count and skip messages that fail to decode (bad fingerprint, truncated,
//    garbage), logging them at a bounded rate: input never crashes a process.
#pragma once

#include <atomic>
#include <cstdio>
#include <chrono>
#include <cstdint>
#include <functional>
#include <map>
#include <memory>
#include <mutex>
#include <string>
#include <type_traits>
#include <vector>

#include <lcm/lcm-cpp.hpp>

#include "runtime/config.hpp"
#include "runtime/lcm_url.hpp"
#include "runtime/log.hpp"
#include "runtime/params.hpp"

namespace hg::runtime {

std::int64_t now_utime();

struct ProcessInfo {
  std::string name;           // "hg-outline-service"
  std::string summary;        // one line for --help
  std::string details;        // further --help text: what it does, what is not there yet
  std::vector<Param> params;  // the process's own parameters
};

// A process's parameters as its command line takes them: its own, then --lcm-url and --log-level, which
// every process has (hg-overview parses the planner's command line with them).
std::vector<Param> process_params(std::vector<Param> own);

struct Counters {
  std::atomic<std::int64_t> received{0}, published{0}, dropped{0}, decode_errors{0};
};

// What a handler learns about the message besides its content.
struct Delivery {
  std::string channel;
  std::int64_t recv_utime = 0;
  std::size_t size = 0;
};

// Parses argv. --help / --help-markdown / --version print and exit 0; a bad command line or config prints
// one line naming the command line or the file and the key, and exits 2. LCM is opened on first use (a
// subscription, a publication, the loop), so a process whose own checks refuse its configuration exits
// before it has opened the bus or logged anything else (runtime/process.hpp).
class Node {
 public:
  Node(ProcessInfo info, int argc, char** argv);
  ~Node();
  Node(const Node&) = delete;
  Node& operator=(const Node&) = delete;

  const std::string& name() const { return info_.name; }
  const std::string& lcm_url() const { return lcm_url_; }
  const Config& config() const { return params_.config(); }
  // The one way to read a parameter (command line > config > default): params().number("tool-radius").
  const Params& params() const { return params_; }
  std::vector<std::string> positional() const { return params_.positional(); }

  lcm::LCM& lcm() { return open_lcm(); }
  Counters& counters() { return counters_; }

  // Subscribe with decoding: messages that do not decode exactly are counted and skipped.
  template <class T>
  void subscribe(const std::string& channel, std::function<void(const T&, const Delivery&)> handler);
  // Raw subscription (bytes), counted as received.
  void subscribe_raw(const std::string& channel,
                     std::function<void(const lcm::ReceiveBuffer&, const Delivery&)> handler);
  // LCM silently drops a message that arrives while a subscription already has this many waiting for
  // the loop (LCM's default: 30). Applies to the subscriptions made after the call; 0 keeps LCM's default,
  // except on the job channels (HG_JOB_REQUEST, HG_JOB_STATUS), which always get kJobQueueCapacity.
  void set_queue_capacity(int messages) { queue_capacity_ = messages; }
  static constexpr int kJobQueueCapacity = 10000;

  // Publish; fills header.seq (per channel) and header.utime (if 0) of messages that have a header.
  // Thread-safe. Returns false (and logs) if LCM refused it.
  template <class T>
  bool publish(const std::string& channel, T& msg);

  // Call fn every period on the main loop (first call after one period).
  void every(std::chrono::milliseconds period, std::function<void()> fn);

  // Heartbeat state (heartbeat_t::STATE_*), with a reason when not OK. Thread-safe.
  void set_state(std::int8_t state, const std::string& text = "");
  void set_latency(double seconds) { last_latency_ = seconds; }
  void count_dropped(std::int64_t n = 1) { counters_.dropped += n; }
  void count_decode_error(const std::string& channel, const std::string& what);

  // Runs the main loop until SIGINT/SIGTERM or stop(); returns the process exit code (0 on a clean stop).
  int run();
  void stop();  // thread-safe, async-signal-safe
  bool stopping() const { return stop_requested_.load(); }

  double uptime() const;

 private:
  struct Timer {
    std::chrono::milliseconds period;
    std::chrono::steady_clock::time_point next;
    std::function<void()> fn;
  };
  struct Handler {  // LCM 1.3 takes member-function callbacks only
    std::function<void(const lcm::ReceiveBuffer*, const std::string&)> fn;
    void on(const lcm::ReceiveBuffer* rbuf, const std::string& channel) { fn(rbuf, channel); }
  };
  void publish_heartbeat();
  lcm::LCM& open_lcm();  // opens LCM on first use (thread-safe); cannot open it: one line, exit 1
  void parse(int argc, char** argv);
  void print_usage(std::FILE* out) const;
  void add_handler(const std::string& channel, std::function<void(const lcm::ReceiveBuffer*, const std::string&)> fn);
  void fill_header(const std::string& channel, std::int64_t& seq, std::int64_t& utime);

  ProcessInfo info_;
  Params params_;
  std::string lcm_url_;
  std::unique_ptr<lcm::LCM> lcm_;
  std::once_flag lcm_once_;
  std::vector<std::unique_ptr<Handler>> handlers_;
  std::vector<Timer> timers_;
  Counters counters_;
  std::atomic<double> last_latency_{-1};
  std::atomic<bool> stop_requested_{false};
  std::mutex state_mutex_;
  std::int8_t state_ = 0;
  std::string state_text_;
  std::mutex seq_mutex_;
  std::map<std::string, std::int64_t> seq_;
  std::int64_t heartbeat_seq_ = 0;
  std::chrono::steady_clock::time_point start_;
  RateLimiter decode_log_limit_;
  int queue_capacity_ = 0;
};

// ---- templates ----

template <class T>
void Node::subscribe(const std::string& channel, std::function<void(const T&, const Delivery&)> handler) {
  add_handler(channel, [this, handler](const lcm::ReceiveBuffer* rbuf, const std::string& ch) {
    T msg;
    int used = -1;
    try {
      used = msg.decode(rbuf->data, 0, rbuf->data_size);
    } catch (const std::exception& e) {  // absurd array lengths in a forged message
      used = -1;
    }
    if (used < 0 || static_cast<std::uint32_t>(used) != rbuf->data_size) {
      count_decode_error(ch, used < 0 ? std::string("not a valid ") + T::getTypeName()
                                      : std::string("trailing bytes after ") + T::getTypeName());
      return;
    }
    ++counters_.received;
    handler(msg, Delivery{ch, rbuf->recv_utime, rbuf->data_size});
  });
}

template <class T>
bool Node::publish(const std::string& channel, T& msg) {
  if constexpr (requires {
                  msg.header.seq;
                  msg.header.utime;
                })
    fill_header(channel, msg.header.seq, msg.header.utime);
  if (open_lcm().publish(channel, &msg) != 0) {
    logf(Level::Error, "publish on %s failed", channel.c_str());
    return false;
  }
  ++counters_.published;
  return true;
}

}  // namespace hg::runtime
