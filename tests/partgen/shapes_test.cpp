// Shapes: areas and perimeters against closed forms written from the parts' drawings (not from the
// library's own formulas), the chord bound on curves, ring orientation, and contains() against
// analytic membership.
#include "sim/partgen/shapes.hpp"

#include <gtest/gtest.h>

#include <cmath>
#include <functional>
#include <numbers>
#include <random>
#include <stdexcept>

using namespace hg::partgen;
namespace {
constexpr double pi = std::numbers::pi;
constexpr double tol = 0.05e-3;  // chord error required by the brief

// Closed-form area and perimeter from the drawing dimensions (metres, scale 1).
struct Expect {
  const char* name;
  double area, perimeter, min_radius;
};
const Expect kExpect[] = {
    // 400x250 plate, D100 hole, obround 120 long x 40 wide (straight part 80)
    {"plate-hole-slot", 0.4 * 0.25 - pi * 0.05 * 0.05 - (0.08 * 0.04 + pi * 0.02 * 0.02),
     2 * (0.4 + 0.25) + pi * 0.1 + (2 * 0.08 + pi * 0.04), 0.02},
    // legs 300x60 and 60x140, R15 fillet adds (r^2 - pi r^2 / 4), its arc replaces 2r of straight edge
    {"l-bracket", 0.3 * 0.06 + 0.06 * 0.14 + (0.015 * 0.015 - pi * 0.015 * 0.015 / 4),
     0.3 + 0.06 + 0.24 + 0.14 + 0.06 + 0.2 - 2 * 0.015 + pi * 0.015 / 2, 0.015},
    // right triangle 300x300 minus a R40 half disc on the hypotenuse
    {"knee-scallop", 0.3 * 0.3 / 2 - pi * 0.04 * 0.04 / 2, 0.6 + std::sqrt(2.0) * 0.3 - 0.08 + pi * 0.04, 0.04},
    // 350x300 minus 40x40 snipe triangle minus a 70-wide notch 100 deep to the centre of its R35 end
    {"collar-notch", 0.35 * 0.3 - 0.04 * 0.04 / 2 - (0.07 * 0.1 + pi * 0.035 * 0.035 / 2),
     2 * (0.35 + 0.3) - 0.08 + 0.04 * std::sqrt(2.0) - 0.07 + 0.2 + pi * 0.035, 0.035},
    {"ring-flange", pi*(0.25 * 0.25 - 0.15 * 0.15), 2 * pi*(0.25 + 0.15), 0.15},
    // trapezoid 500/300 x 250, slanted sides sqrt(0.1^2 + 0.25^2), five D30 holes
    {"trapezoid-holes", 0.8 / 2 * 0.25 - 5 * pi * 0.015 * 0.015, 0.8 + 2 * std::hypot(0.1, 0.25) + 5 * pi * 0.03,
     0.015},
};

// Analytic membership of the ideal parts (true arcs), scale 1, plate frame.
bool in_circle(double x, double y, double cx, double cy, double r) { return std::hypot(x - cx, y - cy) < r; }
bool ideal(const std::string& name, double x, double y) {
  if (name == "plate-hole-slot") {
    if (!(x > 0 && x < 0.4 && y > 0 && y < 0.25)) return false;
    if (in_circle(x, y, 0.12, 0.125, 0.05)) return false;
    const bool slot = (x > 0.25 && x < 0.33 && std::abs(y - 0.125) < 0.02) || in_circle(x, y, 0.25, 0.125, 0.02) ||
                      in_circle(x, y, 0.33, 0.125, 0.02);
    return !slot;
  }
  if (name == "l-bracket") {
    const bool legs = (x > 0 && x < 0.3 && y > 0 && y < 0.06) || (x > 0 && x < 0.06 && y > 0 && y < 0.2);
    const bool fillet = x >= 0.06 && x < 0.075 && y >= 0.06 && y < 0.075 && !in_circle(x, y, 0.075, 0.075, 0.015);
    return legs || fillet;
  }
  if (name == "knee-scallop") return x > 0 && y > 0 && x + y < 0.3 && !in_circle(x, y, 0.15, 0.15, 0.04);
  if (name == "collar-notch") {
    if (!(x > 0 && x < 0.35 && y > 0 && y < 0.3) || x + y < 0.04) return false;
    const bool notch = (std::abs(x - 0.175) < 0.035 && y > 0.2) || in_circle(x, y, 0.175, 0.2, 0.035);
    return !notch;
  }
  if (name == "ring-flange") {
    const double r = std::hypot(x - 0.25, y - 0.25);
    return r < 0.25 && r > 0.15;
  }
  if (name == "trapezoid-holes") {
    if (!(y > 0 && y < 0.25 && x > 0.1 * y / 0.25 && x < 0.5 - 0.1 * y / 0.25)) return false;
    const double c[5][2] = {{0.15, 0.08}, {0.25, 0.08}, {0.35, 0.08}, {0.20, 0.17}, {0.30, 0.17}};
    for (const auto& h : c)
      if (in_circle(x, y, h[0], h[1], 0.015)) return false;
    return true;
  }
  throw std::logic_error("no ideal shape " + name);
}
}  // namespace

