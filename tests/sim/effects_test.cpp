// The renderer's sensor effects (docs/scene.md), each alone, against an expectation the test computes
// itself from the scene's geometry (brute-force visibility, numeric integration of the speckle law, the
// lattice of the table's holes, the bow's paraboloid), over many seeds and placements.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <functional>
#include <map>
#include <string>

#include "sim/partgen/synth.hpp"
#include "sim/scene/scene.hpp"

namespace sim = hg::sim;
using Vec2 = Eigen::Vector2d;
using Vec3 = Eigen::Vector3d;

namespace {

// The profile without its random noise, dropout and flying pixels: only the effect under test acts.
sim::CameraProfile clean(const std::string& name) {
  sim::CameraProfile p = sim::camera_profile(name);
  p.noise_a = p.noise_b = p.dropout = p.flying_pixel_prob = 0;
  return p;
}

hg::partgen::Ring rect(double w, double h, double cx = 0, double cy = 0, bool clockwise = false) {
  hg::partgen::Ring r{
      {cx - w / 2, cy - h / 2}, {cx + w / 2, cy - h / 2}, {cx + w / 2, cy + h / 2}, {cx - w / 2, cy + h / 2}};
  if (clockwise) std::reverse(r.begin(), r.end());
  return r;
}

// A w x h plate (optionally with a square hole of side `hole` at its middle) with its centre at (x, y) on a
// level table; no effect on.
sim::SceneSpec plate_scene(double x, double y, double w, double h, double t, double hole, std::uint64_t seed) {
  sim::SceneSpec spec;
  spec.name = "test-plate";
  spec.seed = seed;
  sim::ScenePart p;
  p.polygon.outer = rect(w, h);
  if (hole > 0) p.polygon.holes.push_back(rect(hole, hole, 0, 0, true));
  p.x = x, p.y = y, p.theta = 0, p.thickness = t;
  spec.parts.push_back(p);
  return spec;
}

Vec3 table_point(const sim::RenderedFrame& f, int r, int c, double z) {
  const auto& in = f.intrinsics;
  return f.camera_from_table.inverse() * (z * Vec3((c - in.cx) / in.fx, (r - in.cy) / in.fy, 1));
}

// The depth of the table plane along pixel (r, c)'s ray.
double table_depth(const sim::RenderedFrame& f, int r, int c) {
  const auto& in = f.intrinsics;
  const Vec3 d((c - in.cx) / in.fx, (r - in.cy) / in.fy, 1);
  return f.table_offset / f.table_normal.dot(d);
}

double metres(const sim::RenderedFrame& f, int r, int c) {
  return f.depth.at<std::uint16_t>(r, c) * f.intrinsics.depth_unit;
}

// P(gamma(N, mean S / N) > threshold) by Simpson's rule on the gamma density: the speckle law's detection
// probability, computed without the closed form the renderer uses.
double detection_numeric(double S, double threshold, int N) {
  const double theta = S / N;  // scale
  const double x1 = threshold;
  const int n = 2000;
  auto pdf = [&](double x) {
    return x <= 0 ? (N == 1 ? 1 / theta : 0)
                  : std::pow(x, N - 1) * std::exp(-x / theta) / (std::tgamma(N) * std::pow(theta, N));
  };
  double sum = pdf(0) + pdf(x1);
  for (int i = 1; i < n; ++i) sum += (i % 2 ? 4 : 2) * pdf(x1 * i / n);
  return 1 - sum * (x1 / n) / 3;
}

}  // namespace

