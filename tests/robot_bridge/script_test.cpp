// URScript generation, read back by the fake controller's own parser.
#include <gtest/gtest.h>

#include <Eigen/Geometry>
#include <cmath>
#include <cstdio>
#include <fstream>
#include <unistd.h>

#include "fake_ur.hpp"
#include "script_check.hpp"
#include "robot_bridge/path.hpp"
#include "robot_bridge/urscript.hpp"
#include "test_paths.hpp"

using namespace hg::robot_bridge;

TEST(RobotBridgeScript, ProgramMatchesThePath) {
  const auto path = rbtest::square_path("s1");
  ScriptOptions o;
  o.accel = 0.7;
  o.blend_radius = 0.002;
  o.progress_register = 30;
  o.done_tag = 1234567890;
  const std::string text = make_script(from_lcm(path), o);
  const auto ps = rbtest::parse_script(text);
  expect_script_matches(ps, path, 30, 0.7);
  ASSERT_FALSE(ps.ops.empty());
  EXPECT_EQ(ps.ops.back().value, 1234567890);
  // Blend radius capped by 40 % of the shorter neighbouring segment: waypoint 1 sits between 5 cm segments.
  EXPECT_NEAR(ps.moves[1].r, 0.002, 1e-9);
}

TEST(RobotBridgeScript, RotationVectorOfHalfTurnAndIdentity) {
  // Tool down = half turn about x: rotation vector (pi, 0, 0); identity: zero vector.
  const std::string down = ur_pose(Vec3(0.1, 0.2, 0.3), Quat(0, 1, 0, 0));
  double v[6];
  ASSERT_EQ(std::sscanf(down.c_str(), "p[%lf, %lf, %lf, %lf, %lf, %lf]", &v[0], &v[1], &v[2], &v[3], &v[4], &v[5]), 6);
  EXPECT_NEAR(std::abs(v[3]), M_PI, 1e-9);
  EXPECT_NEAR(v[4], 0, 1e-12);
  EXPECT_NEAR(v[5], 0, 1e-12);
  const std::string id = ur_pose(Vec3(0, 0, 0), Quat(-1, 0, 0, 0));  // -q: same rotation
  ASSERT_EQ(std::sscanf(id.c_str(), "p[%lf, %lf, %lf, %lf, %lf, %lf]", &v[0], &v[1], &v[2], &v[3], &v[4], &v[5]), 6);
  EXPECT_NEAR(std::hypot(v[3], v[4], v[5]), 0, 1e-12);
}

TEST(RobotBridgeScript, StopProgramParses) {
  const auto ps = rbtest::parse_script(stop_script(0.5));
  ASSERT_TRUE(ps.ok) << ps.error;
  ASSERT_EQ(ps.ops.size(), 1u);
  EXPECT_EQ(ps.ops[0].kind, rbtest::ParsedScript::Op::Stop);
}

TEST(RobotBridgeScript, ReadsPathJson) {
  const std::string file = ::testing::TempDir() + "rb_path_" + std::to_string(getpid()) + ".json";
  {
    std::ofstream out(file);
    out << R"({"job_id": "J", "frame": "robot_base", "waypoints": [
      {"position": [0.4, 0, 0.2], "orientation": [0, 1, 0, 0], "speed": 0.05, "kind": "approach"},
      {"position": [0.45, 0, 0.2], "orientation": [0, 1, 0, 0], "speed": 0.02, "kind": 2}]})";
  }
  const Path p = read_path_json(file);
  ASSERT_EQ(p.size(), 2u);
  EXPECT_EQ(p.job_id, "J");
  EXPECT_EQ(p.kind[0], 0);
  EXPECT_EQ(p.kind[1], 2);
  EXPECT_EQ(p.position[1].x(), 0.45);
  {
    std::ofstream out(file);
    out << R"({"waypoints": [{"position": [0.4, 0], "orientation": [0, 1, 0, 0], "speed": 0.05, "kind": 0}]})";
  }
  try {
    read_path_json(file);
    FAIL() << "a 2-number position must be refused";
  } catch (const std::runtime_error& e) {
    EXPECT_NE(std::string(e.what()).find("waypoint 0"), std::string::npos) << e.what();
  }
  std::remove(file.c_str());
}
