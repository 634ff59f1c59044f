// HG_ROBOT_MOVE on the simulated robot, on the test's own clock: the TCP ends at the commanded pose, the
// move is reported like a job (RUNNING then DONE), and what must not run is refused with nothing moved.
#include <gtest/gtest.h>

#include <memory>
#include <random>

#include "hullgrind/job_status_t.hpp"
#include "robot_bridge/bridge.hpp"
#include "robot_bridge/sim_driver.hpp"
#include "test_paths.hpp"

using namespace hg::robot_bridge;
using hullgrind::job_status_t;
using hullgrind::robot_move_t;

namespace {

struct Cell {
  std::vector<job_status_t> statuses;
  std::unique_ptr<Bridge> bridge;
  double now = 0;
  Cell() {
    SimOptions so;
    so.home.position = Vec3(0.5, 0, 0.3);
    so.home.orientation = Quat(0, 1, 0, 0);
    so.time_scale = 10;
    BridgeOutputs out;
    out.job_status = [this](job_status_t& s) { statuses.push_back(s); };
    bridge = std::make_unique<Bridge>(BridgeConfig{}, std::make_unique<SimDriver>(so), out, now);
  }
  // Ticks at 100 Hz until the move ends (or 600 simulated seconds); returns its last state.
  std::int8_t run(const std::string& id) {
    for (int i = 0; i < 6000; ++i) {
      bridge->tick(now += 0.01);
      if (!statuses.empty() && statuses.back().job_id == id && statuses.back().state != +job_status_t::STATE_RUNNING)
        break;
    }
    return statuses.back().state;
  }
};

robot_move_t move(const std::string& id, const Vec3& p, const Quat& q, double speed = 0.2) {
  robot_move_t m{};
  m.header.frame_id = "robot_base";
  m.move_id = id;
  for (int i = 0; i < 3; ++i) m.position[i] = p[i];
  m.orientation[0] = q.w(), m.orientation[1] = q.x(), m.orientation[2] = q.y(), m.orientation[3] = q.z();
  m.speed = speed;
  return m;
}

}  // namespace

TEST(RobotBridgeMove, TheTcpEndsAtEachCommandedPose) {
  Cell c;
  std::mt19937_64 rng(14);
  std::uniform_real_distribution<double> u(-1, 1);
  for (int k = 0; k < 20; ++k) {
    const Vec3 p(0.5 + 0.4 * u(rng), 0.4 * u(rng), 0.2 + 0.15 * u(rng));
    const Quat q = Quat(Eigen::Vector4d(u(rng), u(rng), u(rng), u(rng)).normalized());
    const std::string id = "move-" + std::to_string(k);
    c.bridge->on_move(move(id, p, q), c.now);
    ASSERT_EQ(c.statuses.back().state, +job_status_t::STATE_RUNNING) << c.statuses.back().message;
    ASSERT_EQ(c.run(id), +job_status_t::STATE_DONE) << c.statuses.back().message;
    const Pose& tcp = c.bridge->driver().state().tcp;
    EXPECT_LT((tcp.position - p).norm(), 1e-9);
    EXPECT_LT(tcp.orientation.angularDistance(q), 1e-9);
    EXPECT_EQ(c.bridge->state(), Bridge::State::Idle);
  }
}

TEST(RobotBridgeMove, RefusesWhatMustNotRunAndMovesNothing) {
  Cell c;
  const Quat down(0, 1, 0, 0);
  const Vec3 home = c.bridge->driver().state().tcp.position;
  c.bridge->on_move(move("below", Vec3(0.5, 0, -0.6), down), c.now);  // under the default table (-0.5)
  EXPECT_EQ(c.statuses.back().state, +job_status_t::STATE_REFUSED);
  EXPECT_NE(c.statuses.back().message.find("nothing moved"), std::string::npos) << c.statuses.back().message;
  c.bridge->on_move(move("fast", Vec3(0.6, 0, 0.3), down, 5.0), c.now);  // above max speed
  EXPECT_EQ(c.statuses.back().state, +job_status_t::STATE_REFUSED);
  c.bridge->tick(c.now += 0.01);
  EXPECT_EQ(c.bridge->driver().state().tcp.position, home);
  // Busy: a second move while one runs is refused; the same id again answers with its state.
  c.bridge->on_move(move("long", Vec3(0.9, 0.3, 0.3), down, 0.05), c.now);
  c.bridge->on_move(move("second", Vec3(0.5, 0, 0.2), down), c.now);
  EXPECT_EQ(c.statuses.back().job_id, "second");
  EXPECT_EQ(c.statuses.back().state, +job_status_t::STATE_REFUSED);
  EXPECT_EQ(c.run("long"), +job_status_t::STATE_DONE);
  c.bridge->on_move(move("long", Vec3(0.5, 0, 0.2), down), c.now);
  EXPECT_EQ(c.statuses.back().state, +job_status_t::STATE_DONE);
  EXPECT_LT((c.bridge->driver().state().tcp.position - Vec3(0.9, 0.3, 0.3)).norm(), 1e-9);
}