// The loss of return: on a dark table tilted up to 57 deg, the fraction of pixels with no data, in bins of
// the model's probability, is 1 - P(detect) with the mean return albedo * cos(incidence) * (H / r)^2.
TEST(SceneEffects, ReturnProbabilityFallsWithTheIncidenceAngleAsTheSpeckleLaw) {
  for (const std::string name : {"lsr-l", "pm806"}) {
    const sim::CameraProfile prof = clean(name);
    std::vector<double> expect(10, 0), seen(10, 0), count(10, 0);
    std::map<long, double> memo;
    for (int s = 0; s < 4; ++s) {
      sim::SceneSpec spec;
      spec.name = "tilted";
      spec.seed = 100 + s;
      spec.table_tilt_x = 0.25 * s;
      spec.table_tilt_y = 0.1 * s - 0.15;
      spec.effects.incidence = true;
      spec.effects.table_surface.albedo = 0.05;  // dark, so the law spans most of its range
      const sim::RenderedFrame f = sim::render(spec, prof, 0);
      const Vec3 L = f.camera_from_table.inverse() * prof.emitter;
      for (int r = 0; r < f.depth.rows; r += 2)
        for (int c = 0; c < f.depth.cols; c += 2) {
          const Vec3 X = table_point(f, r, c, table_depth(f, r, c));
          const Vec3 to_l = L - X;
          const double cos_i = to_l.normalized().z();  // table normal is +z in the table frame
          const double S = 0.05 * cos_i * L.z() * L.z() / to_l.squaredNorm();
          // Memoised on S in steps of 1e-6 (the law changes by far less over a step).
          const long key = std::lround(S * 1e6);
          auto it = memo.find(key);
          if (it == memo.end())
            it = memo.emplace(key, detection_numeric(key * 1e-6, prof.return_threshold, prof.speckle_cells)).first;
          const double p = it->second;
          const int bin = std::min(9, static_cast<int>(p * 10));
          expect[bin] += p, seen[bin] += f.depth.at<std::uint16_t>(r, c) > 0, count[bin] += 1;
        }
    }
    int bins = 0;
    for (int b = 0; b < 10; ++b) {
      if (count[b] < 200) continue;
      ++bins;
      const double pe = expect[b] / count[b], pm = seen[b] / count[b];
      const double sigma = std::sqrt(pe * (1 - pe) / count[b]);
      std::printf("  %s bin %d: %6.0f pixels, expected return %.4f, seen %.4f\n", name.c_str(), b, count[b], pe, pm);
      EXPECT_NEAR(pm, pe, 5 * sigma + 0.003) << name << " bin " << b;
    }
    EXPECT_GE(bins, 3) << name << ": the tilts must span the law";
  }
}

namespace {

// Whether the straight segment from table point P (on the table, z = 0) to `source` passes through the
// plate (brute force: 400 heights between 0 and t, each tested against the rectangle and its hole).
bool blocked(const Vec3& P, const Vec3& source, const sim::SceneSpec& spec) {
  const auto& part = spec.parts[0];
  const double w = part.polygon.outer[1].x() - part.polygon.outer[0].x();
  const double h = part.polygon.outer[2].y() - part.polygon.outer[1].y();
  const double hole =
      part.polygon.holes.empty() ? 0 : std::abs(part.polygon.holes[0][0].x() - part.polygon.holes[0][2].x());
  for (int i = 0; i <= 400; ++i) {
    const double z = part.thickness * i / 400.0;
    const Vec3 q = P + (source - P) * (z / source.z());
    const double dx = std::abs(q.x() - part.x), dy = std::abs(q.y() - part.y);
    const bool in_outer = dx < w / 2 && dy < h / 2, in_hole = dx < hole / 2 && dy < hole / 2;
    if (in_outer && !in_hole) return true;
  }
  return false;
}

}  // namespace

