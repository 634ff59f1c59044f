// A fake Universal Robots controller for tests, on loopback: a script port that parses the URScript it
// receives (movel/movep poses, a, v, r; output register writes; stopl) and "runs" it, and an RTDE server
// (protocol version, output recipe by name, start, data packages at 125 Hz) with the knobs a test needs:
// protective stop at a waypoint, connection drops, raw bytes injected into the stream. Its own encoding,
// written from the RTDE guide, independent of the bridge's.
#pragma once

#include <atomic>
#include <cstdint>
#include <map>
#include <mutex>
#include <string>
#include <thread>
#include <vector>

namespace rbtest {

struct ParsedScript {
  struct Move {
    bool process = false;  // movep (else movel)
    double pose[6] = {0, 0, 0, 0, 0, 0};
    double a = 0, v = 0, r = 0;
  };
  struct Op {
    enum Kind { Move, Register, Stop } kind;
    std::size_t move = 0;  // index into moves
    int reg = 0;
    std::int32_t value = 0;
  };
  std::string name;
  std::vector<Move> moves;
  std::vector<Op> ops;
  bool ok = false;  // def ... end with only statements we understand
  std::string error;
};
ParsedScript parse_script(const std::string& text);

class FakeUr {
 public:
  FakeUr(int script_port, int rtde_port);
  ~FakeUr();

  void set_tcp(const double pose[6]);
  void set_safety_mode(std::int32_t m);
  void set_robot_mode(std::int32_t m);
  void set_speedup(double s) { speedup_ = s; }
  void protective_stop_at(int waypoint) { stop_at_ = waypoint; }
  // Closes the RTDE client now; for `seconds` every new connection is accepted and closed at once.
  void drop_rtde(double seconds);
  void inject(const std::vector<std::uint8_t>& bytes);

  std::vector<std::string> scripts();
  std::vector<double> accept_times();  // steady clock seconds of every RTDE connection accepted
  int handshakes() const { return handshakes_; }
  std::int32_t safety_mode();
  std::uint32_t runtime_state();
  void tcp(double out[6]);

 private:
  void loop();
  void serve_rtde_input();
  void send_data();
  void step_program(double dt);
  void send_pkg(std::uint8_t type, const std::vector<std::uint8_t>& payload);

  int script_listen_ = -1, rtde_listen_ = -1, client_ = -1;
  std::thread thread_;
  std::atomic<bool> quit_{false};
  std::mutex mutex_;
  // controller state (under mutex_)
  double tcp_[6] = {0.4, 0, 0.3, 3.14159265358979, 0, 0};
  std::int32_t robot_mode_ = 7, safety_mode_ = 1;
  std::uint32_t runtime_state_ = 1;
  std::map<int, std::int32_t> registers_;
  ParsedScript program_;
  std::size_t pc_ = 0;
  bool playing_ = false;
  std::vector<std::string> scripts_;
  std::vector<double> accepts_;
  double outage_until_ = 0;
  std::vector<std::uint8_t> inject_, rx_;
  std::vector<std::string> recipe_;
  bool streaming_ = false;
  std::atomic<double> speedup_{1.0};
  std::atomic<int> stop_at_{-1};
  std::atomic<int> handshakes_{0};
};

double steady_seconds();

}  // namespace rbtest