TEST(PartgenShapes, CatalogueHasTheSixRequiredParts) {
  const auto names = shape_names();
  ASSERT_EQ(names.size(), std::size(kExpect));
  for (size_t i = 0; i < names.size(); ++i) EXPECT_EQ(names[i], kExpect[i].name);
}

TEST(PartgenShapes, AreaAndPerimeterMatchClosedFormAtSeveralScales) {
  for (double scale : {0.25, 1.0, 3.0}) {
    for (const Expect& e : kExpect) {
      SCOPED_TRACE(std::string(e.name) + " scale " + std::to_string(scale));
      const Shape s = make_shape(e.name, scale);
      const double area = e.area * scale * scale, perimeter = e.perimeter * scale;
      EXPECT_NEAR(s.exact_area, area, 1e-12 * area);
      EXPECT_NEAR(s.exact_perimeter, perimeter, 1e-12 * perimeter);
      // Each chord of an inscribed polygon is within tol of its arc, so the area differs by less than
      // (boundary length) x tol; a chord is shorter than its arc by under arc x tol / r.
      EXPECT_NEAR(polygon_area(s.polygon), area, perimeter * tol);
      const double pp = polygon_perimeter(s.polygon);
      EXPECT_LE(pp, perimeter * (1 + 1e-12));
      EXPECT_GE(pp, perimeter * (1 - tol / (e.min_radius * scale)));
    }
  }
}

TEST(PartgenShapes, RingsAreOrientedAndHolesLieInside) {
  for (const Shape& s : catalogue()) {
    SCOPED_TRACE(s.name);
    EXPECT_GT(signed_area(s.polygon.outer), 0);
    EXPECT_EQ(static_cast<int>(s.polygon.holes.size()), s.exact_hole_count);
    PolygonWithHoles outer_only{s.polygon.outer, {}};
    for (const Ring& h : s.polygon.holes) {
      EXPECT_LT(signed_area(h), 0);
      for (const Vec2& p : h) EXPECT_TRUE(contains(outer_only, p.x(), p.y()));
    }
  }
}

TEST(PartgenShapes, CircleChordsStayWithinTolerance) {
  // Ring flange at an awkward scale: every vertex on its circle, every chord midpoint within tol.
  for (double scale : {0.1, 1.0, 4.0}) {
    const Shape s = make_shape("ring-flange", scale);
    const Vec2 c(0.25 * scale, 0.25 * scale);
    auto check = [&](const Ring& r, double radius) {
      for (size_t i = 0; i < r.size(); ++i) {
        const Vec2& a = r[i];
        const Vec2& b = r[(i + 1) % r.size()];
        EXPECT_NEAR((a - c).norm(), radius, 1e-12);
        const double mid = ((a + b) / 2 - c).norm();
        EXPECT_LE(radius - mid, tol);
        EXPECT_GE(radius - mid, 0);
      }
    };
    check(s.polygon.outer, 0.25 * scale);
    check(s.polygon.holes.at(0), 0.15 * scale);
  }
}

TEST(PartgenShapes, ContainsKnownProbes) {
  struct Probe {
    const char* shape;
    double x, y;
    bool inside;
  };
  const Probe probes[] = {
      {"plate-hole-slot", 0.01, 0.01, true},    {"plate-hole-slot", 0.12, 0.125, false},
      {"plate-hole-slot", 0.29, 0.144, false},  {"plate-hole-slot", 0.29, 0.146, true},
      {"plate-hole-slot", 0.235, 0.125, false}, {"plate-hole-slot", 0.225, 0.125, true},
      {"plate-hole-slot", -0.001, 0.1, false},  {"plate-hole-slot", 0.401, 0.1, false},
      {"l-bracket", 0.2, 0.03, true},           {"l-bracket", 0.2, 0.1, false},
      {"l-bracket", 0.03, 0.15, true},          {"l-bracket", 0.062, 0.062, true},
      {"l-bracket", 0.07, 0.07, false},         {"knee-scallop", 0.05, 0.05, true},
      {"knee-scallop", 0.15, 0.15, false},      {"knee-scallop", 0.12, 0.15, false},
      {"knee-scallop", 0.1, 0.1, true},         {"knee-scallop", 0.2, 0.2, false},
      {"knee-scallop", 0.05, 0.24, true},       {"collar-notch", 0.175, 0.28, false},
      {"collar-notch", 0.175, 0.17, false},     {"collar-notch", 0.175, 0.16, true},
      {"collar-notch", 0.01, 0.01, false},      {"collar-notch", 0.03, 0.03, true},
      {"ring-flange", 0.25, 0.25, false},       {"ring-flange", 0.45, 0.25, true},
      {"ring-flange", 0.51, 0.25, false},       {"ring-flange", 0.399, 0.25, false},
      {"trapezoid-holes", 0.25, 0.08, false},   {"trapezoid-holes", 0.01, 0.2, false},
      {"trapezoid-holes", 0.09, 0.2, true},     {"trapezoid-holes", 0.25, 0.12, true},
  };
  for (const Probe& p : probes) {
    EXPECT_EQ(contains(make_shape(p.shape), p.x, p.y), p.inside) << p.shape << " at " << p.x << ", " << p.y;
    EXPECT_EQ(ideal(p.shape, p.x, p.y), p.inside) << "test's own model: " << p.shape;
  }
}

