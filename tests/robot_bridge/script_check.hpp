// Compares a URScript program, as the fake controller parsed it, with the path it was made from.
#pragma once

#include <gtest/gtest.h>

#include <Eigen/Geometry>
#include <cmath>

#include "fake_ur.hpp"
#include "hullgrind/grind_path_t.hpp"

// Checks a parsed program against the path: pose, rotation (as a rotation, up to the sign of q), speed,
// move kind, register writes 0..n-1 before the moves and the done tag after the last. Shared with test_ur.
inline void expect_script_matches(const rbtest::ParsedScript& ps, const hullgrind::grind_path_t& path, int reg,
                                  double accel) {
  ASSERT_TRUE(ps.ok) << ps.error;
  ASSERT_EQ(int(ps.moves.size()), path.n);
  int expected_next_reg = 0;
  std::size_t move = 0;
  for (const auto& op : ps.ops) {
    if (op.kind == rbtest::ParsedScript::Op::Register) {
      EXPECT_EQ(op.reg, reg);
      if (move < ps.moves.size()) EXPECT_EQ(op.value, expected_next_reg++);
      else
        EXPECT_GE(op.value, 1000000000);  // the done tag, larger than any index
    } else if (op.kind == rbtest::ParsedScript::Op::Move) {
      EXPECT_EQ(op.move, move);
      EXPECT_EQ(int(op.move) + 1, expected_next_reg) << "register write before each move";
      ++move;
    }
  }
  for (int i = 0; i < path.n; ++i) {
    const auto& m = ps.moves[std::size_t(i)];
    for (int k = 0; k < 3; ++k)
      EXPECT_NEAR(m.pose[k], path.position[std::size_t(i)][std::size_t(k)], 1e-6) << "waypoint " << i;
    const Eigen::Vector3d rv(m.pose[3], m.pose[4], m.pose[5]);
    const double angle = rv.norm();
    EXPECT_LE(angle, M_PI + 1e-9);
    const Eigen::Quaterniond got =
        angle > 0 ? Eigen::Quaterniond(Eigen::AngleAxisd(angle, rv / angle)) : Eigen::Quaterniond::Identity();
    const auto& o = path.orientation[std::size_t(i)];
    const Eigen::Quaterniond want(o[0], o[1], o[2], o[3]);
    EXPECT_NEAR(std::abs(got.dot(want.normalized())), 1.0, 1e-9) << "waypoint " << i;
    EXPECT_NEAR(m.v, path.speed[std::size_t(i)], 1e-6);
    EXPECT_NEAR(m.a, accel, 1e-6);
    const int kind = path.kind[std::size_t(i)];
    EXPECT_EQ(m.process, kind == 1 || kind == 2 || kind == 3) << "waypoint " << i;
    EXPECT_GE(m.r, 0.0);
    if (i + 1 == path.n) EXPECT_EQ(m.r, 0.0);  // stops exactly at the end
  }
}