// The baseline's shadow: every table pixel the camera sees is without data exactly where the straight line
// to the emitter passes through the plate (outer edges and the hole's walls); pixels within 0.3 mm of the
// shadow's border are not judged. The shadow lies on the side away from the emitter; its width beside the
// outer edge facing away is the baseline geometry's t (L_x - x_e) / (L_z - t), less what the camera
// cannot see itself.
TEST(SceneEffects, ShadowLiesAwayFromTheEmitterWithTheBaselineGeometrysWidth) {
  hg::partgen::Rng rng(7);
  for (const std::string name : {"lsr-l", "pm806"}) {
    const sim::CameraProfile prof = clean(name);
    int shadowed_all = 0;
    for (int s = 0; s < 5; ++s) {
      const double t = 0.006 + 0.024 * rng.uniform();
      sim::SceneSpec spec =
          plate_scene(-0.15 + 0.25 * rng.uniform(), -0.1 + 0.2 * rng.uniform(), 0.30, 0.20, t, 0.08, s);
      spec.effects.shadow = true;
      const sim::RenderedFrame f = sim::render(spec, prof, 0);
      const Eigen::Isometry3d table_from_camera = f.camera_from_table.inverse();
      const Vec3 L = table_from_camera * prof.emitter;
      int judged = 0, shadowed = 0, wrong = 0, emitter_side = 0;
      for (int r = 0; r < f.depth.rows; ++r)
        for (int c = 0; c < f.depth.cols; ++c) {
          if (f.truth_labels.at<std::uint8_t>(r, c) != 0) continue;
          const Vec3 P = table_point(f, r, c, table_depth(f, r, c));
          if (std::abs(P.x() - spec.parts[0].x) > 0.19 || std::abs(P.y() - spec.parts[0].y) > 0.14) continue;
          const bool expect = blocked(P, L, spec);
          const bool seen = f.depth.at<std::uint16_t>(r, c) == 0;
          bool border = false;
          for (const Vec3 d : {Vec3(3e-4, 0, 0), Vec3(-3e-4, 0, 0), Vec3(0, 3e-4, 0), Vec3(0, -3e-4, 0)})
            border |= blocked(P + d, L, spec) != expect;
          if (border) continue;
          ++judged;
          shadowed += seen;
          wrong += seen != expect;
          // The side towards the emitter (table points whose line to it leaves the plate behind) stays lit.
          emitter_side += seen && (P.x() - spec.parts[0].x) > 0.151;
        }
      const double x_e = spec.parts[0].x - 0.15;
      std::printf(
          "  %s t %.1f mm, outer edge at x %.3f: %d pixels judged, %d in shadow, %d wrong; width "
          "at the -x edge %.2f mm (before the camera's own occlusion)\n",
          name.c_str(), t * 1e3, x_e, judged, shadowed, wrong, 1e3 * t * (L.x() - x_e) / (L.z() - t));
      EXPECT_EQ(wrong, 0) << name << " seed " << s;
      EXPECT_EQ(emitter_side, 0) << name << " seed " << s;
      shadowed_all += shadowed;
    }
    // A shadow narrower than a pixel may fall between pixel centres; over the seeds there must be shadow.
    EXPECT_GT(shadowed_all, 500) << name;
  }
}

// Mixed pixels: every pixel whose depth differs from the clean rendering lies within the footprint of a
// depth jump (a plate edge, or a side wall the camera sees, whose depth runs steeply across its pixels), its depth
// between the nearest and farthest clean depth around it; and most pixels at a jump are mixed.
TEST(SceneEffects, MixedPixelsLieBetweenPlateAndTableOnlyAtTheEdge) {
  hg::partgen::Rng rng(11);
  for (const std::string name : {"lsr-l", "pm806"}) {
    const sim::CameraProfile prof = clean(name);
    const int reach = static_cast<int>(std::ceil(prof.footprint_px / 2)) + 1;
    for (int s = 0; s < 4; ++s) {
      sim::SceneSpec spec = plate_scene(-0.2 + 0.4 * rng.uniform(), -0.1 + 0.2 * rng.uniform(), 0.3, 0.2,
                                        0.006 + 0.024 * rng.uniform(), 0.1, s);
      const sim::RenderedFrame base = sim::render(spec, prof, 0);
      spec.effects.mixed_pixels = true;
      const sim::RenderedFrame f = sim::render(spec, prof, 0);
      int mixed = 0, far_from_edge = 0, outside = 0, jumps = 0;
      const double q = prof.depth_unit;
      for (int r = reach; r < f.depth.rows - reach; ++r)
        for (int c = reach; c < f.depth.cols - reach; ++c) {
          double lo = 1e9, hi = -1e9;
          bool edge = false;
          const int l0 = base.truth_labels.at<std::uint8_t>(r, c);
          for (int dr = -reach; dr <= reach; ++dr)
            for (int dc = -reach; dc <= reach; ++dc) {
              lo = std::min(lo, metres(base, r + dr, c + dc)), hi = std::max(hi, metres(base, r + dr, c + dc));
              edge |= base.truth_labels.at<std::uint8_t>(r + dr, c + dc) != l0;
            }
          const double z = metres(f, r, c), z0 = metres(base, r, c);
          jumps += edge && std::abs(metres(base, r, c - 1) - z0) > 0.003;
          if (std::abs(z - z0) <= 1.5 * q) continue;
          ++mixed;
          far_from_edge += !(hi - lo > 0.003);
          outside += z < lo - q || z > hi + q;
        }
      std::printf("  %s seed %d: %d mixed pixels, %d column jumps, %d away from an edge, %d outside\n", name.c_str(), s,
                  mixed, jumps, far_from_edge, outside);
      EXPECT_EQ(far_from_edge, 0);
      EXPECT_EQ(outside, 0);
      EXPECT_GT(mixed, jumps / 2) << "the veil must exist";
    }
  }
}