TEST(PartgenShapes, ContainsBoundaryRuleIsHalfOpen) {
  // Documented tie rule (shared with the rasteriser, so parts sharing an edge never both claim a pixel):
  // left and bottom edges are inside, right and top edges outside. Plate outer edge: 0..0.4 x 0..0.25.
  const Shape s = make_shape("plate-hole-slot");
  EXPECT_TRUE(contains(s, 0.0, 0.1));
  EXPECT_FALSE(contains(s, 0.4, 0.1));
  EXPECT_TRUE(contains(s, 0.2, 0.0));
  EXPECT_FALSE(contains(s, 0.2, 0.25));
  EXPECT_TRUE(contains(s, 0.0, 0.0));
  EXPECT_FALSE(contains(s, 0.4, 0.25));
}

TEST(PartgenShapes, ContainsAgreesWithAnalyticPartsAwayFromTheBoundary) {
  std::mt19937_64 rng(42);
  for (const Shape& s : catalogue()) {
    SCOPED_TRACE(s.name);
    const Box b = bounding_box(s.polygon);
    std::uniform_real_distribution<double> ux(b.min_x - 0.01, b.max_x + 0.01), uy(b.min_y - 0.01, b.max_y + 0.01);
    int compared = 0, inside = 0;
    for (int i = 0; i < 20000; ++i) {
      const double x = ux(rng), y = uy(rng), d = 2 * tol;
      const bool v = ideal(s.name, x, y);
      // Only points whose neighbourhood (2 chord tolerances) is on one side are decided.
      bool uniform = true;
      for (int k = 0; k < 8 && uniform; ++k)
        uniform = ideal(s.name, x + d * std::cos(k * pi / 4), y + d * std::sin(k * pi / 4)) == v;
      if (!uniform) continue;
      ++compared;
      inside += v;
      ASSERT_EQ(contains(s, x, y), v) << x << ", " << y;
    }
    EXPECT_GT(compared, 19000);
    EXPECT_GT(inside, 5000);
  }
}

TEST(PartgenShapes, PoseMovesPolygonRigidly) {
  const Shape s = make_shape("knee-scallop");
  const Pose pose{0.7, Vec2(1.5, -2.0)};
  const PolygonWithHoles moved = transform(s.polygon, pose);
  EXPECT_NEAR(polygon_area(moved), polygon_area(s.polygon), 1e-12);
  EXPECT_NEAR(polygon_perimeter(moved), polygon_perimeter(s.polygon), 1e-12);
  // The right-angle corner (0,0) lands on the translation; the (0.3,0) corner at angle 0.7.
  EXPECT_NEAR((moved.outer[0] - Vec2(1.5, -2.0)).norm(), 0, 1e-15);
  EXPECT_NEAR((moved.outer[1] - Vec2(1.5 + 0.3 * std::cos(0.7), -2.0 + 0.3 * std::sin(0.7))).norm(), 0, 1e-15);
  // A point inside stays inside after moving it the same way.
  const Vec2 q = pose.apply(Vec2(0.05, 0.05));
  EXPECT_TRUE(contains(moved, q.x(), q.y()));
}

TEST(PartgenShapes, SceneRejectsOverlapsAndSumsParts) {
  Scene scene = demo_scene();
  ASSERT_EQ(scene.parts.size(), 4u);
  double area = 0;
  for (const auto& p : scene.parts) area += make_shape(p.shape.name).exact_area;
  EXPECT_NEAR(scene.total_area(), area, 1e-15);
  const Shape f = make_shape("ring-flange");
  EXPECT_THROW(scene.add_part(f, scene.parts[3].pose), std::invalid_argument);
}

TEST(PartgenShapes, BadNamesAndScalesAreClearErrors) {
  try {
    make_shape("dinghy");
    FAIL() << "no exception";
  } catch (const std::invalid_argument& e) {
    EXPECT_NE(std::string(e.what()).find("dinghy"), std::string::npos);
    EXPECT_NE(std::string(e.what()).find("ring-flange"), std::string::npos);
  }
  EXPECT_THROW(make_shape("ring-flange", 0.0), std::invalid_argument);
  EXPECT_THROW(make_shape("ring-flange", -1.0), std::invalid_argument);
  EXPECT_THROW(make_shape("ring-flange", NAN), std::invalid_argument);
}
