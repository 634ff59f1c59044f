// Universal Robots driver: the path goes to the controller as a URScript program over the script port
// (primary/secondary interface, 30002), the state comes back through RTDE (30004): protocol version 2,
// one output recipe, data packages. Everything runs non-blocking on the caller's loop.
#pragma once

#include <cstdint>
#include <string>
#include <vector>

#include "robot_bridge/driver.hpp"
#include "robot_bridge/urscript.hpp"

namespace hg::robot_bridge {

struct UrOptions {
  std::string host = "127.0.0.1";  // IPv4 literal; anything but loopback needs allow_remote
  bool allow_remote = false;
  int script_port = 30002;
  int rtde_port = 30004;
  double frequency = 125;     // RTDE output rate requested, Hz
  ScriptOptions script;       // accel, blend radius, progress register
  double data_timeout = 0.5;  // no data package for this long: connection lost
  double handshake_timeout = 2.0;
  double start_timeout = 5.0;  // the program must be seen playing (or done) this soon after sending
  double backoff_initial = 0.2, backoff_max = 5.0;  // reconnect attempts
};

// Controller-side enums (RTDE robot_mode, safety_mode, runtime_state), for names in messages and tests.
const char* ur_robot_mode_name(int mode);
const char* ur_safety_mode_name(int mode);

class UrDriver final : public Driver {
 public:
  explicit UrDriver(UrOptions options);  // throws std::invalid_argument for a non-loopback host without allow_remote
  ~UrDriver() override;
  const char* name() const override { return "ur"; }
  void update(double now) override;
  const RobotState& state() const override { return state_; }
  std::string start(const Path& path, double now) override;
  void stop(double now) override;
  std::string reset(double now) override;

  // Last values read from the controller (tests, status).
  struct Raw {
    double timestamp = 0;
    double tcp[6] = {0, 0, 0, 0, 0, 0};
    std::int32_t robot_mode = -1, safety_mode = 0;
    std::uint32_t runtime_state = 0;
    std::int32_t progress_register = 0;
    std::int64_t packages = 0;  // data packages parsed
  };
  const Raw& raw() const { return raw_; }
  int connections() const { return connections_; }  // successful RTDE handshakes so far

 private:
  enum class Link { Down, WaitVersion, WaitSetup, WaitStart, Streaming };
  void try_connect(double now);
  void drop(const std::string& why, double now);
  void read_socket(double now);
  void handle(std::uint8_t type, const std::uint8_t* payload, std::size_t size, double now);
  void on_data(double now);
  void evaluate(double now);
  void latch(std::int32_t code, const std::string& text);
  bool send_rtde(std::uint8_t type, const std::vector<std::uint8_t>& payload);
  std::string send_script(const std::string& script);
  void decode_error(const std::string& what);

  UrOptions o_;
  RobotState state_;
  Raw raw_;
  int fd_ = -1;
  Link link_ = Link::Down;
  std::vector<std::uint8_t> rx_;
  std::uint8_t recipe_id_ = 0;
  double link_since_ = 0, last_data_ = 0, next_attempt_ = 0, backoff_ = 0;
  bool ever_streamed_ = false;
  bool have_data_ = false;  // a data package arrived on the current link
  int connections_ = 0;
  // the running program
  bool program_ = false, seen_playing_ = false;
  double sent_at_ = 0;
  std::int32_t done_tag_ = 0;
  std::vector<Vec3> pts_;    // start pose + waypoints
  std::vector<double> cum_;  // distance at each point of pts_
};

}  // namespace hg::robot_bridge