// The perforated table: no data exactly where the pixel's table point lies in a hole of the staggered
// lattice (60 deg, pitch p, diameter d), the holes' share of the table pi d^2 / (2 sqrt(3) p^2).
TEST(SceneEffects, PerforationHolesSitAtTheTablesPitch) {
  hg::partgen::Rng rng(3);
  for (int s = 0; s < 4; ++s) {
    sim::SceneSpec spec = sim::scene_preset("empty");
    spec.seed = s;
    auto& table = spec.effects.table;
    table.kind = sim::TableSpec::Kind::Perforated;
    table.hole_pitch = 0.012 + 0.02 * rng.uniform();
    table.hole_diameter = table.hole_pitch * (0.3 + 0.4 * rng.uniform());
    const sim::CameraProfile prof = clean(s % 2 ? "pm806" : "lsr-l");
    const sim::RenderedFrame f = sim::render(spec, prof, 0);
    const double p = table.hole_pitch, rad = table.hole_diameter / 2;
    // Lattice basis a = (p, 0), b = (p/2, p sqrt(3)/2); nearest lattice point by trying the cell's corners.
    auto in_hole = [&](double x, double y, double margin) {
      const double j = y / (p * std::sqrt(3.0) / 2), i = x / p - j / 2;
      for (double di : {0.0, 1.0})
        for (double dj : {0.0, 1.0}) {
          const double ii = std::floor(i) + di, jj = std::floor(j) + dj;
          const Vec2 c(ii * p + jj * p / 2, jj * p * std::sqrt(3.0) / 2);
          if ((Vec2(x, y) - c).norm() < rad + margin) return true;
        }
      return false;
    };
    long holes = 0, total = 0, wrong = 0;
    for (int r = 0; r < f.depth.rows; ++r)
      for (int c = 0; c < f.depth.cols; ++c) {
        const Vec3 P = table_point(f, r, c, table_depth(f, r, c));
        const bool seen = f.depth.at<std::uint16_t>(r, c) == 0;
        ++total;
        holes += seen;
        if (in_hole(P.x(), P.y(), -1e-5) != in_hole(P.x(), P.y(), 1e-5)) continue;  // on a rim
        wrong += seen != in_hole(P.x(), P.y(), 0);
      }
    const double share = M_PI * table.hole_diameter * table.hole_diameter / (2 * std::sqrt(3.0) * p * p);
    std::printf("  pitch %.1f mm, holes D%.1f mm: %.4f of the pixels open (lattice %.4f), %ld wrong\n", p * 1e3,
                table.hole_diameter * 1e3, double(holes) / total, share, wrong);
    EXPECT_EQ(wrong, 0);
    EXPECT_NEAR(double(holes) / total, share, 0.03 * share + 0.002);
  }
}

