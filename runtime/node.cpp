#include "runtime/node.hpp"

#include <cerrno>
#include <csignal>
#include <cstdio>
#include <cstdlib>
#include <cstring>
#include <fcntl.h>
#include <poll.h>
#include <sstream>
#include <sys/time.h>
#include <unistd.h>

#include "hullgrind/heartbeat_t.hpp"
#include "hullgrind/log_line_t.hpp"
#include "runtime/channels.hpp"
#include "runtime/log_sink.hpp"

namespace hg::runtime {
namespace {

int g_signal_pipe[2] = {-1, -1};

void on_signal(int) {
  const char c = 's';
  [[maybe_unused]] ssize_t n = write(g_signal_pipe[1], &c, 1);
}

void install_signal_handlers() {
  if (g_signal_pipe[0] >= 0) return;
  if (pipe2(g_signal_pipe, O_NONBLOCK | O_CLOEXEC) != 0) {
    perror("pipe2");
    std::exit(1);
  }
  struct sigaction sa {};
  sa.sa_handler = on_signal;
  sigemptyset(&sa.sa_mask);
  sa.sa_flags = SA_RESTART;
  sigaction(SIGINT, &sa, nullptr);
  sigaction(SIGTERM, &sa, nullptr);
  signal(SIGPIPE, SIG_IGN);  // a peer closing a socket is an error to handle, not a reason to die
}

}  // namespace

std::int64_t now_utime() {
  timeval tv{};
  gettimeofday(&tv, nullptr);
  return std::int64_t(tv.tv_sec) * 1000000 + tv.tv_usec;
}

Node::Node(ProcessInfo info, int argc, char** argv) : info_(std::move(info)) {
  start_ = std::chrono::steady_clock::now();
  set_process_name(info_.name);
  parse(argc, argv);
  install_signal_handlers();
  lcm_url_ = with_receive_buffer(lcm_url_);
}

lcm::LCM& Node::open_lcm() {
  std::call_once(lcm_once_, [this] {
    lcm_ = std::make_unique<lcm::LCM>(lcm_url_);
    if (!lcm_->good()) {
      logf(Level::Error,
           "cannot open LCM at '%s' (for udpm: is there a multicast route? "
           "`ip route add 224.0.0.0/4 dev lo`)",
           lcm_url_.c_str());
      std::exit(1);
    }
    // Every log line on HG_LOG as well. Not through publish(): a log line is not the process's output (not
    // counted in `published`), and a failure to publish it is not logged again.
    set_log_sink([this](Level level, std::int64_t utime, const char* text) {
      hullgrind::log_line_t m{};
      fill_header(channels::kLog, m.header.seq, utime);
      m.header.utime = utime;
      m.process = info_.name;
      m.pid = int32_t(getpid());
      m.level = std::int8_t(level);
      m.text = text;
      lcm_->publish(channels::kLog, &m);
    });
  });
  return *lcm_;
}

Node::~Node() {
  if (lcm_) set_log_sink(nullptr);  // waits for a line being published
}

void Node::print_usage(std::FILE* out) const {
  std::fprintf(out, "usage: %s [options]\n\n%s\n", info_.name.c_str(), info_.summary.c_str());
  if (!info_.details.empty()) std::fprintf(out, "\n%s\n", info_.details.c_str());
  std::fprintf(out, "\nOptions (each may also be set as a key in the --config file; the command line wins):\n");
  params_.print_options(out);
  std::fprintf(out, "  --config FILE                      YAML config file (keys as the options above, without --)\n");
  std::fprintf(out, "  --help, --help-markdown, --version this text, the options as a Markdown table, the version\n");
  std::fprintf(
      out,
      "\nPublishes hullgrind.heartbeat_t on HG_HEARTBEAT at 1 Hz; exits cleanly on SIGINT/SIGTERM.\n"
      "Exit status: 0 clean stop, 1 cannot open LCM, 2 bad command line or config (one line names the key).\n");
}

std::vector<Param> process_params(std::vector<Param> own) {
  own.push_back(text_param("lcm-url", default_lcm_url(),
                           "LCM provider [$LCM_DEFAULT_URL, else " + std::string(kDefaultLcmUrl) + "]"));
  own.push_back(text_param("log-level", "info", "log threshold", {"debug", "info", "warn", "error"}));
  return own;
}

void Node::parse(int argc, char** argv) {
  params_ = Params(process_params(info_.params));
  try {
    switch (params_.parse(argc, argv)) {
      case Params::Action::Help: print_usage(stdout); std::exit(0);
      case Params::Action::HelpMarkdown: std::fputs(params_.markdown().c_str(), stdout); std::exit(0);
      case Params::Action::Version: std::printf("%s %s\n", info_.name.c_str(), version()); std::exit(0);
      case Params::Action::Run: break;
    }
    set_log_level(parse_level(params_.text("log-level")));
    lcm_url_ = params_.text("lcm-url");
  } catch (const std::exception& e) {
    std::fprintf(stderr, "%s: %s (see --help)\n", info_.name.c_str(), e.what());
    std::exit(2);
  }
}

void Node::add_handler(const std::string& channel,
                       std::function<void(const lcm::ReceiveBuffer*, const std::string&)> fn) {
  handlers_.push_back(std::make_unique<Handler>(Handler{std::move(fn)}));
  lcm::Subscription* sub = open_lcm().subscribe(channel, &Handler::on, handlers_.back().get());
  if (!sub) return;
  if (queue_capacity_ > 0) {
    sub->setQueueCapacity(queue_capacity_);
  } else if (channel == channels::kJobRequest || channel == channels::kJobStatus) {
    // Job requests and statuses are small and none may be lost: a burst of them (a retrying writer's
    // repeats, several jobs at once) must not overflow LCM's 30 while the loop is busy planning.
    sub->setQueueCapacity(kJobQueueCapacity);
  }
}

void Node::subscribe_raw(const std::string& channel,
                         std::function<void(const lcm::ReceiveBuffer&, const Delivery&)> handler) {
  add_handler(channel, [this, handler](const lcm::ReceiveBuffer* rbuf, const std::string& ch) {
    ++counters_.received;
    handler(*rbuf, Delivery{ch, rbuf->recv_utime, rbuf->data_size});
  });
}

void Node::count_decode_error(const std::string& channel, const std::string& what) {
  ++counters_.decode_errors;
  std::uint64_t suppressed = 0;
  if (decode_log_limit_.allow(suppressed))
    logf(Level::Warn, "skipped a message on %s that does not decode: %s (%lld so far%s)", channel.c_str(), what.c_str(),
         (long long)counters_.decode_errors.load(),
         suppressed ? (", " + std::to_string(suppressed) + " not logged").c_str() : "");
}

void Node::fill_header(const std::string& channel, std::int64_t& seq, std::int64_t& utime) {
  std::lock_guard lock(seq_mutex_);
  seq = seq_[channel]++;
  if (utime == 0) utime = now_utime();
}

void Node::every(std::chrono::milliseconds period, std::function<void()> fn) {
  timers_.push_back(Timer{period, std::chrono::steady_clock::now() + period, std::move(fn)});
}

void Node::set_state(std::int8_t state, const std::string& text) {
  std::lock_guard lock(state_mutex_);
  if (state != state_ || text != state_text_) {
    if (state == hullgrind::heartbeat_t::STATE_OK) logf(Level::Info, "state OK");
    else if (state == hullgrind::heartbeat_t::STATE_STOPPING)
      logf(Level::Info, "stopping: %s", text.c_str());
    else
      logf(state >= hullgrind::heartbeat_t::STATE_ERROR ? Level::Error : Level::Warn, "state %d: %s", int(state),
           text.c_str());
  }
  state_ = state;
  state_text_ = text;
}

double Node::uptime() const { return std::chrono::duration<double>(std::chrono::steady_clock::now() - start_).count(); }

void Node::publish_heartbeat() {
  hullgrind::heartbeat_t hb{};
  hb.header.seq = heartbeat_seq_++;
  hb.header.utime = now_utime();
  hb.header.frame_id = "";
  hb.process = info_.name;
  hb.pid = int32_t(getpid());
  {
    std::lock_guard lock(state_mutex_);
    hb.state = state_;
    hb.state_text = state_text_;
  }
  hb.uptime = uptime();
  hb.received = counters_.received;
  hb.published = counters_.published;
  hb.dropped = counters_.dropped;
  hb.decode_errors = counters_.decode_errors;
  hb.last_latency = last_latency_;
  open_lcm().publish(channels::kHeartbeat, &hb);
}

void Node::stop() { on_signal(0); }

int Node::run() {
  using clock = std::chrono::steady_clock;
  open_lcm();
  logf(Level::Info, "started, pid %d, LCM %s%s%s", int(getpid()), lcm_url_.c_str(), config().empty() ? "" : ", config ",
       config().empty() ? "" : config().source().c_str());
  {
    std::lock_guard lock(state_mutex_);
    if (state_ == hullgrind::heartbeat_t::STATE_STARTING) state_ = hullgrind::heartbeat_t::STATE_OK;
  }
  publish_heartbeat();
  auto next_heartbeat = clock::now() + std::chrono::seconds(1);
  pollfd fds[2] = {{open_lcm().getFileno(), POLLIN, 0}, {g_signal_pipe[0], POLLIN, 0}};
  while (!stop_requested_) {
    auto now = clock::now();
    auto wake = next_heartbeat;
    for (const Timer& t : timers_) wake = std::min(wake, t.next);
    int timeout_ms =
        int(std::max<long long>(0, std::chrono::duration_cast<std::chrono::milliseconds>(wake - now).count() + 1));
    int n = poll(fds, 2, timeout_ms);
    if (n < 0 && errno != EINTR) {
      logf(Level::Error, "poll: %s", std::strerror(errno));
      break;
    }
    if (n > 0 && (fds[1].revents & POLLIN)) {
      char buf[16];
      while (read(g_signal_pipe[0], buf, sizeof buf) > 0) {
      }
      stop_requested_ = true;
      break;
    }
    if (n > 0 && (fds[0].revents & POLLIN)) {
      try {
        lcm_->handleTimeout(0);
      } catch (const std::exception& e) {  // a handler must not take the process down with it
        logf(Level::Error, "handler failed: %s", e.what());
      }
    }
    now = clock::now();
    for (Timer& t : timers_) {
      if (now >= t.next) {
        t.next = now + t.period;
        try {
          t.fn();
        } catch (const std::exception& e) {
          logf(Level::Error, "timer failed: %s", e.what());
        }
      }
    }
    if (now >= next_heartbeat) {
      publish_heartbeat();
      next_heartbeat += std::chrono::seconds(1);
      if (next_heartbeat < now) next_heartbeat = now + std::chrono::seconds(1);  // after a long handler
    }
  }
  set_state(hullgrind::heartbeat_t::STATE_STOPPING, "shutting down");
  publish_heartbeat();
  logf(Level::Info, "stopped cleanly after %.1f s", uptime());
  return 0;
}

}  // namespace hg::runtime
