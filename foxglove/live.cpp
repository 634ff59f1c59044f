#include "live.hpp"

#include <pthread.h>
#include <sched.h>

#include <algorithm>
#include <condition_variable>
#include <cstring>
#include <deque>
#include <map>
#include <optional>
#include <stdexcept>
#include <thread>

#include "bridge.hpp"
#include "cell/cell.hpp"
#include "cell/cell_params.hpp"
#include "hullgrind/heartbeat_t.hpp"
#include "runtime/log.hpp"
#include "foxglove/publish.hpp"
#include "runtime/channels.hpp"
#include "ws_server.hpp"

namespace hg::foxglove {

namespace {

// Messages below this are converted even without a subscriber (kept as their channel's last message for a
// client that subscribes later: the cloud, outline and path come once per job); a 1.6 M-point cloud (19 MB)
// is converted only for a subscriber.
constexpr std::size_t kSmall = 4u << 20;

// The conversion thread at SCHED_IDLE (Linux, per thread; an unprivileged thread may lower itself to it):
// it then runs only on a core no other thread of the machine wants, so turning 19 MB clouds into JSON for
// viewers never takes a core from the outline service. What it cannot keep up with waits in the bounded
// queue and is dropped there, counted. The LCM thread and the heartbeat stay at normal priority, the
// server's thread (accepting connections, writing shared payloads) at normal policy with a nice value
// (server-nice).
void enter_conversion_thread(bool idle) {
  pthread_setname_np(pthread_self(), "hg-fox-convert");  // /proc/PID/task/TID/comm: tests and top see it
  if (!idle) return;
  sched_param sp{};  // SCHED_IDLE has one priority, 0
  if (int err = pthread_setschedparam(pthread_self(), SCHED_IDLE, &sp))
    runtime::logf(runtime::Level::Warn, "cannot run the conversion at idle priority (%s): it runs at normal priority",
                  std::strerror(err));
}

struct Pending {
  std::string channel;
  std::int64_t recv_utime;
  std::string bytes;
};

class Live {
 public:
  Live(runtime::Node& node, BridgeOptions bopt, WsServerOptions sopt, std::size_t queue_messages,
       std::size_t queue_bytes, bool idle, double raw_period, double cloud_period)
      : node_(node),
        raw_period_us_(static_cast<std::int64_t>(raw_period * 1e6)),
        cloud_period_us_(static_cast<std::int64_t>(cloud_period * 1e6)),
        bridge_(lcmtools::Schema::embedded(), with_cancel(std::move(bopt), &cancel_)),
        server_(std::move(sopt)),
        max_messages_(queue_messages),
        max_bytes_(queue_bytes) {
    worker_ = std::thread([this, idle] {
      enter_conversion_thread(idle);
      work();
    });
  }
  ~Live() {
    {
      std::lock_guard<std::mutex> lock(mu_);
      stop_ = true;
    }
    cancel_ = true;  // a conversion at idle priority might otherwise hold up the exit for as long as the cell is busy
    cv_.notify_one();
    worker_.join();
  }
  int port() const { return server_.bound_port(); }

  // LCM thread: a copy into the queue, nothing else. It never waits for the conversion thread: at idle
  // priority, preempted while it holds mu_ (a pop, well under a microsecond), that thread may not run again
  // for as long as the cell keeps both cores busy, and this thread also runs the heartbeat. After a short
  // spin the message is dropped, counted.
  void on_message(const lcm::ReceiveBuffer& rb, const runtime::Delivery& d) {
    if (rb.data_size >= kSmall && !cloud_due(d.channel, d.recv_utime)) return;  // before the 19 MB copy
    Pending p{d.channel, d.recv_utime, std::string(static_cast<const char*>(rb.data), rb.data_size)};
    {
      std::unique_lock<std::mutex> lock(mu_, std::defer_lock);
      for (int i = 0; i < 1000 && !lock.try_lock(); ++i) std::this_thread::yield();
      if (!lock.owns_lock()) {
        node_.count_dropped();
        return;
      }
      if (p.bytes.size() >= kSmall) replace_waiting(p.channel);
      bytes_ += p.bytes.size();
      queue_.push_back(std::move(p));
      while (queue_.size() > max_messages_ || (bytes_ > max_bytes_ && queue_.size() > 1)) {
        bytes_ -= queue_.front().bytes.size();
        queue_.pop_front();
        node_.count_dropped();
      }
    }
    cv_.notify_one();
  }