// The slatted table: gaps of width g every w + g along x; chips on it raise the expected share of the table.
TEST(SceneEffects, SlatGapsAndChipsCoverTheirShareOfTheTable) {
  for (int s = 0; s < 3; ++s) {
    sim::SceneSpec spec = sim::scene_preset("empty");
    spec.seed = 40 + s;
    spec.table_tilt_x = spec.table_tilt_y = 0;
    auto& table = spec.effects.table;
    table.kind = sim::TableSpec::Kind::Slatted;
    table.slat_width = 0.03 + 0.01 * s, table.slat_gap = 0.008 + 0.004 * s;
    table.chips_per_m2 = 150;
    const sim::CameraProfile prof = clean("lsr-l");
    const sim::RenderedFrame f = sim::render(spec, prof, 0);
    const double period = table.slat_width + table.slat_gap;
    long total = 0, open = 0, wrong = 0, raised = 0, on_slat = 0;
    for (int r = 0; r < f.depth.rows; ++r)
      for (int c = 0; c < f.depth.cols; ++c) {
        const Vec3 P = table_point(f, r, c, table_depth(f, r, c));
        const double phase = P.x() - period * std::floor(P.x() / period);
        const bool gap = phase >= table.slat_width;
        const bool seen = f.depth.at<std::uint16_t>(r, c) == 0;
        ++total;
        open += seen;
        if (std::abs(phase - table.slat_width) > 1e-5 && phase > 1e-5 && period - phase > 1e-5) wrong += seen != gap;
        if (!gap && !seen) ++on_slat, raised += metres(f, r, c) < table_depth(f, r, c) - 0.0002;
      }
    // Chips: radius uniform in 1..4 mm, every one thicker than 0.2 mm: E[pi r^2] = pi (4^3 - 1^3) / (3 * 3) mm^2.
    const double chip_share = 150 * M_PI * (64.0 - 1.0) / 9.0 * 1e-6;
    std::printf(
        "  slats %.0f mm, gaps %.0f mm: open %.4f (expected %.4f), %ld wrong; chips on %.5f of the slats "
        "(expected %.5f)\n",
        table.slat_width * 1e3, table.slat_gap * 1e3, double(open) / total, table.slat_gap / period, wrong,
        double(raised) / on_slat, chip_share);
    EXPECT_EQ(wrong, 0);
    EXPECT_NEAR(double(open) / total, table.slat_gap / period, 0.01);
    EXPECT_NEAR(double(raised) / on_slat, chip_share, 0.35 * chip_share);
  }
}

// The bow: the top face's height above the table at every pixel away from the edges is t + the paraboloid
// 4 s (|p - c|^2 - r0^2) of the configured sagitta s, edges up or middle up.
TEST(SceneEffects, WarpAmplitudeIsAsConfigured) {
  hg::partgen::Rng rng(5);
  for (int s = 0; s < 4; ++s) {
    const double sag = (s % 2 ? -1 : 1) * (0.002 + 0.004 * rng.uniform());
    sim::SceneSpec spec = plate_scene(-0.1 + 0.2 * rng.uniform(), -0.05 + 0.1 * rng.uniform(), 0.5, 0.35, 0.012, 0, s);
    spec.table_tilt_x = 0.01, spec.table_tilt_y = -0.008;
    spec.effects.warp = sag;
    const sim::CameraProfile prof = clean("lsr-l");
    const sim::RenderedFrame f = sim::render(spec, prof, 0);
    const Vec2 c(spec.parts[0].x, spec.parts[0].y);
    const double R2 = 0.25 * 0.25 + 0.175 * 0.175;
    double worst = 0, lo = 1e9, hi = -1e9;
    int n = 0;
    for (int r = 2; r < f.depth.rows - 2; ++r)
      for (int col = 2; col < f.depth.cols - 2; ++col) {
        bool inner = true;
        for (int d = -2; d <= 2; ++d)
          inner &= f.truth_labels.at<std::uint8_t>(r + d, col) == 1 && f.truth_labels.at<std::uint8_t>(r, col + d) == 1;
        if (!inner) continue;
        const Vec3 P = table_point(f, r, col, metres(f, r, col));
        const double d2 = (Vec2(P.x(), P.y()) - c).squaredNorm();
        const double w = 4 * sag * (d2 - (sag < 0 ? R2 : 0));
        worst = std::max(worst, std::abs(P.z() - 0.012 - w));
        lo = std::min(lo, P.z() - 0.012), hi = std::max(hi, P.z() - 0.012);
        ++n;
      }
    std::printf("  sagitta %+.1f mm/m: %d pixels, bow %.2f..%.2f mm (model 0..%.2f), worst deviation %.3f mm\n",
                sag * 1e3, n, lo * 1e3, hi * 1e3, 4 * std::abs(sag) * R2 * 1e3, worst * 1e3);
    EXPECT_GT(n, 10000);
    EXPECT_LT(worst, 0.0001);  // half a depth count (0.05 mm) plus the count of the table's own plane
    EXPECT_NEAR(hi - lo, 4 * std::abs(sag) * R2, 0.1 * 4 * std::abs(sag) * R2);
  }
}

