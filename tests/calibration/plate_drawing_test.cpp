// The generated calibration plate is the plate of the drawing in docs/calibration.md (numbers typed from
// the drawing's table here, not taken from the code).
#include <cmath>

#include <gtest/gtest.h>

#include "calibration/target.hpp"
#include "sim/partgen/shapes.hpp"

TEST(CalibrationPlateDrawing, TheGeneratedPartHasTheDrawingsHoles) {
  struct Hole {
    const char* id;
    double x, y, d;  // mm
  };
  const Hole drawing[] = {{"H1", 50, 50, 30},   {"H2", 370, 50, 40},  {"H3", 370, 250, 50},
                          {"H4", 250, 110, 60}, {"H5", 260, 230, 70}, {"H6", 110, 190, 80}};
  const hg::partgen::Shape plate = hg::partgen::make_shape("calibration-plate");
  EXPECT_DOUBLE_EQ(plate.thickness, 0.010);
  ASSERT_EQ(plate.polygon.holes.size(), std::size(drawing));
  EXPECT_NEAR(hg::partgen::signed_area(plate.polygon.outer), 0.42 * 0.30, 1e-15);
  const hg::calibration::Drawing target = hg::calibration::calibration_plate_drawing();
  ASSERT_EQ(target.holes.size(), std::size(drawing));
  for (std::size_t k = 0; k < std::size(drawing); ++k) {
    SCOPED_TRACE(drawing[k].id);
    const Eigen::Vector2d c(drawing[k].x * 1e-3, drawing[k].y * 1e-3);
    const double r = drawing[k].d * 1e-3 / 2;
    // Every vertex of the hole ring on the drawing's circle; the ring goes clockwise (a hole).
    for (const auto& p : plate.polygon.holes[k]) EXPECT_NEAR((p - c).norm(), r, 1e-12);
    EXPECT_LT(hg::partgen::signed_area(plate.polygon.holes[k]), 0);
    EXPECT_EQ(target.holes[k].id, drawing[k].id);
    EXPECT_NEAR((target.holes[k].centre - Eigen::Vector3d(c.x(), c.y(), 0.010)).norm(), 0, 1e-15);
    EXPECT_NEAR(target.holes[k].diameter, 2 * r, 1e-15);
  }
  // Not a test piece: the six-part catalogue stays as it is.
  for (const auto& name : hg::partgen::shape_names()) EXPECT_NE(name, "calibration-plate");
}
