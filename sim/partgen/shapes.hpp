// Hull-part shapes as exact polygons with holes, plus the analytic area and perimeter of the ideal
// (curved) part so tests can compare against a closed form. Shared by the cloud generator (hg-gen) and
// the camera bridge's scene renderer, so nothing here depends on how the part is later sampled.
//
// Conventions: metres; plate frame x right, y up; outer ring counter-clockwise, holes clockwise;
// rings are open (the last vertex is not repeated). Curves are polygonised with vertices ON the curve
// (inscribed), with sagitta (chord error) <= kChordTolerance.
#pragma once

#include <Eigen/Core>

#include <cstddef>
#include <string>
#include <string_view>
#include <vector>

#include "polygon/polygon.hpp"

namespace hg::partgen {

using Vec2 = Eigen::Vector2d;
using Ring = std::vector<Vec2>;

struct PolygonWithHoles {
  Ring outer;               // counter-clockwise
  std::vector<Ring> holes;  // each clockwise, strictly inside outer, disjoint
};

// Largest distance between a polygonised curve and the true curve (0.05 mm).
inline constexpr double kChordTolerance = 0.05e-3;

struct Shape {
  std::string name;
  std::string description;
  double scale = 1.0;          // every length of the nominal part is multiplied by this
  double thickness = 0.012;    // plate thickness in metres (top surface height above the table)
  PolygonWithHoles polygon;    // in the plate frame
  double exact_area = 0;       // analytic area of the ideal part (curves as true arcs)
  double exact_perimeter = 0;  // analytic length of every boundary (outer + holes)
  int exact_hole_count = 0;    // cut-outs that do not touch the outer edge
};

// Signed area (positive for counter-clockwise) and length of a closed ring (polygon/polygon.hpp).
using polygon::ring_length;
using polygon::signed_area;
// Area of the polygon (outer minus holes) and total boundary length.
double polygon_area(const PolygonWithHoles& poly);
double polygon_perimeter(const PolygonWithHoles& poly);

// Even-odd point-in-polygon over outer ring and holes. A point on a left/bottom edge counts as inside
// and on a right/top edge as outside (half-open rule, the same one the rasteriser uses), so the answer
// is deterministic even exactly on the boundary.
bool contains(const PolygonWithHoles& poly, double x, double y);
// The crossing rule contains() and the rasteriser share: edge a-b crosses the horizontal line at y when
// exactly one end lies strictly above it; the crossing's x is computed from the lower end, so its rounding
// does not depend on the ring's direction.
inline bool edge_crosses(const Vec2& a, const Vec2& b, double y) { return (a.y() > y) != (b.y() > y); }
double crossing_x(const Vec2& a, const Vec2& b, double y);
inline bool contains(const Shape& shape, double x, double y) { return contains(shape.polygon, x, y); }

// Names of every shape of the catalogue, in catalogue order.
std::vector<std::string> shape_names();
// One of each shape at the given scale.
std::vector<Shape> catalogue(double scale = 1.0);
// Fixtures of the cell (not hull parts): "calibration-plate", the hand-eye calibration target. make_shape
// makes them too; they are not in shape_names() / catalogue(), the test pieces.
std::vector<std::string> fixture_names();
struct CalibrationHole {
  std::string id;   // "H1".."H6", as on the drawing
  Vec2 centre;      // plate frame, metres
  double diameter;  // metres
};
// The calibration plate's drawing (docs/calibration.md) at the given scale.
std::vector<CalibrationHole> calibration_plate_holes(double scale = 1.0);
// Throws std::invalid_argument naming the shape (and listing the valid names) when unknown, or when
// scale is not a positive finite number.
Shape make_shape(std::string_view name, double scale = 1.0);

// Number of segments needed for an arc of radius r and angle |sweep| so that the sagitta <= tol.
int arc_segments(double radius, double sweep, double tol = kChordTolerance);
// Appends the arc centre + r (cos t, sin t) for t from start to start+sweep to ring, including both
// end points unless skip_first (so consecutive pieces do not repeat a vertex).
void append_arc(Ring& ring, const Vec2& centre, double radius, double start, double sweep, bool skip_first,
                double tol = kChordTolerance);

// Rigid placement on the table: p' = R(theta) p + translation.
struct Pose {
  double theta = 0;  // radians, counter-clockwise
  Vec2 translation = Vec2::Zero();
  Vec2 apply(const Vec2& p) const;
};
PolygonWithHoles transform(const PolygonWithHoles& poly, const Pose& pose);

struct Box {
  double min_x, min_y, max_x, max_y;
};
Box bounding_box(const PolygonWithHoles& poly);

// A part placed on the table, with its polygon already transformed to the table frame.
struct PlacedPart {
  Shape shape;
  Pose pose;
  PolygonWithHoles placed;  // shape.polygon transformed by pose
};

// Several parts on one table. Parts must not overlap: add_part throws std::invalid_argument when the
// new part's bounding box meets an existing part's bounding box (a conservative but simple test).
struct Scene {
  std::vector<PlacedPart> parts;
  void add_part(const Shape& shape, const Pose& pose);
  double total_area() const;       // exact, sum over parts
  double total_perimeter() const;  // exact, sum over parts
};

// A part rotated by rotation_rad about its bounding-box centre and then placed so that its bounding box
// centre lands on `centre`.
Pose pose_about_centre(const Shape& shape, double rotation_rad, const Vec2& centre);
// One part alone, rotated about its bounding-box centre, bounding-box centre at the origin of the table.
Scene single_part_scene(const Shape& shape, double rotation_rad = 0.0);
// A table with several different parts at once (plate, L bracket, knee, flange), spaced apart.
Scene demo_scene(double scale = 1.0);

}  // namespace hg::partgen