// Specular lobes: with the whole top ground (no strip tilt), a pixel saturates where the Beckmann lobe
// about the half vector of light and view alone exceeds the saturation level, and never where the lobe plus
// eight times the mean diffuse return stays below it. Saturated pixels have no depth and intensity 255.
TEST(SceneEffects, SaturationFollowsTheSpecularLobe) {
  for (const std::string name : {"lsr-l", "pm806"}) {
    const sim::CameraProfile prof = clean(name);
    for (int s = 0; s < 3; ++s) {
      sim::SceneSpec spec = plate_scene(prof.emitter.x() / 2 + 0.05 * s - 0.05, 0.02 * s, 0.4, 0.3, 0.01, 0, s);
      spec.table_tilt_x = spec.table_tilt_y = 0;
      spec.effects.specular = true;
      spec.effects.intensity = true;
      spec.effects.ground_fraction = 1;
      spec.effects.strip_tilt_sigma = 0;
      const sim::Surface g = spec.effects.ground;
      const sim::RenderedFrame f = sim::render(spec, prof, 0);
      const Eigen::Isometry3d table_from_camera = f.camera_from_table.inverse();
      const Vec3 L = table_from_camera * prof.emitter, C = table_from_camera * Vec3::Zero();
      int saturated = 0, must = 0, wrong = 0;
      for (int r = 1; r < f.depth.rows - 1; ++r)
        for (int c = 1; c < f.depth.cols - 1; ++c) {
          if (f.truth_labels.at<std::uint8_t>(r, c) != 1 || f.truth_labels.at<std::uint8_t>(r, c - 1) != 1 ||
              f.truth_labels.at<std::uint8_t>(r, c + 1) != 1)
            continue;
          const auto& in = f.intrinsics;
          const Vec3 d((c - in.cx) / in.fx, (r - in.cy) / in.fy, 1);
          const Vec3 P = table_from_camera * ((f.table_offset + 0.01) / f.table_normal.dot(d) * d);
          const Vec3 l = (L - P).normalized(), v = (C - P).normalized(), h = (l + v).normalized();
          const double falloff = L.z() * L.z() / (L - P).squaredNorm();
          const double tan2 = (1 - h.z() * h.z()) / (h.z() * h.z());
          const double lobe = g.specular * std::exp(-tan2 / (g.roughness * g.roughness)) * falloff;
          const double diffuse = g.albedo * l.z() * falloff;
          const bool sat = f.depth.at<std::uint16_t>(r, c) == 0;
          saturated += sat;
          if (sat) wrong += f.intensity.at<std::uint8_t>(r, c) != 255;
          if (lobe >= prof.saturation * 1.001) ++must, wrong += !sat;
          if (lobe + 8 * diffuse < prof.saturation) wrong += sat;
        }
      std::printf("  %s seed %d: %d saturated pixels, %d required by the lobe, %d wrong\n", name.c_str(), s, saturated,
                  must, wrong);
      EXPECT_GT(must, 50);
      EXPECT_EQ(wrong, 0);
    }
  }
}

