#include "fake_ur.hpp"

#include <arpa/inet.h>
#include <chrono>
#include <cmath>
#include <cstring>
#include <netinet/in.h>
#include <poll.h>
#include <sstream>
#include <stdexcept>
#include <sys/socket.h>
#include <unistd.h>

namespace rbtest {

double steady_seconds() {
  return std::chrono::duration<double>(std::chrono::steady_clock::now().time_since_epoch()).count();
}

namespace {

std::string trim(const std::string& s) {
  const auto b = s.find_first_not_of(" \t\r");
  if (b == std::string::npos) return "";
  return s.substr(b, s.find_last_not_of(" \t\r") - b + 1);
}

int listen_on(int port) {
  int fd = socket(AF_INET, SOCK_STREAM | SOCK_CLOEXEC, 0);
  int one = 1;
  setsockopt(fd, SOL_SOCKET, SO_REUSEADDR, &one, sizeof one);
  sockaddr_in a{};
  a.sin_family = AF_INET;
  a.sin_port = htons(std::uint16_t(port));
  a.sin_addr.s_addr = htonl(INADDR_LOOPBACK);
  if (bind(fd, reinterpret_cast<sockaddr*>(&a), sizeof a) != 0 || listen(fd, 8) != 0)
    throw std::runtime_error("fake UR: cannot listen on 127.0.0.1:" + std::to_string(port) + ": " +
                             std::strerror(errno));
  return fd;
}

void put_be(std::vector<std::uint8_t>& out, std::uint64_t v, int bytes) {
  for (int i = bytes - 1; i >= 0; --i) out.push_back(std::uint8_t(v >> (8 * i)));
}
void put_double(std::vector<std::uint8_t>& out, double d) {
  std::uint64_t u;
  std::memcpy(&u, &d, 8);
  put_be(out, u, 8);
}

}  // namespace

ParsedScript parse_script(const std::string& text) {
  ParsedScript ps;
  std::istringstream in(text);
  std::string line;
  bool in_def = false, ended = false;
  int lineno = 0;
  while (std::getline(in, line)) {
    ++lineno;
    line = trim(line);
    if (line.empty() || line[0] == '#') continue;
    auto fail = [&](const std::string& why) {
      ps.error = "line " + std::to_string(lineno) + ": " + why + ": " + line;
      return ps;
    };
    if (!in_def) {
      char name[64];
      if (std::sscanf(line.c_str(), "def %63[A-Za-z0-9_]():", name) != 1) return fail("expected def");
      ps.name = name;
      in_def = true;
      continue;
    }
    if (ended) return fail("text after end");
    if (line == "end") {
      ended = true;
      continue;
    }
    int reg = 0;
    long long value = 0;
    double a = 0;
    ParsedScript::Move m;
    char kind[8];
    char tail[4];
    if (std::sscanf(line.c_str(), "write_output_integer_register(%d, %lld)%1s", &reg, &value, tail) == 2) {
      ps.ops.push_back({ParsedScript::Op::Register, 0, reg, std::int32_t(value)});
    } else if (std::sscanf(line.c_str(), "%5[movelp](p[%lf, %lf, %lf, %lf, %lf, %lf], a=%lf, v=%lf, r=%lf)%1s", kind,
                           &m.pose[0], &m.pose[1], &m.pose[2], &m.pose[3], &m.pose[4], &m.pose[5], &m.a, &m.v, &m.r,
                           tail) == 10 &&
               (std::string(kind) == "movel" || std::string(kind) == "movep")) {
      m.process = std::string(kind) == "movep";
      ps.ops.push_back({ParsedScript::Op::Move, ps.moves.size(), 0, 0});
      ps.moves.push_back(m);
    } else if (std::sscanf(line.c_str(), "stopl(%lf)%1s", &a, tail) == 1) {
      ps.ops.push_back({ParsedScript::Op::Stop, 0, 0, 0});
    } else {
      return fail("statement the fake controller does not know");
    }
  }
  if (!ended) {
    ps.error = "no end";
    return ps;
  }
  ps.ok = true;
  return ps;
}

FakeUr::FakeUr(int script_port, int rtde_port) {
  script_listen_ = listen_on(script_port);
  rtde_listen_ = listen_on(rtde_port);
  thread_ = std::thread([this] { loop(); });
}

FakeUr::~FakeUr() {
  quit_ = true;
  thread_.join();
  if (client_ >= 0) close(client_);
  close(script_listen_);
  close(rtde_listen_);
}

void FakeUr::set_tcp(const double pose[6]) {
  std::lock_guard l(mutex_);
  std::memcpy(tcp_, pose, sizeof tcp_);
}
void FakeUr::set_safety_mode(std::int32_t m) {
  std::lock_guard l(mutex_);
  safety_mode_ = m;
}
void FakeUr::set_robot_mode(std::int32_t m) {
  std::lock_guard l(mutex_);
  robot_mode_ = m;
}
void FakeUr::drop_rtde(double seconds) {
  std::lock_guard l(mutex_);
  if (client_ >= 0) close(client_);
  client_ = -1;
  streaming_ = false;
  outage_until_ = steady_seconds() + seconds;
}
void FakeUr::inject(const std::vector<std::uint8_t>& bytes) {
  std::lock_guard l(mutex_);
  inject_.insert(inject_.end(), bytes.begin(), bytes.end());
}
std::vector<std::string> FakeUr::scripts() {
  std::lock_guard l(mutex_);
  return scripts_;
}
std::vector<double> FakeUr::accept_times() {
  std::lock_guard l(mutex_);
  return accepts_;
}
std::int32_t FakeUr::safety_mode() {
  std::lock_guard l(mutex_);
  return safety_mode_;
}
std::uint32_t FakeUr::runtime_state() {
  std::lock_guard l(mutex_);
  return runtime_state_;
}
void FakeUr::tcp(double out[6]) {
  std::lock_guard l(mutex_);
  std::memcpy(out, tcp_, sizeof tcp_);
}

void FakeUr::send_pkg(std::uint8_t type, const std::vector<std::uint8_t>& payload) {
  if (client_ < 0) return;
  std::vector<std::uint8_t> pkg;
  put_be(pkg, 3 + payload.size(), 2);
  pkg.push_back(type);
  pkg.insert(pkg.end(), payload.begin(), payload.end());
  if (send(client_, pkg.data(), pkg.size(), MSG_NOSIGNAL) != ssize_t(pkg.size())) {
    close(client_);
    client_ = -1;
    streaming_ = false;
  }
}

void FakeUr::serve_rtde_input() {
  std::uint8_t buf[4096];
  ssize_t n = recv(client_, buf, sizeof buf, MSG_DONTWAIT);
  if (n == 0 || (n < 0 && errno != EAGAIN && errno != EWOULDBLOCK)) {
    close(client_);
    client_ = -1;
    streaming_ = false;
    rx_.clear();
    return;
  }
  if (n > 0) rx_.insert(rx_.end(), buf, buf + n);
  while (rx_.size() >= 3) {
    const std::size_t size = std::size_t(rx_[0]) << 8 | rx_[1];
    if (size < 3 || rx_.size() < size) break;
    const std::uint8_t type = rx_[2];
    std::vector<std::uint8_t> p(rx_.begin() + 3, rx_.begin() + long(size));
    rx_.erase(rx_.begin(), rx_.begin() + long(size));
    if (type == 'V') {
      const bool v2 = p.size() == 2 && p[0] == 0 && p[1] == 2;
      send_pkg('V', {std::uint8_t(v2 ? 1 : 0)});
    } else if (type == 'O' && p.size() >= 8) {
      std::string names(p.begin() + 8, p.end()), types;
      recipe_.clear();
      std::stringstream ss(names);
      for (std::string item; std::getline(ss, item, ',');) {
        std::string t = "NOT_FOUND";
        if (item == "timestamp") t = "DOUBLE";
        else if (item == "actual_TCP_pose")
          t = "VECTOR6D";
        else if (item == "robot_mode" || item == "safety_mode")
          t = "INT32";
        else if (item == "runtime_state")
          t = "UINT32";
        else if (item.rfind("output_int_register_", 0) == 0)
          t = "INT32";
        recipe_.push_back(item);
        types += (types.empty() ? "" : ",") + t;
      }
      std::vector<std::uint8_t> reply{1};
      reply.insert(reply.end(), types.begin(), types.end());
      send_pkg('O', reply);
    } else if (type == 'S') {
      send_pkg('S', {1});
      streaming_ = true;
      ++handshakes_;
    } else if (type == 'P') {
      send_pkg('P', {1});
      streaming_ = false;
    }
  }
}

void FakeUr::send_data() {
  std::vector<std::uint8_t> p{1};
  for (const std::string& f : recipe_) {
    if (f == "timestamp") put_double(p, steady_seconds());
    else if (f == "actual_TCP_pose")
      for (double v : tcp_) put_double(p, v);
    else if (f == "robot_mode")
      put_be(p, std::uint32_t(robot_mode_), 4);
    else if (f == "safety_mode")
      put_be(p, std::uint32_t(safety_mode_), 4);
    else if (f == "runtime_state")
      put_be(p, runtime_state_, 4);
    else if (f.rfind("output_int_register_", 0) == 0)
      put_be(p, std::uint32_t(registers_[std::atoi(f.c_str() + 20)]), 4);
  }
  send_pkg('U', p);
}

void FakeUr::step_program(double dt) {
  while (playing_ && pc_ < program_.ops.size()) {
    const auto& op = program_.ops[pc_];
    if (op.kind == ParsedScript::Op::Register) {
      registers_[op.reg] = op.value;
      ++pc_;
      if (op.value == stop_at_) {  // the cell's safety system trips here
        safety_mode_ = 3;
        runtime_state_ = 4;  // PAUSED
        playing_ = false;
        stop_at_ = -1;
        return;
      }
      continue;
    }
    if (op.kind == ParsedScript::Op::Move) {
      const auto& m = program_.moves[op.move];
      double d[3], dist = 0;
      for (int i = 0; i < 3; ++i) d[i] = m.pose[i] - tcp_[i], dist += d[i] * d[i];
      dist = std::sqrt(dist);
      const double step = m.v * speedup_ * dt;
      if (dist <= step) {
        std::memcpy(tcp_, m.pose, sizeof tcp_);
        ++pc_;
        continue;
      }
      for (int i = 0; i < 3; ++i) tcp_[i] += d[i] / dist * step;
      return;
    }
    ++pc_;  // stopl in a program: nothing more to do
  }
  if (playing_ && pc_ >= program_.ops.size()) {
    playing_ = false;
    runtime_state_ = 1;  // STOPPED
  }
}

void FakeUr::loop() {
  double last = steady_seconds(), next_data = last;
  while (!quit_) {
    pollfd fds[3] = {{script_listen_, POLLIN, 0}, {rtde_listen_, POLLIN, 0}, {-1, POLLIN, 0}};
    {
      std::lock_guard l(mutex_);
      fds[2].fd = client_;
    }
    poll(fds, 3, 2);
    std::lock_guard l(mutex_);
    const double now = steady_seconds();
    if (fds[0].revents & POLLIN) {
      int c = accept4(script_listen_, nullptr, nullptr, SOCK_CLOEXEC);
      if (c >= 0) {
        timeval tv{1, 0};
        setsockopt(c, SOL_SOCKET, SO_RCVTIMEO, &tv, sizeof tv);
        std::string text;
        char buf[4096];
        for (ssize_t n; (n = recv(c, buf, sizeof buf, 0)) > 0;) text.append(buf, std::size_t(n));
        close(c);
        scripts_.push_back(text);
        ParsedScript ps = parse_script(text);
        bool is_stop = false;
        for (const auto& op : ps.ops) is_stop |= op.kind == ParsedScript::Op::Stop;
        if (ps.ok && is_stop) {  // a new program replaces the running one; this one only decelerates
          playing_ = false;
          runtime_state_ = 1;
        } else if (ps.ok && (safety_mode_ == 1 || safety_mode_ == 2) && robot_mode_ == 7) {
          program_ = ps;
          pc_ = 0;
          playing_ = true;
          runtime_state_ = 2;
        }
      }
    }
    if (fds[1].revents & POLLIN) {
      int c = accept4(rtde_listen_, nullptr, nullptr, SOCK_CLOEXEC);
      if (c >= 0) {
        accepts_.push_back(now);
        if (now < outage_until_) {
          close(c);
        } else {
          if (client_ >= 0) close(client_);
          client_ = c;
          streaming_ = false;
          rx_.clear();
        }
      }
    }
    if (client_ >= 0 && fds[2].fd == client_ && (fds[2].revents & (POLLIN | POLLHUP | POLLERR))) serve_rtde_input();
    step_program(now - last);
    last = now;
    if (client_ >= 0 && !inject_.empty()) {
      send(client_, inject_.data(), inject_.size(), MSG_NOSIGNAL);
      inject_.clear();
    }
    if (now >= next_data) {
      next_data = now + 1.0 / 125;
      if (client_ >= 0 && streaming_) send_data();
    }
  }
}

}  // namespace rbtest