  void health() {
    std::optional<WsStats> maybe = server_.try_stats();
    if (!maybe) return;  // the conversion thread holds the server's lock: the state text of a second ago stays
    const WsStats& st = *maybe;
    std::int64_t dropped_clients = 0;
    std::string text = std::to_string(st.clients.size()) + " clients";
    for (const WsClientStats& c : st.clients) {
      dropped_clients += static_cast<std::int64_t>(c.dropped);
      text +=
          "; " + c.peer + " dropped " + std::to_string(c.dropped);  // not "sent": the text would change every second
    }
    text += "; " + std::to_string(st.disconnected_garbage) + " closed for garbage; " + std::to_string(unknown_.load()) +
            " messages of unknown type; " + std::to_string(st.bad_requests + st.timeouts) + " bad HTTP requests";
    node_.set_state(hullgrind::heartbeat_t::STATE_OK, text);
    (void)dropped_clients;
  }

 private:
  // A big message (a cloud) replaces the one of its channel still waiting: a viewer gets the newest cloud,
  // not one that waited while the conversion had no core (mu_ held).
  void replace_waiting(const std::string& channel) {
    auto old = std::find_if(queue_.begin(), queue_.end(),
                            [&](const Pending& q) { return q.bytes.size() >= kSmall && q.channel == channel; });
    if (old == queue_.end()) return;
    bytes_ -= old->bytes.size();
    queue_.erase(old);
    node_.count_dropped();
  }

  void work() {
    auto next_tf = std::chrono::steady_clock::now();
    for (;;) {
      Pending p;
      bool have = false;
      {
        std::unique_lock<std::mutex> lock(mu_);
        cv_.wait_until(lock, next_tf, [this] { return stop_ || !queue_.empty(); });
        if (stop_) return;
        if (!queue_.empty()) {
          p = std::move(queue_.front());
          queue_.pop_front();
          bytes_ -= p.bytes.size();
          have = true;
        }
      }
      if (have) convert(p);
      if (std::chrono::steady_clock::now() >= next_tf) {
        next_tf += std::chrono::seconds(1);
        send(bridge_.camera_transform(runtime::now_utime()), runtime::now_utime());
      }
    }
  }

  void convert(const Pending& p) {
    const auto* data = reinterpret_cast<const std::uint8_t*>(p.bytes.data());
    // A topic this message creates is built too: nobody can have subscribed to it yet.
    const int known = static_cast<int>(bridge_.topics().size());
    auto wanted = [&](int t) {
      if (p.bytes.size() < kSmall || t >= known) return true;
      if (!server_.subscribed(t)) return false;
      return bridge_.topics()[t].name != p.channel || raw_due(p.channel, p.recv_utime);  // 3-D topics: always
    };
    Converted c = bridge_.convert(p.channel, data, p.bytes.size(), wanted);
    if (p.bytes.size() >= kSmall) note_raw_sent(p.channel, p.recv_utime, c);
    if (c.unknown_type) ++unknown_;
    if (!c.error.empty() && !cancel_) node_.count_decode_error(p.channel, c.error);
    send(std::move(c), p.recv_utime);
  }

  // LCM thread. A big message at all (its 3-D topics too) at most once per cloud_period_us_ per channel: the
  // camera's 5 Hz of the same plate is more than a viewer needs, and each costs a 19 MB copy and decode.
  bool cloud_due(const std::string& channel, std::int64_t utime) {
    std::int64_t& last = last_cloud_[channel];
    if (last != 0 && utime - last < cloud_period_us_) {
      node_.count_dropped();
      return false;
    }
    last = utime;
    return true;
  }

  // A big message's own JSON (a 1.6 M-point cloud's every number as text, about 40 MB) at most once per
  // raw_period_us_ per channel, skipped ones counted as dropped: it is the conversion's and the viewers' bulk,
  // and on two cores even at idle priority its memory traffic slows the outline service (docs/foxglove.md).
  bool raw_due(const std::string& channel, std::int64_t utime) {
    auto last = last_raw_.find(channel);
    if (last == last_raw_.end() || utime - last->second >= raw_period_us_) return true;
    node_.count_dropped();
    return false;
  }
  void note_raw_sent(const std::string& channel, std::int64_t utime, const Converted& c) {
    for (const Output& o : c.outputs)
      if (bridge_.topics()[o.topic].name == channel) last_raw_[channel] = utime;
  }

