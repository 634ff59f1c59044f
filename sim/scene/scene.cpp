#include "sim/scene/scene.hpp"

#include <algorithm>
#include <cmath>
#include <stdexcept>

#include <nlohmann/json.hpp>

#include "sim/partgen/synth.hpp"
#include "sim/partgen/writers.hpp"
#include "sim/scene/effects.hpp"

namespace hg::sim {

namespace {

std::string join(const std::vector<std::string>& names) {
  std::string s;
  for (const auto& n : names) s += (s.empty() ? "" : ", ") + n;
  return s;
}

CameraProfile make_profile(std::string name, int w, int h, double hfov_deg, double mount, double unit, double a,
                           double b, double dropout, double flying) {
  CameraProfile p;
  p.name = std::move(name);
  p.width = w;
  p.height = h;
  p.fx = p.fy = (w / 2.0) / std::tan(hfov_deg * M_PI / 360.0);  // square pixels
  p.cx = (w - 1) / 2.0;  // pixel centres at integer coordinates (OpenCV convention)
  p.cy = (h - 1) / 2.0;
  p.mount_height = mount;
  p.depth_unit = unit;
  p.noise_a = a;
  p.noise_b = b;
  p.dropout = dropout;
  p.flying_pixel_prob = flying;
  return p;
}

// Depth from the camera along the optical axis (z) at which the ray through pixel (u, v) meets the plane
// n . p = offset; the ray direction is ((u - cx) / fx, (v - cy) / fy, 1).
inline double plane_z(const Eigen::Vector3d& n, double offset, double a, double b) {
  return offset / (n.x() * a + n.y() * b + n.z());
}

}  // namespace

// Assumptions (plausible, not vendor data sheets):
//  pm806: PM806-class structured-light camera, 1280x960, ~60 deg horizontal field of view, mounted 1.5 m
//    above the table (view 1.73 x 1.30 m, ~1.35 mm per pixel on the table), depth in millimetre counts,
//    sigma(z) = 0.3 mm + 0.4 mm/m^2 z^2 (1.2 mm at 1.5 m), 1 % dropout.
//  lsr-l: LSR-L-class laser structured light, 2048x1536, ~45 deg horizontal field of view, mounted 2.0 m
//    above the table (view 1.66 x 1.24 m, ~0.8 mm per pixel), 0.1 mm depth counts,
//    sigma(z) = 0.1 mm + 0.05 mm/m^2 z^2 (0.3 mm at 2 m), 0.5 % dropout.
//  m130: a Zivid 2+ M130 structured-light camera (docs/scene.md cites its data sheet for the sensor and the
//    pixel spacing), 2448x2048, 0.32 mm between pixels at 1.3 m, mounted 1.6 m above the table (view 0.96 x
//    0.81 m, ~0.39 mm per pixel), 0.1 mm depth counts; assumed: sigma(z) = 0.05 mm + 0.05 mm/m^2 z^2 (0.18 mm at
//    1.6 m), 0.5 % dropout.
//  All: 30 % of the pixels at a depth edge return a mixed depth between the two surfaces.
// The principle and its constants (used only by SensorEffects; docs/scene.md gives the reasons):
//  pm806: structured light (a projector beside the depth camera; an active-stereo camera's second view
//    stands in the same place): its light and its second line of sight 0.10 m along the camera's x; an
//    incoherent pattern averages ~4 speckle cells per pixel; detection at 3 % of the return of a grey face
//    met square on; saturation at 3 times it; the matching window blurs ~2 pixels.
//  lsr-l: laser triangulation: the laser's scanning mirror 0.35 m along the camera's x (a triangulation
//    angle of ~10 deg at 2 m); coherent light, ~2 speckle cells per pixel; detection at 2 %; saturation at 3
//    times; the laser line ~1.5 pixels wide.
//  m130: structured light, its projector 0.13 m along the camera's x (assumed); otherwise as pm806.
CameraProfile camera_profile(const std::string& name) {
  if (name == "pm806") {
    CameraProfile p = make_profile("pm806", 1280, 960, 60.0, 1.5, 0.001, 0.3e-3, 0.4e-3, 0.01, 0.3);
    p.principle = "structured-light";
    p.emitter = Eigen::Vector3d(0.10, 0, 0);
    p.return_threshold = 0.03, p.speckle_cells = 4, p.saturation = 3.0, p.footprint_px = 2.0;
    return p;
  }
  if (name == "lsr-l") {
    CameraProfile p = make_profile("lsr-l", 2048, 1536, 45.0, 2.0, 0.0001, 0.1e-3, 0.05e-3, 0.005, 0.3);
    p.principle = "laser-triangulation";
    p.emitter = Eigen::Vector3d(0.35, 0, 0);
    p.return_threshold = 0.02, p.speckle_cells = 2, p.saturation = 3.0, p.footprint_px = 1.5;
    return p;
  }
  if (name == "m130") {
    // Zivid 2+ M130: 2448 x 2048 and 0.32 mm between pixels at 1300 mm (data sheet), so fx = 1.3 / 0.32e-3.
    const double fx = 1.300 / 0.32e-3, hfov = 2 * std::atan(1224.0 / fx) * 180 / M_PI;
    CameraProfile p = make_profile("m130", 2448, 2048, hfov, 1.6, 0.0001, 0.05e-3, 0.05e-3, 0.005, 0.3);
    p.principle = "structured-light";
    p.emitter = Eigen::Vector3d(0.13, 0, 0);
    p.return_threshold = 0.03, p.speckle_cells = 4, p.saturation = 3.0, p.footprint_px = 2.0;
    return p;
  }
  throw std::invalid_argument("unknown camera profile '" + name + "' (known: " + join(camera_profile_names()) + ")");
}

std::vector<std::string> camera_profile_names() { return {"pm806", "lsr-l", "m130"}; }

namespace {
ScenePart catalogue_part(const std::string& shape, double x, double y, double theta) {
  ScenePart p;
  p.shape = shape;
  p.x = x;
  p.y = y;
  p.theta = theta;
  p.thickness = partgen::make_shape(shape).thickness;
  return p;
}
}  // namespace

std::vector<std::string> scene_preset_names() {
  std::vector<std::string> names{"empty"};
  for (const auto& s : partgen::shape_names()) names.push_back(s);
  names.push_back("three-parts");
  names.push_back("demo");
  for (const auto& s : partgen::shape_names()) names.push_back(s + "-realistic");
  return names;
}

// The values docs/scene.md derives: a perforated downdraft grinding table (8 mm holes on a 16 mm staggered
// pitch) with spatter and chips, 0.5 mm edge rounding, a third of each top face ground, 3 mm per metre bow.
SensorEffects realistic_effects() {
  SensorEffects fx;
  fx.incidence = true;
  fx.edge_radius = 0.0005;
  fx.specular = true;
  fx.mixed_pixels = true;
  fx.shadow = true;
  fx.table.kind = TableSpec::Kind::Perforated;
  fx.table.spatter_per_m2 = 300;
  fx.table.chips_per_m2 = 60;
  fx.warp = 0.003;
  fx.intensity = true;
  return fx;
}

SceneSpec scene_preset(const std::string& name) {
  SceneSpec spec;
  spec.name = name;
  spec.table_tilt_x = 0.012;  // ~0.7 deg and ~0.5 deg: a table that is level only to the eye
  spec.table_tilt_y = -0.009;
  spec.seed = 0x5EED0001;
  const auto shapes = partgen::shape_names();
  if (name == "empty") return spec;
  if (std::find(shapes.begin(), shapes.end(), name) != shapes.end()) {
    spec.parts.push_back(catalogue_part(name, 0.03, -0.02, 0.10));
    return spec;
  }
  const std::string suffix = "-realistic";
  if (name.size() > suffix.size() && name.compare(name.size() - suffix.size(), suffix.size(), suffix) == 0) {
    const std::string shape = name.substr(0, name.size() - suffix.size());
    if (std::find(shapes.begin(), shapes.end(), shape) != shapes.end()) {
      spec.parts.push_back(catalogue_part(shape, 0.03, -0.02, 0.10));
      spec.effects = realistic_effects();
      return spec;
    }
  }
  // Placements of partgen's demo scene; three-parts leaves out the knee.
  if (name == "three-parts" || name == "demo") {
    spec.parts.push_back(catalogue_part("plate-hole-slot", -0.33, 0.22, 0.05));
    spec.parts.push_back(catalogue_part("l-bracket", 0.30, 0.24, -0.12));
    if (name == "demo") spec.parts.push_back(catalogue_part("knee-scallop", -0.30, -0.24, 0.30));
    spec.parts.push_back(catalogue_part("ring-flange", 0.30, -0.26, 0.0));
    return spec;
  }
  throw std::invalid_argument("unknown scene '" + name + "' (known: " + join(scene_preset_names()) + ")");
}

namespace {

// Places the spec's parts on the table (validated through partgen::Scene, which rejects overlaps).
partgen::Scene place_parts(const SceneSpec& spec) {
  partgen::Scene scene;
  for (std::size_t k = 0; k < spec.parts.size(); ++k) {
    const ScenePart& p = spec.parts[k];
    partgen::Shape shape;
    if (!p.shape.empty()) {
      shape = partgen::make_shape(p.shape, p.scale);
    } else {
      if (p.polygon.outer.size() < 3)
        throw std::invalid_argument("scene part " + std::to_string(k) + ": no shape name and no polygon");
      shape.name = "polygon";
      shape.polygon = p.polygon;
    }
    if (!(p.thickness >= 0.006 && p.thickness <= 0.030))
      throw std::invalid_argument("scene part " + std::to_string(k) + ": thickness " + std::to_string(p.thickness) +
                                  " m outside 0.006..0.030");
    shape.thickness = p.thickness;
    scene.add_part(shape, partgen::pose_about_centre(shape, p.theta, {p.x, p.y}));
  }
  return scene;
}

}  // namespace

namespace {

// The ring with extra vertices so that no piece is longer than `step`.
partgen::Ring densify(const partgen::Ring& ring, double step) {
  partgen::Ring out;
  for (std::size_t i = 0; i < ring.size(); ++i) {
    const auto& a = ring[i];
    const auto& b = ring[(i + 1) % ring.size()];
    const int n = std::max(1, static_cast<int>(std::ceil((b - a).norm() / step)));
    for (int j = 0; j < n; ++j) out.push_back(a + (b - a) * (static_cast<double>(j) / n));
  }
  return out;
}

// Camera above the table origin looking down: camera x = table x, camera y = -table y, camera z = -table z;
// the table tilted about its x then y axis. Sets the pose and the table plane in the camera frame.
void place_camera(const SceneSpec& spec, const CameraProfile& prof, RenderedFrame& out) {
  const Eigen::Matrix3d flip = Eigen::Vector3d(1, -1, -1).asDiagonal();
  const Eigen::Matrix3d tilt = (Eigen::AngleAxisd(spec.table_tilt_x, Eigen::Vector3d::UnitX()) *
                                Eigen::AngleAxisd(spec.table_tilt_y, Eigen::Vector3d::UnitY()))
                                   .toRotationMatrix();
  out.camera_from_table.linear() = flip * tilt;
  out.camera_from_table.translation() = Eigen::Vector3d(0, 0, prof.mount_height);
  const Eigen::Isometry3d& T = out.camera_from_table;
  out.table_normal = T.linear() * Eigen::Vector3d::UnitZ();
  out.table_offset = out.table_normal.dot(T.translation());
}

// Each part's top face (z = thickness, polygons 0..n-1) and footprint (z = 0, polygons n..2n-1) projected
// into the image; the parts' polygons and thicknesses are recorded in `out`. A plane maps to the image by a
// homography, so straight edges stay straight and the even-odd spans of the projected rings are exactly
// the pixels whose centre ray meets the face (or, for the footprint, reaches the table inside it). A bowed
// part (SensorEffects::warp) is lifted by its bow: its rings are cut into 5 mm pieces first, each vertex at
// its own height, so the projection follows the curved face to well under a micrometre.
std::vector<partgen::PolygonWithHoles> project_parts(const partgen::Scene& scene, const SceneSpec& spec,
                                                     const CameraProfile& prof, const std::vector<detail::Warp>& warps,
                                                     RenderedFrame& out) {
  const int W = prof.width, H = prof.height;
  const int nparts = static_cast<int>(scene.parts.size());
  const Eigen::Isometry3d& T = out.camera_from_table;
  std::vector<partgen::PolygonWithHoles> image_polys(2 * nparts);
  auto project_ring = [&](const partgen::Ring& ring, double z, partgen::Ring& dst, int k) {
    const detail::Warp& w = warps[k];
    const partgen::Ring pts = w.s == 0 ? ring : densify(ring, 0.005);
    dst.reserve(pts.size());
    for (const auto& q : pts) {
      const Eigen::Vector3d p = T * Eigen::Vector3d(q.x(), q.y(), w.s == 0 ? z : z + w.height(q.x(), q.y()));
      const double u = prof.fx * p.x() / p.z() + prof.cx, v = prof.fy * p.y() / p.z() + prof.cy;
      if (!(p.z() > 0) || u < -0.5 || v < -0.5 || u > W - 0.5 || v > H - 0.5)
        throw std::invalid_argument("scene '" + spec.name + "': part " + std::to_string(k) +
                                    " lies outside the view of camera '" + prof.name + "'");
      dst.emplace_back(u, v);
    }
  };
  for (int k = 0; k < nparts; ++k) {
    const auto& placed = scene.parts[k].placed;
    const double t = scene.parts[k].shape.thickness;
    out.part_polygons.push_back(placed);
    out.part_thickness.push_back(t);
    for (int level = 0; level < 2; ++level) {
      auto& dst = image_polys[level * nparts + k];
      project_ring(placed.outer, level == 0 ? t : 0.0, dst.outer, k);
      for (const auto& h : placed.holes) project_ring(h, level == 0 ? t : 0.0, dst.holes.emplace_back(), k);
    }
  }
  return image_polys;
}

// Pixel ray directions ((c - cx) / fx, (r - cy) / fy, 1): a per column, b per row.
struct Rays {
  std::vector<double> a, b;
};

// The parts in one image row of the noise-free depth `zr` (metres, the table already there) and labels.
// Top faces first: nothing of a part is nearer to the camera than its top. Then rays that reach the table
// inside a footprint but miss the top face: they enter through a side wall (outer edge or a hole's). The
// entry is where the ray's table-frame point first falls inside the outline, found by bisection along the
// ray between the top-face and table heights.
void render_row(int r, const std::vector<partgen::Span>& spans, const Rays& ray, const RenderedFrame& out,
                const std::vector<detail::Warp>& warps, double* zr, std::uint8_t* lr) {
  const int W = static_cast<int>(ray.a.size());
  const int nparts = static_cast<int>(out.part_polygons.size());
  const Eigen::Vector3d& n = out.table_normal;
  const Eigen::Isometry3d table_from_camera = out.camera_from_table.inverse();
  auto columns = [&](const partgen::Span& s) {  // pixel centres c with x0 <= c < x1
    return std::pair{std::max(0, static_cast<int>(std::ceil(s.x0))), std::min(W, static_cast<int>(std::ceil(s.x1)))};
  };
  for (const auto& s : spans) {
    if (s.part >= nparts) continue;
    const double t = out.part_thickness[s.part];
    const auto [c0, c1] = columns(s);
    for (int c = c0; c < c1; ++c) {
      zr[c] = warps[s.part].s == 0 ? plane_z(n, out.table_offset + t, ray.a[c], ray.b[r])
                                   : detail::top_depth(out, warps[s.part], t, ray.a[c], ray.b[r]);
      lr[c] = static_cast<std::uint8_t>(s.part + 1);
    }
  }
  for (const auto& s : spans) {
    if (s.part < nparts) continue;
    const int k = s.part - nparts;
    const double t = out.part_thickness[k];
    const auto& poly = out.part_polygons[k];
    const auto [c0, c1] = columns(s);
    for (int c = c0; c < c1; ++c) {
      if (lr[c]) continue;
      const Eigen::Vector3d d(ray.a[c], ray.b[r], 1.0);
      double z_out = warps[k].s == 0 ? plane_z(n, out.table_offset + t, d.x(), d.y())
                                     : detail::top_depth(out, warps[k], t, d.x(), d.y()),
             z_in = zr[c];
      for (int it = 0; it < 30; ++it) {
        const double zm = 0.5 * (z_out + z_in);
        const Eigen::Vector3d q = table_from_camera * (zm * d);
        (partgen::contains(poly, q.x(), q.y()) ? z_in : z_out) = zm;
      }
      zr[c] = z_in;
      lr[c] = static_cast<std::uint8_t>(k + 1);
    }
  }
}

// Noise-free depth (metres) of table and parts; sets out.truth_labels. Pixels whose ray only grazes a
// part's corner between two walls (entering and leaving through walls without reaching table or top
// inside the footprint) are not modelled: slivers well under a pixel.
cv::Mat true_depth(const CameraProfile& prof, const std::vector<partgen::PolygonWithHoles>& image_polys,
                   const std::vector<detail::Warp>& warps, RenderedFrame& out) {
  const int W = prof.width, H = prof.height;
  Rays ray{std::vector<double>(W), std::vector<double>(H)};
  for (int c = 0; c < W; ++c) ray.a[c] = (c - prof.cx) / prof.fx;
  for (int r = 0; r < H; ++r) ray.b[r] = (r - prof.cy) / prof.fy;
  cv::Mat z_true(H, W, CV_64FC1);
  out.truth_labels = cv::Mat::zeros(H, W, CV_8UC1);
  for (int r = 0; r < H; ++r) {
    double* zr = z_true.ptr<double>(r);
    for (int c = 0; c < W; ++c) zr[c] = plane_z(out.table_normal, out.table_offset, ray.a[c], ray.b[r]);
  }
  if (image_polys.empty()) return z_true;
  std::vector<const partgen::PolygonWithHoles*> polys;
  for (const auto& p : image_polys) polys.push_back(&p);
  const partgen::SpanRasterizer raster(polys, H, -1.0, 8.0);
  std::vector<partgen::Span> spans;
  for (int r = 0; r < H; ++r) {
    raster.spans(r, spans);
    render_row(r, spans, ray, out, warps, z_true.ptr<double>(r), out.truth_labels.ptr<std::uint8_t>(r));
  }
  return z_true;
}

// Sensor effects, from one random stream per (seed, frame): mixed depths at edges, noise, dropout; then
// quantised to depth counts.
cv::Mat sensor_depth(const cv::Mat& z_true, const SceneSpec& spec, const CameraProfile& prof,
                     std::uint64_t frame_index) {
  const int W = z_true.cols, H = z_true.rows;
  partgen::Rng rng(partgen::stream_seed(spec.seed, frame_index));
  const double edge_jump = 0.003;  // a depth step larger than this between neighbours is an edge
  cv::Mat depth(H, W, CV_16UC1);
  for (int r = 0; r < H; ++r) {
    const double* zr = z_true.ptr<double>(r);
    std::uint16_t* dr = depth.ptr<std::uint16_t>(r);
    for (int c = 0; c < W; ++c) {
      double z = zr[c];
      const double u_drop = rng.uniform(), u_fly = rng.uniform(), u_mix = rng.uniform(), noise = rng.normal();
      // The neighbour across the largest depth step, if it is an edge.
      double other = z, step = edge_jump;
      auto consider = [&](double zn) {
        if (std::abs(zn - z) > step) {
          step = std::abs(zn - z);
          other = zn;
        }
      };
      if (c > 0) consider(zr[c - 1]);
      if (c + 1 < W) consider(zr[c + 1]);
      if (r > 0) consider(z_true.ptr<double>(r - 1)[c]);
      if (r + 1 < H) consider(z_true.ptr<double>(r + 1)[c]);
      if (other != z && u_fly < prof.flying_pixel_prob) z += u_mix * (other - z);
      z += (prof.noise_a + prof.noise_b * z * z) * noise;
      const double counts = std::round(z / prof.depth_unit);
      dr[c] = (u_drop < prof.dropout || !(counts > 0)) ? 0 : static_cast<std::uint16_t>(std::min(counts, 65535.0));
    }
  }
  return depth;
}

}  // namespace

RenderedFrame render(const SceneSpec& spec, const CameraProfile& prof, std::uint64_t frame_index) {
  if (prof.width <= 0 || prof.height <= 0 || !(prof.fx > 0) || !(prof.fy > 0) || !(prof.mount_height > 0) ||
      !(prof.depth_unit > 0))
    throw std::invalid_argument("camera profile '" + prof.name + "' is incomplete");
  const partgen::Scene scene = place_parts(spec);
  if (scene.parts.size() > 254) throw std::invalid_argument("at most 254 parts per scene");

  RenderedFrame out;
  out.intrinsics = prof.intrinsics();
  place_camera(spec, prof, out);
  std::vector<partgen::PolygonWithHoles> placed;
  for (const auto& p : scene.parts) placed.push_back(p.placed);
  const std::vector<detail::Warp> warps = detail::warps_of(placed, spec.effects.warp);
  const std::vector<partgen::PolygonWithHoles> image_polys = project_parts(scene, spec, prof, warps, out);
  cv::Mat z_true = true_depth(prof, image_polys, warps, out);
  if (spec.effects.any()) detail::apply_effects(spec, prof, frame_index, warps, z_true, out);
  else
    out.depth = sensor_depth(z_true, spec, prof, frame_index);
  return out;
}

namespace {
nlohmann::json ring_json(const partgen::Ring& ring) {
  nlohmann::json a = nlohmann::json::array();
  for (const auto& p : ring) a.push_back({p.x(), p.y()});
  return a;
}
nlohmann::json vec_json(const Eigen::Vector3d& v) { return {v.x(), v.y(), v.z()}; }
}  // namespace

void write_truth(const SceneSpec& spec, const CameraProfile& prof, const RenderedFrame& frame,
                 std::uint64_t frame_index, const std::string& path) {
  nlohmann::json j;
  j["scene"] = spec.name;
  j["seed"] = spec.seed;
  j["frame_index"] = frame_index;
  j["table_tilt_x"] = spec.table_tilt_x;
  j["table_tilt_y"] = spec.table_tilt_y;
  j["units"] = "metres";
  j["frames"] = {{"table", "x right, y up, z up towards the camera; table surface z = 0"},
                 {"camera", "x right, y down, z along the optical axis"}};
  j["camera"] = {{"profile", prof.name},
                 {"width", prof.width},
                 {"height", prof.height},
                 {"fx", prof.fx},
                 {"fy", prof.fy},
                 {"cx", prof.cx},
                 {"cy", prof.cy},
                 {"depth_unit", prof.depth_unit},
                 {"mount_height", prof.mount_height},
                 {"noise_a", prof.noise_a},
                 {"noise_b", prof.noise_b},
                 {"dropout", prof.dropout},
                 {"flying_pixel_prob", prof.flying_pixel_prob}};
  nlohmann::json m = nlohmann::json::array();
  for (int r = 0; r < 4; ++r) m.push_back(nlohmann::json::array());
  const Eigen::Matrix4d T = frame.camera_from_table.matrix();
  for (int r = 0; r < 4; ++r)
    for (int c = 0; c < 4; ++c) m[r].push_back(T(r, c));
  j["camera_from_table"] = m;
  j["table_plane_camera"] = {{"normal", vec_json(frame.table_normal)}, {"offset", frame.table_offset}};
  nlohmann::json parts = nlohmann::json::array();
  for (std::size_t k = 0; k < frame.part_polygons.size(); ++k) {
    const auto& poly = frame.part_polygons[k];
    nlohmann::json holes = nlohmann::json::array();
    for (const auto& h : poly.holes) holes.push_back(ring_json(h));
    parts.push_back({{"label", k + 1},
                     {"shape", spec.parts[k].shape.empty() ? "polygon" : spec.parts[k].shape},
                     {"thickness", frame.part_thickness[k]},
                     {"pose", {{"x", spec.parts[k].x}, {"y", spec.parts[k].y}, {"theta", spec.parts[k].theta}}},
                     {"area", partgen::polygon_area(poly)},
                     {"perimeter", partgen::polygon_perimeter(poly)},
                     {"outer", ring_json(poly.outer)},
                     {"holes", holes},
                     {"truth_pixels", cv::countNonZero(frame.truth_labels == static_cast<int>(k + 1))}});
  }
  j["parts"] = parts;
  partgen::write_json(j, path);
}

}  // namespace hg::sim
