// Unit tests of the outline and path files, against independent (analytic) expectations.
#include <gtest/gtest.h>

#include "tests/path_planner/step_shapes.hpp"

TEST(PathPlannerIo, OutlineJsonErrorsNameThePlace) {
  const Plane pl;
  try {
    read_outline_json("{\"loops\": [", pl);  // 11 bytes: the error is at the end, byte 12
    FAIL();
  } catch (const std::runtime_error& e) {
    EXPECT_NE(std::string(e.what()).find("byte 12"), std::string::npos) << e.what();
  }
  try {
    read_outline_json(R"({"loops": [{"hole": false, "points": [[0,0],[1,0],["x",1]]}]})", pl);
    FAIL();
  } catch (const std::runtime_error& e) {
    EXPECT_NE(std::string(e.what()).find("loops[0].points[2]"), std::string::npos) << e.what();
  }
  const OutlineInput in = read_outline_json(
      R"({"plane": {"origin": [1,2,3], "normal": [0,0,1], "u": [1,0,0], "v": [0,1,0]},
          "loops": [{"hole": true, "area": 1, "perimeter": 4, "points": [[0,0],[0,1],[1,1],[1,0]]}]})",
      pl);
  ASSERT_EQ(in.loops.size(), 1u);
  EXPECT_TRUE(in.loops[0].hole);
  EXPECT_EQ(in.plane.origin, Vec3(1, 2, 3));
  EXPECT_EQ(in.loops[0].points[2], Vec2(1, 1));
}
