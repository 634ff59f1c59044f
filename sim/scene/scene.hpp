// Synthetic depth scenes: a grinding table (slightly tilted) with hull parts lying on it, seen from above
// by a depth camera of a given profile. Used by the bridge's `synthetic` source, by the virtual OpenNI2
// driver (sim/virtual_device) and by the tests, which compare segmentation to the ground truth
// returned with each frame. No LCM here: library hg_camera_scene (hg_partgen + OpenCV + Eigen).
//
// Frames:
//  - table frame: metres, x right, y up (partgen's plate frame), z up out of the table towards the camera;
//    the table surface is z = 0, a part's top face is z = thickness.
//  - camera frame: OpenCV/OpenNI pinhole convention, x right, y down, z along the optical axis.
//    Untilted, the camera looks straight down at the table origin from mount_height, so image row 0 is the
//    table's largest y (the scan-line order of partgen's clouds). The tilt turns the table about its own
//    x axis (table_tilt_x) then y axis (table_tilt_y) at the point under the camera.
#pragma once

#include <cstdint>
#include <string>
#include <vector>

#include <Eigen/Geometry>
#include <opencv2/core.hpp>

#include "camera_types/depth_source.hpp"
#include "sim/partgen/shapes.hpp"

namespace hg::sim {

struct CameraProfile {
  std::string name;
  int width = 0, height = 0;
  double fx = 0, fy = 0, cx = 0, cy = 0;  // pixels
  double mount_height = 0;                // optical centre above the table origin, metres
  double depth_unit = 0.001;              // metres per depth count
  double noise_a = 0, noise_b = 0;        // depth noise sigma(z) = noise_a + noise_b * z^2 (metres, z in metres)
  double dropout = 0;                     // fraction of pixels with no data (count 0), at random
  double flying_pixel_prob = 0;           // chance that a pixel at a depth edge gets a mixed depth
  // The sensing principle and what follows from it, used only by the effects of SceneSpec::effects
  // (docs/scene.md): where the light comes from and how the return is detected.
  std::string principle;                              // "structured-light" or "laser-triangulation"
  Eigen::Vector3d emitter = Eigen::Vector3d::Zero();  // projector / laser exit pupil, camera frame, metres
  double return_threshold = 0;  // detection threshold / mean return of a grey (albedo 1) face met square on
  int speckle_cells = 1;        // speckle cells averaged per pixel (the gamma law's order)
  double saturation = 0;        // mean return (same unit) that saturates the pixel
  double footprint_px = 1;      // side of the pixel's footprint on the scene (optics + spot), pixels
  camera::Intrinsics intrinsics() const { return {width, height, fx, fy, cx, cy, depth_unit}; }
};

// "pm806": 1280x960, Percipio PM806-class (low density); "lsr-l": 2048x1536, Mech-Eye LSR-L-class (high
// density); "m130": 2448x2048, a Zivid 2+ M130 at 1.6 m (0.39 mm per pixel). The pm806 and lsr-l numbers are
// assumptions of plausible values, m130's sensor and pixel spacing are its data sheet's (scene.cpp says which
// and why). Throws std::invalid_argument listing the known names.
CameraProfile camera_profile(const std::string& name);
std::vector<std::string> camera_profile_names();

struct ScenePart {
  std::string shape;                  // partgen catalogue name; empty: use `polygon`
  double scale = 1.0;                 // of the catalogue shape
  partgen::PolygonWithHoles polygon;  // in the part's own frame, used when shape is empty
  double x = 0, y = 0, theta = 0;     // pose on the table: bounding-box centre at (x, y), rotated by theta (rad)
  double thickness = 0.012;           // metres, 0.006 .. 0.030
};

// The grinding table's top (docs/scene.md, "The table"). Plain: a flat steel top.
struct TableSpec {
  enum class Kind { Plain, Perforated, Slatted };
  Kind kind = Kind::Plain;
  double hole_diameter = 0.008;  // perforated: round holes on a 60-degree staggered lattice of this pitch
  double hole_pitch = 0.016;
  double slat_width = 0.040;  // slatted: slats along the table's y, gaps between them open to the floor
  double slat_gap = 0.010;
  double spatter_per_m2 = 0;  // weld spatter balls (diameter 0.6..2 mm) per square metre of table
  double chips_per_m2 = 0;    // grinding / cutting chips (flat flakes 2..8 mm, 0.3..1 mm thick) per m^2
};

// Materials: diffuse albedo and specular lobe (Beckmann roughness m, peak ratio to a grey face).
struct Surface {
  double albedo = 1;
  double specular = 0;
  double roughness = 0.3;
};

// What real sensors do (docs/scene.md). Every effect is off by default; the `<part>-realistic` presets
// turn all of them on. Effects that depend on the principle (the shadow) take their geometry from the
// camera profile.
struct SensorEffects {
  bool incidence = false;          // return probability from the illumination's incidence angle (speckle law)
  double edge_radius = 0;          // top edge rounded by thermal cutting (ISO 9013), metres; needs incidence
  bool specular = false;           // specular lobe: saturated pixels; ground strips on the top faces
  double ground_fraction = 0.3;    // share of each top face ground in strips (the rest mill scale)
  double strip_width = 0.050;      // width of a grinding strip, metres
  double strip_tilt_sigma = 0.02;  // random cross slope of a strip, radians
  bool mixed_pixels = false;       // depth of a pixel straddling a depth jump: mean over its footprint
  bool shadow = false;             // no return where the surface cannot see the emitter (the baseline's shadow)
  TableSpec table;
  double warp = 0;         // plate bow: sagitta over a 1 m chord, metres (> 0 edges up, < 0 centre up)
  bool intensity = false;  // render the intensity image
  // Specular peak = F / (4 m^2) for Fresnel reflectance F (docs/scene.md, "Specular lobes").
  Surface table_surface{0.4, 0.1, 0.35};  // painted / rusted table (F 0.05)
  Surface mill_scale{0.2, 0.8, 0.25};     // plate top as rolled: dark oxide (F 0.2)
  Surface ground{0.08, 38.0, 0.06};       // ground strips: bright steel, little diffuse return (F 0.55)
  Surface cut_face{0.25, 0.55, 0.3};      // thermally cut faces, oxidised (F 0.2)
  bool any() const {
    return incidence || specular || mixed_pixels || shadow || table.kind != TableSpec::Kind::Plain ||
           table.spatter_per_m2 > 0 || table.chips_per_m2 > 0 || warp != 0 || intensity;
  }
};

struct SceneSpec {
  std::string name;
  std::vector<ScenePart> parts;               // must not overlap on the table
  double table_tilt_x = 0, table_tilt_y = 0;  // radians
  std::uint64_t seed = 1;                     // noise, dropout and flying pixels are a function of (seed, frame index)
  SensorEffects effects;                      // all off unless a realistic preset or the caller turns them on
};

// Every effect on, at the values docs/scene.md gives: what `<part>-realistic` presets use.
SensorEffects realistic_effects();

// "empty" (table only), "plate-hole-slot", "l-bracket", "knee-scallop", "collar-notch", "ring-flange",
// "trapezoid-holes" (one catalogue part each, at its own thickness), "three-parts", "demo" (four parts);
// "<part>-realistic" for every catalogue part: the same scene with realistic_effects() on a perforated table.
// Throws std::invalid_argument listing the known names.
SceneSpec scene_preset(const std::string& name);
std::vector<std::string> scene_preset_names();

struct RenderedFrame {
  cv::Mat depth;  // CV_16UC1, counts of intrinsics.depth_unit, 0 = no data
  // CV_8UC1 intensity (reflected light, 255 = saturated) when SensorEffects::intensity, else empty.
  cv::Mat intensity;
  camera::Intrinsics intrinsics;
  // CV_8UC1 ground truth per pixel: 0 = table, k + 1 = the pixel's centre ray first hits part k (its top
  // face or a side wall), before noise, dropout and flying pixels.
  cv::Mat truth_labels;
  cv::Mat truth_mask() const { return truth_labels > 0; }
  // Ground truth geometry.
  std::vector<partgen::PolygonWithHoles> part_polygons;  // top-face outlines in the table frame
  std::vector<double> part_thickness;
  Eigen::Isometry3d camera_from_table = Eigen::Isometry3d::Identity();  // p_cam = T * p_table
  Eigen::Vector3d table_normal = Eigen::Vector3d::UnitZ();              // camera frame, pointing to the camera
  double table_offset = 0;  // table plane in the camera frame: normal . p = offset (negative: camera above)
};

// Deterministic for (spec, profile, frame_index). Throws std::invalid_argument on a bad spec (unknown
// shape, thickness outside 6..30 mm, overlapping parts, part outside the camera's view).
RenderedFrame render(const SceneSpec& spec, const CameraProfile& profile, std::uint64_t frame_index);

// Ground truth of a rendered frame as JSON (part polygons in the table frame, thicknesses, table plane and
// camera pose, profile, scene) written atomically to path. Throws std::runtime_error naming the path.
void write_truth(const SceneSpec& spec, const CameraProfile& profile, const RenderedFrame& frame,
                 std::uint64_t frame_index, const std::string& path);

}  // namespace hg::sim