// The intensity image: empty without the effect; with it, a lit grey table's mean intensity is
// 255 albedo cos(i) (H / r)^2 / saturation (the speckle gain has mean 1), and shadows are black.
TEST(SceneEffects, IntensityIsTheMeanReturnScaledToSaturation) {
  EXPECT_TRUE(sim::render(sim::scene_preset("plate-hole-slot"), sim::camera_profile("pm806"), 0).intensity.empty());
  for (const std::string name : {"lsr-l", "pm806"}) {
    const sim::CameraProfile prof = clean(name);
    sim::SceneSpec spec = sim::scene_preset("empty");
    spec.effects.intensity = true;
    const sim::RenderedFrame f = sim::render(spec, prof, 3);
    ASSERT_EQ(f.intensity.type(), CV_8UC1);
    const Vec3 L = f.camera_from_table.inverse() * prof.emitter;
    double seen = 0, expect = 0;
    long n = 0;
    for (int r = 0; r < f.depth.rows; r += 3)
      for (int c = 0; c < f.depth.cols; c += 3) {
        const Vec3 P = table_point(f, r, c, table_depth(f, r, c));
        const Vec3 to_l = L - P;
        expect += 255 * spec.effects.table_surface.albedo * to_l.normalized().z() * L.z() * L.z() / to_l.squaredNorm() /
                  prof.saturation;
        seen += f.intensity.at<std::uint8_t>(r, c);
        ++n;
      }
    std::printf("  %s: mean intensity %.2f, model %.2f\n", name.c_str(), seen / n, expect / n);
    EXPECT_NEAR(seen / n, expect / n, 0.02 * expect / n + 0.5);  // rounding to whole levels: +-0.5
  }
}

// Every catalogue part has a realistic preset; each renders with both profiles, deterministically per
// (seed, frame), with the effects visible (dropout, an intensity image) and the same ground truth as the
// clean preset.
TEST(SceneEffects, RealisticPresetsOfEveryPartAreDeterministic) {
  for (const std::string& shape : hg::partgen::shape_names()) {
    const sim::SceneSpec spec = sim::scene_preset(shape + "-realistic");
    EXPECT_TRUE(spec.effects.any());
    for (const std::string name : {"pm806", "lsr-l"}) {
      const sim::CameraProfile prof = sim::camera_profile(name);
      const sim::RenderedFrame a = sim::render(spec, prof, 1), b = sim::render(spec, prof, 1);
      ASSERT_FALSE(a.intensity.empty());
      EXPECT_EQ(cv::norm(a.depth, b.depth, cv::NORM_INF), 0) << shape << "@" << name;
      EXPECT_EQ(cv::norm(a.intensity, b.intensity, cv::NORM_INF), 0) << shape << "@" << name;
      const sim::RenderedFrame c = sim::render(spec, prof, 2);
      EXPECT_GT(cv::norm(a.depth, c.depth, cv::NORM_L1), 0) << "frames differ";
      const sim::RenderedFrame plain = sim::render(sim::scene_preset(shape), prof, 1);
      ASSERT_EQ(plain.part_polygons.size(), a.part_polygons.size());
      EXPECT_EQ(plain.part_polygons[0].outer, a.part_polygons[0].outer);
      const double zero = 1.0 - double(cv::countNonZero(a.depth)) / a.depth.total();
      const double zero_plain = 1.0 - double(cv::countNonZero(plain.depth)) / plain.depth.total();
      std::printf("  %s-realistic@%s: %.1f %% of the pixels without data (clean preset %.1f %%)\n", shape.c_str(),
                  name.c_str(), 100 * zero, 100 * zero_plain);
      EXPECT_GT(zero, zero_plain + 0.05);
    }
  }
}
