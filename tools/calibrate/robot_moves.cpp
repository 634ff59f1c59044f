#include "tools/calibrate/robot_moves.hpp"

#include <chrono>
#include <stdexcept>

#include <lcm/lcm-cpp.hpp>

#include "hullgrind/job_status_t.hpp"
#include "hullgrind/robot_move_t.hpp"
#include "hullgrind/robot_status_t.hpp"
#include "runtime/channels.hpp"

namespace hg::calibrate {

struct RobotMoves::Impl {
  lcm::LCM lcm;
  std::string waiting_for;
  int final_state = -1;
  std::string message;
  long statuses = 0;
  Eigen::Vector3d tcp = Eigen::Vector3d::Zero();
  Eigen::Quaterniond orientation = Eigen::Quaterniond::Identity();
  explicit Impl(const std::string& url) : lcm(url) {}
  void on_job(const lcm::ReceiveBuffer*, const std::string&, const hullgrind::job_status_t* s) {
    if (s->job_id != waiting_for || s->source != "hg-robot-bridge") return;
    message = s->message;
    if (s->state != +hullgrind::job_status_t::STATE_RUNNING) final_state = s->state;
  }
  void on_robot(const lcm::ReceiveBuffer*, const std::string&, const hullgrind::robot_status_t* s) {
    tcp = Eigen::Vector3d(s->tcp_position[0], s->tcp_position[1], s->tcp_position[2]);
    const double* q = s->tcp_orientation;
    orientation = Eigen::Quaterniond(q[0], q[1], q[2], q[3]);
    ++statuses;
  }
};

RobotMoves::RobotMoves(const std::string& url) : impl_(std::make_unique<Impl>(url)) {
  if (!impl_->lcm.good()) throw std::runtime_error("cannot start LCM on " + url);
  impl_->lcm.subscribe(channels::kJobStatus, &Impl::on_job, impl_.get());
  impl_->lcm.subscribe(channels::kRobotStatus, &Impl::on_robot, impl_.get());
}

RobotMoves::~RobotMoves() = default;

MoveResult RobotMoves::move_to(const std::string& id, const Eigen::Vector3d& p, const Eigen::Quaterniond& q,
                               double speed, double timeout_s) {
  Impl& m = *impl_;
  m.waiting_for = id;
  m.final_state = -1;
  m.message = "no answer from the robot bridge";
  hullgrind::robot_move_t msg{};
  msg.header.frame_id = "robot_base";
  msg.move_id = id;
  for (int i = 0; i < 3; ++i) msg.position[i] = p[i];
  msg.orientation[0] = q.w(), msg.orientation[1] = q.x(), msg.orientation[2] = q.y(), msg.orientation[3] = q.z();
  msg.speed = speed;
  const auto deadline = std::chrono::steady_clock::now() + std::chrono::duration<double>(timeout_s);
  const auto resend_every = std::chrono::milliseconds(500);  // the bridge may not be listening yet; ids repeat safely
  auto next_send = std::chrono::steady_clock::now();
  while (m.final_state < 0 && std::chrono::steady_clock::now() < deadline) {
    if (std::chrono::steady_clock::now() >= next_send && m.message == "no answer from the robot bridge") {
      m.lcm.publish(channels::kRobotMove, &msg);
      next_send += resend_every;
    }
    m.lcm.handleTimeout(50);
  }
  MoveResult r;
  r.done = m.final_state == +hullgrind::job_status_t::STATE_DONE;
  r.message = m.message;
  const long seen = m.statuses;  // a status published after DONE carries the final TCP
  while (m.statuses < seen + 2 && std::chrono::steady_clock::now() < deadline) m.lcm.handleTimeout(50);
  r.tcp = m.tcp;
  r.orientation = m.orientation;
  return r;
}

std::optional<Eigen::Vector3d> RobotMoves::current_tcp(double timeout_s) {
  const long seen = impl_->statuses;
  const auto deadline = std::chrono::steady_clock::now() + std::chrono::duration<double>(timeout_s);
  while (impl_->statuses == seen && std::chrono::steady_clock::now() < deadline) impl_->lcm.handleTimeout(50);
  if (impl_->statuses == seen) return std::nullopt;
  return impl_->tcp;
}

}  // namespace hg::calibrate