  void send(Converted c, std::int64_t utime) {
    if (!c.retired_topics.empty()) server_.unadvertise(c.retired_topics);
    if (!c.new_topics.empty()) {
      std::vector<WsChannel> list;
      for (int t : c.new_topics) {
        const Topic& topic = bridge_.topics()[t];
        list.push_back(
            WsChannel{t, topic.name, topic.encoding, topic.schema_name, topic.schema, topic.schema_encoding});
        if (topic.encoding == "lcm")
          runtime::logf(runtime::Level::Warn, "channel %s carries a type that is no hullgrind type: advertised raw",
                        topic.name.c_str());
      }
      server_.advertise(std::move(list));
    }
    auto ts = static_cast<std::uint64_t>(std::max<std::int64_t>(0, utime)) * 1000;
    for (Output& o : c.outputs) {
      server_.publish(o.topic, ts, std::make_shared<const std::string>(std::move(o.payload)));
      ++node_.counters().published;
    }
  }

  static BridgeOptions with_cancel(BridgeOptions o, const std::atomic<bool>* cancel) {
    o.cancel = cancel;
    return o;
  }

  runtime::Node& node_;
  std::int64_t raw_period_us_, cloud_period_us_;
  // By channel: when a big message was last let into the queue (LCM thread), its own JSON last sent (worker).
  std::map<std::string, std::int64_t> last_cloud_, last_raw_;
  std::atomic<bool> cancel_{false};  // before bridge_, which holds its address
  Bridge bridge_;                    // worker thread only
  WsServer server_;
  std::size_t max_messages_, max_bytes_;
  std::mutex mu_;
  std::condition_variable cv_;
  std::deque<Pending> queue_;
  std::size_t bytes_ = 0;
  bool stop_ = false;
  std::atomic<std::int64_t> unknown_{0};
  std::thread worker_;
};

BridgeOptions bridge_options(runtime::Node& node) {
  BridgeOptions o;
  o.max_points = static_cast<std::size_t>(node.params().integer("max-points"));
  o.camera_frame = node.params().text("camera-frame");
  if (!node.params().text("cell").empty()) {
    cell::Cell cell;
    try {
      cell = cell::read_cell(node.params().text("cell"));
    } catch (const cell::CellError& e) {  // a bad cell file is bad input: exit 2 before the bus is opened
      throw std::invalid_argument(e.what());
    }
    o.base_frame = cell.frames.base;
    if (cell.calibration.camera_to_flange) o.camera_to_flange = cell.calibration.camera_to_flange;
    else
      o.camera_to_base = cell.calibration.camera_to_base;
  }
  return o;
}

}  // namespace

runtime::ProcessInfo process_info() {
  using runtime::integer_param;
  using runtime::text_param;
  return {
      "hg-foxglove",
      "The bus, live, for Foxglove and Lichtblick: a Foxglove WebSocket protocol server (read-only).",
      "Every LCM channel is a topic of the same name with the JSON Schema generated from the .lcm files\n"
      "(encoding json; a channel of an unknown type is advertised once with encoding lcm, raw, and counted),\n"
      "plus the 3-D picture in Foxglove's schemas: /hg/plate/points (foxglove.PointCloud), /hg/outline and\n"
      "/hg/grind_path (foxglove.SceneUpdate), /tf/camera and /tf (foxglove.FrameTransform: base <- camera\n"
      "from --cell, base <- tcp from HG_ROBOT_STATUS), /hg/log (foxglove.Log: log lines and job statuses). hg-mcap writes the same topics.\n"
      "Open ws://HOST:PORT in Foxglove or Lichtblick. No client publishing unless --client-publish: then an\n"
      "operator of --users-file (the station's users file) who logs in with HTTP Basic on the upgrade\n"
      "(ws://USER:PASSWORD@HOST:PORT) may publish HG_JOB_REQUEST as JSON. The conversion runs at idle\n"
      "scheduling priority (--conversion-priority), the process at nice 19 in the shipped pipelines (their\n"
      "nice = 19, docs/RUNNING.md): it takes no core the cell wants, and what waits too long is dropped (the\n"
      "heartbeat's dropped); a plate cloud is converted at most once per --cloud-period and\n"
      "sent as its own JSON at most once per --raw-cloud-period (their memory traffic slows the outline\n"
      "service even at idle priority). A slow client misses frames (counted per client in the\n"
      "heartbeat's state text); a client sending garbage is disconnected with a close reason. Details:\n"
      "docs/foxglove.md.",
      {text_param("host", "127.0.0.1", "address to listen on (loopback: the cell's traffic stays on the machine)"),
       integer_param("port", "8765", "TCP port (0: any free port, logged)", 0, 65535),
       integer_param("max-points", "200000", "foxglove.PointCloud: at most this many points (every k-th; 0 = all)", 0,
                     1e9),
       text_param("cell", "",
                  "cell file (config/cell.yaml): the base frame (frames.base) and the base <- camera transform; "
                  "empty: robot_base, no camera transform"),
       text_param("camera-frame", "camera", "the camera's frame until a plate cloud names it"),
       integer_param("max-clients", "16", "clients served at once; more are refused", 1, 1000),
       runtime::flag_param("client-publish", "offer clientPublish of HG_JOB_REQUEST to operators of --users-file"),
       text_param("users-file", "", "the station's users file (--client-publish: who may publish)"),
       integer_param("client-queue-frames", "256", "messages queued per client before its frames are dropped", 1, 1e6),
       integer_param("client-queue-mb", "64", "MB queued per client before its frames are dropped", 1, 1e5),
       integer_param("queue-messages", "64", "LCM messages waiting for conversion before the oldest is dropped", 1,
                     1e6),
       integer_param("queue-mb", "256", "MB of LCM messages waiting for conversion before the oldest is dropped", 1,
                     1e5),
       text_param("conversion-priority", "idle",
                  "the conversion thread's scheduling: idle (SCHED_IDLE: only a core the cell leaves free; what "
                  "waits too long is dropped, counted) or normal (viewers get more, the cell gets slower)",
                  {"idle", "normal"}),
       integer_param("server-nice", "10",
                     "the nice value of the WebSocket server's thread (its writes to viewers; the process's if that "
                     "is higher): above the cell's 0, "
                     "so that under load a viewer's frames wait and are dropped, not the cell's work; 0: as the cell",
                     0, 19),
       runtime::number_param("cloud-period", "1",
                             "seconds between two messages of 4 MB or more (plate clouds) converted for viewers, per "
                             "channel (their 3-D topics and JSON); the others are dropped, counted; 0: every one",
                             0, 3600),
       runtime::number_param("raw-cloud-period", "30",
                             "seconds between two messages of 4 MB or more (plate clouds) sent on their own channel "
                             "as JSON; their 3-D topics (/hg/plate/points) carry every one; 0: every one",
                             0, 3600),
       cell::moved_to_cell({{"base-frame", "frames.base"}}).front()}};
}

namespace {

// --client-publish: HG_JOB_REQUEST from the operators of the users file (publish.hpp).
void enable_publishing(runtime::Node& node, WsServerOptions& s) {
  const std::string users = node.params().text("users-file");
  if (users.empty()) throw std::invalid_argument("client-publish needs users-file (the station's users file)");
  std::shared_ptr<JobRequestGate> gate;
  try {
    gate = std::make_shared<JobRequestGate>(node, users);
  } catch (const station::UsersError& e) {
    throw std::invalid_argument(std::string("users-file: ") + e.what());
  }
  s.publish_topics = {channels::kJobRequest};
  s.identify = [gate](const std::string& authorization, const std::string& peer) {
    return gate->identify(authorization, peer);
  };
  s.on_publish = [gate](const WsClientChannel& c, const std::string& user, std::string_view payload) {
    return gate->publish(c, user, payload);
  };
}

}  // namespace

std::shared_ptr<void> attach(runtime::Node& node) {
  WsServerOptions s;
  s.host = node.params().text("host");
  s.port = static_cast<int>(node.params().integer("port"));
  s.max_clients = static_cast<std::size_t>(node.params().integer("max-clients"));
  s.max_connections = static_cast<int>(4 * s.max_clients);  // room for upgrades being read and 503s being sent
  s.queue_frames = static_cast<std::size_t>(node.params().integer("client-queue-frames"));
  s.queue_bytes = static_cast<std::size_t>(node.params().integer("client-queue-mb")) << 20;
  s.thread_nice = static_cast<int>(node.params().integer("server-nice"));
  if (node.params().flag("client-publish")) enable_publishing(node, s);
  auto live = std::make_shared<Live>(node, bridge_options(node), s,
                                     static_cast<std::size_t>(node.params().integer("queue-messages")),
                                     static_cast<std::size_t>(node.params().integer("queue-mb")) << 20,
                                     node.params().text("conversion-priority") == "idle",
                                     node.params().number("raw-cloud-period"), node.params().number("cloud-period"));
  runtime::logf(runtime::Level::Info, "serving the bus on ws://%s:%d (Foxglove WebSocket protocol)", s.host.c_str(),
                live->port());
  node.subscribe_raw(".*",
                     [live](const lcm::ReceiveBuffer& rb, const runtime::Delivery& d) { live->on_message(rb, d); });
  node.every(std::chrono::seconds(1), [live] { live->health(); });
  node.set_state(hullgrind::heartbeat_t::STATE_OK, "0 clients");
  return live;
}

}  // namespace hg::foxglove
