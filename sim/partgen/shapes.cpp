#include "sim/partgen/shapes.hpp"

#include <algorithm>
#include <cmath>
#include <numbers>
#include <span>
#include <stdexcept>

namespace hg::partgen {

namespace {
constexpr double kPi = std::numbers::pi;

Ring reversed(Ring r) {
  std::reverse(r.begin(), r.end());
  return r;
}

// Full circle as an open ring; clockwise for a hole.
Ring circle_ring(const Vec2& c, double r, bool clockwise) {
  Ring ring;
  append_arc(ring, c, r, 0.0, clockwise ? -2 * kPi : 2 * kPi, false);
  ring.pop_back();  // the end point repeats the start
  return ring;
}

// Obround (stadium) slot: two semicircles of radius r whose centres are `length` apart along x.
Ring obround_ccw(const Vec2& c, double length, double r) {
  Ring ring;
  const Vec2 right = c + Vec2(length / 2, 0), left = c - Vec2(length / 2, 0);
  append_arc(ring, right, r, -kPi / 2, kPi, false);
  append_arc(ring, left, r, kPi / 2, kPi, false);
  return ring;
}

// (a) rectangular plate with a circular lightening hole and an obround slot.
Shape plate_hole_slot(double s) {
  const double W = 0.40 * s, H = 0.25 * s, r = 0.05 * s, L = 0.08 * s, rs = 0.02 * s;
  Shape sh;
  sh.name = "plate-hole-slot";
  sh.description = "rectangular plate 400x250 with a D100 lightening hole and a 120x40 obround slot";
  sh.thickness = 0.012;
  sh.polygon.outer = {{0, 0}, {W, 0}, {W, H}, {0, H}};
  sh.polygon.holes.push_back(circle_ring({0.12 * s, H / 2}, r, true));
  sh.polygon.holes.push_back(reversed(obround_ccw({0.29 * s, H / 2}, L, rs)));
  sh.exact_area = W * H - kPi * r * r - (L * 2 * rs + kPi * rs * rs);
  sh.exact_perimeter = 2 * (W + H) + 2 * kPi * r + (2 * L + 2 * kPi * rs);
  sh.exact_hole_count = 2;
  return sh;
}

// (b) L bracket with a concave fillet in the inner corner.
Shape l_bracket(double s) {
  const double Lx = 0.30 * s, Ly = 0.20 * s, t = 0.06 * s, r = 0.015 * s;
  Shape sh;
  sh.name = "l-bracket";
  sh.description = "L bracket, legs 300 and 200, width 60, R15 fillet in the inner corner";
  sh.thickness = 0.010;
  Ring& o = sh.polygon.outer;
  o = {{0, 0}, {Lx, 0}, {Lx, t}};
  append_arc(o, {t + r, t + r}, r, -kPi / 2, -kPi / 2, false);
  o.push_back({t, Ly});
  o.push_back({0, Ly});
  sh.exact_area = Lx * t + t * (Ly - t) + (r * r - kPi * r * r / 4);
  sh.exact_perimeter = 2 * (Lx + Ly) - 2 * r + kPi * r / 2;
  return sh;
}

// (c) triangular knee plate with a semicircular scallop cut into the middle of the hypotenuse.
Shape knee_scallop(double s) {
  const double a = 0.30 * s, b = 0.30 * s, r = 0.04 * s;
  Shape sh;
  sh.name = "knee-scallop";
  sh.description = "right-angled knee plate, legs 300 and 300, R40 semicircular scallop on the hypotenuse";
  sh.thickness = 0.016;
  const Vec2 A(a, 0), B(0, b), M = (A + B) / 2, u = (B - A).normalized();
  Ring& o = sh.polygon.outer;
  o = {{0, 0}, A};
  // Sweep clockwise from the start point through the side facing the right angle (into the plate).
  append_arc(o, M, r, std::atan2(-u.y(), -u.x()), -kPi, false);
  o.push_back(B);
  const double hyp = std::hypot(a, b);
  sh.exact_area = a * b / 2 - kPi * r * r / 2;
  sh.exact_perimeter = a + b + (hyp - 2 * r) + kPi * r;
  return sh;
}

// (d) collar plate: rectangle with a slot notch open to the top edge, rounded at its end, and a sniped
// (chamfered) bottom-left corner.
Shape collar_notch(double s) {
  const double W = 0.35 * s, H = 0.30 * s, r = 0.035 * s, d = 0.10 * s, c = 0.04 * s, cx = W / 2;
  Shape sh;
  sh.name = "collar-notch";
  sh.description = "collar plate 350x300, notch 70 wide open to the top edge with R35 end, 40x40 snipe";
  sh.thickness = 0.008;
  Ring& o = sh.polygon.outer;
  o = {{c, 0}, {W, 0}, {W, H}, {cx + r, H}};
  append_arc(o, {cx, H - d}, r, 0.0, -kPi, false);
  o.push_back({cx - r, H});
  o.push_back({0, H});
  o.push_back({0, c});
  sh.exact_area = W * H - c * c / 2 - (2 * r * d + kPi * r * r / 2);
  sh.exact_perimeter = 2 * (W + H) - 2 * c + c * std::sqrt(2.0) - 2 * r + 2 * d + kPi * r;
  return sh;
}

// (e) ring flange (annulus).
Shape ring_flange(double s) {
  const double R = 0.25 * s, r = 0.15 * s;
  Shape sh;
  sh.name = "ring-flange";
  sh.description = "ring flange, outer D500, inner D300";
  sh.thickness = 0.025;
  sh.polygon.outer = circle_ring({R, R}, R, false);
  sh.polygon.holes.push_back(circle_ring({R, R}, r, true));
  sh.exact_area = kPi * (R * R - r * r);
  sh.exact_perimeter = 2 * kPi * (R + r);
  sh.exact_hole_count = 1;
  return sh;
}

// (f) isosceles trapezoid with five small round holes.
Shape trapezoid_holes(double s) {
  const double B = 0.50 * s, T = 0.30 * s, H = 0.25 * s, r = 0.015 * s, inset = (B - T) / 2;
  Shape sh;
  sh.name = "trapezoid-holes";
  sh.description = "trapezoid, base 500, top 300, height 250, five D30 holes";
  sh.thickness = 0.006;
  sh.polygon.outer = {{0, 0}, {B, 0}, {B - inset, H}, {inset, H}};
  const double centres[5][2] = {{0.15, 0.08}, {0.25, 0.08}, {0.35, 0.08}, {0.20, 0.17}, {0.30, 0.17}};
  for (const auto& c : centres) sh.polygon.holes.push_back(circle_ring({c[0] * s, c[1] * s}, r, true));
  sh.exact_area = (B + T) / 2 * H - 5 * kPi * r * r;
  sh.exact_perimeter = B + T + 2 * std::hypot(inset, H) + 5 * 2 * kPi * r;
  sh.exact_hole_count = 5;
  return sh;
}

// Calibration target (docs/calibration.md): plate with drilled holes of distinct diameters.
Shape calibration_plate(double s) {
  const double W = 0.42 * s, H = 0.30 * s;
  Shape sh;
  sh.name = "calibration-plate";
  sh.description = "calibration plate 420x300x10, six drilled holes D30..D80 (docs/calibration.md)";
  sh.thickness = 0.010;
  sh.polygon.outer = {{0, 0}, {W, 0}, {W, H}, {0, H}};
  sh.exact_area = W * H;
  sh.exact_perimeter = 2 * (W + H);
  for (const CalibrationHole& h : calibration_plate_holes(s)) {
    sh.polygon.holes.push_back(circle_ring(h.centre, h.diameter / 2, true));
    sh.exact_area -= kPi * h.diameter * h.diameter / 4;
    sh.exact_perimeter += kPi * h.diameter;
  }
  sh.exact_hole_count = static_cast<int>(sh.polygon.holes.size());
  return sh;
}

using Maker = Shape (*)(double);
struct Entry {
  const char* name;
  Maker make;
};
constexpr Entry kShapes[] = {
    {"plate-hole-slot", plate_hole_slot}, {"l-bracket", l_bracket},     {"knee-scallop", knee_scallop},
    {"collar-notch", collar_notch},       {"ring-flange", ring_flange}, {"trapezoid-holes", trapezoid_holes},
};
// Fixtures: made by make_shape and listed by hg-gen, but not test pieces of the catalogue.
constexpr Entry kFixtures[] = {{"calibration-plate", calibration_plate}};
}  // namespace

std::vector<CalibrationHole> calibration_plate_holes(double s) {
  // The drawing of docs/calibration.md, mm: no two diameters closer than 10, no symmetry of the pattern.
  const double holes[6][3] = {{50, 50, 30},   {370, 50, 40},  {370, 250, 50},
                              {250, 110, 60}, {260, 230, 70}, {110, 190, 80}};
  std::vector<CalibrationHole> out;
  for (int k = 0; k < 6; ++k) {
    std::string id = "H";
    id += std::to_string(k + 1);
    out.push_back({id, Vec2(holes[k][0], holes[k][1]) * 1e-3 * s, holes[k][2] * 1e-3 * s});
  }
  return out;
}

std::vector<std::string> fixture_names() {
  std::vector<std::string> names;
  for (const Entry& e : kFixtures) names.emplace_back(e.name);
  return names;
}

double polygon_area(const PolygonWithHoles& poly) {
  double a = std::abs(signed_area(poly.outer));
  for (const Ring& h : poly.holes) a -= std::abs(signed_area(h));
  return a;
}

double polygon_perimeter(const PolygonWithHoles& poly) {
  double l = ring_length(poly.outer);
  for (const Ring& h : poly.holes) l += ring_length(h);
  return l;
}

double crossing_x(const Vec2& a, const Vec2& b, double y) {
  const Vec2& lo = a.y() < b.y() ? a : b;
  const Vec2& hi = a.y() < b.y() ? b : a;
  return lo.x() + (y - lo.y()) * (hi.x() - lo.x()) / (hi.y() - lo.y());
}

static bool ring_parity(const Ring& ring, double x, double y) {
  bool odd = false;
  const size_t n = ring.size();
  for (size_t i = 0, j = n - 1; i < n; j = i++)
    if (edge_crosses(ring[j], ring[i], y) && x < crossing_x(ring[j], ring[i], y)) odd = !odd;
  return odd;
}

bool contains(const PolygonWithHoles& poly, double x, double y) {
  bool odd = ring_parity(poly.outer, x, y);
  for (const Ring& h : poly.holes) odd ^= ring_parity(h, x, y);
  return odd;
}

int arc_segments(double radius, double sweep, double tol) {
  // Sagitta of a chord spanning angle phi: r (1 - cos(phi / 2)).
  const double ratio = 1.0 - tol / radius;
  const double max_phi = ratio <= -1.0 ? 2 * kPi : 2.0 * std::acos(std::max(-1.0, ratio));
  const int n = static_cast<int>(std::ceil(std::abs(sweep) / max_phi));
  return std::max(n, std::abs(sweep) > kPi ? 8 : 2);
}

void append_arc(Ring& ring, const Vec2& centre, double radius, double start, double sweep, bool skip_first,
                double tol) {
  const int n = arc_segments(radius, sweep, tol);
  for (int k = skip_first ? 1 : 0; k <= n; ++k) {
    const double t = start + sweep * k / n;
    ring.emplace_back(centre.x() + radius * std::cos(t), centre.y() + radius * std::sin(t));
  }
}

std::vector<std::string> shape_names() {
  std::vector<std::string> names;
  for (const Entry& e : kShapes) names.emplace_back(e.name);
  return names;
}

std::vector<Shape> catalogue(double scale) {
  std::vector<Shape> all;
  for (const Entry& e : kShapes) all.push_back(make_shape(e.name, scale));
  return all;
}

Shape make_shape(std::string_view name, double scale) {
  if (!(scale > 0) || !std::isfinite(scale))
    throw std::invalid_argument("shape scale must be a positive finite number, got " + std::to_string(scale));
  for (const auto& table : {std::span<const Entry>(kShapes), std::span<const Entry>(kFixtures)}) {
    for (const Entry& e : table) {
      if (name == e.name) {
        Shape s = e.make(scale);
        s.scale = scale;
        return s;
      }
    }
  }
  std::string valid;
  for (const Entry& e : kShapes) valid += std::string(valid.empty() ? "" : ", ") + e.name;
  for (const Entry& e : kFixtures) valid += std::string(", ") + e.name;
  throw std::invalid_argument("unknown shape '" + std::string(name) + "' (valid: " + valid + ")");
}

Vec2 Pose::apply(const Vec2& p) const {
  const double c = std::cos(theta), s = std::sin(theta);
  return {c * p.x() - s * p.y() + translation.x(), s * p.x() + c * p.y() + translation.y()};
}

PolygonWithHoles transform(const PolygonWithHoles& poly, const Pose& pose) {
  PolygonWithHoles out;
  out.outer.reserve(poly.outer.size());
  for (const Vec2& p : poly.outer) out.outer.push_back(pose.apply(p));
  for (const Ring& h : poly.holes) {
    Ring& r = out.holes.emplace_back();
    r.reserve(h.size());
    for (const Vec2& p : h) r.push_back(pose.apply(p));
  }
  return out;
}

Box bounding_box(const PolygonWithHoles& poly) {
  Box b{INFINITY, INFINITY, -INFINITY, -INFINITY};
  for (const Vec2& p : poly.outer) {  // holes lie inside the outer ring
    b.min_x = std::min(b.min_x, p.x());
    b.min_y = std::min(b.min_y, p.y());
    b.max_x = std::max(b.max_x, p.x());
    b.max_y = std::max(b.max_y, p.y());
  }
  return b;
}

void Scene::add_part(const Shape& shape, const Pose& pose) {
  PlacedPart part{shape, pose, transform(shape.polygon, pose)};
  const Box nb = bounding_box(part.placed);
  for (size_t i = 0; i < parts.size(); ++i) {
    const Box ob = bounding_box(parts[i].placed);
    if (nb.min_x <= ob.max_x && ob.min_x <= nb.max_x && nb.min_y <= ob.max_y && ob.min_y <= nb.max_y)
      throw std::invalid_argument("part " + std::to_string(parts.size()) + " (" + shape.name +
                                  ") overlaps the bounding box of part " + std::to_string(i) + " (" +
                                  parts[i].shape.name + ")");
  }
  parts.push_back(std::move(part));
}

double Scene::total_area() const {
  double a = 0;
  for (const PlacedPart& p : parts) a += p.shape.exact_area;
  return a;
}

double Scene::total_perimeter() const {
  double l = 0;
  for (const PlacedPart& p : parts) l += p.shape.exact_perimeter;
  return l;
}

Pose pose_about_centre(const Shape& shape, double rotation_rad, const Vec2& centre) {
  const Box b = bounding_box(shape.polygon);
  const Vec2 c((b.min_x + b.max_x) / 2, (b.min_y + b.max_y) / 2);
  Pose pose;
  pose.theta = rotation_rad;
  pose.translation = centre - Pose{rotation_rad, Vec2::Zero()}.apply(c);
  return pose;
}

Scene single_part_scene(const Shape& shape, double rotation_rad) {
  Scene scene;
  scene.add_part(shape, pose_about_centre(shape, rotation_rad, Vec2::Zero()));
  return scene;
}

Scene demo_scene(double scale) {
  Scene scene;
  const double s = scale;
  scene.add_part(make_shape("plate-hole-slot", s),
                 pose_about_centre(make_shape("plate-hole-slot", s), 0.05, Vec2(-0.33, 0.22) * s));
  const Shape l = make_shape("l-bracket", s);
  scene.add_part(l, pose_about_centre(l, -0.12, Vec2(0.30, 0.24) * s));
  const Shape k = make_shape("knee-scallop", s);
  scene.add_part(k, pose_about_centre(k, 0.30, Vec2(-0.30, -0.24) * s));
  const Shape f = make_shape("ring-flange", s);
  scene.add_part(f, pose_about_centre(f, 0.0, Vec2(0.30, -0.26) * s));
  return scene;
}

}  // namespace hg::partgen
