// hg-gen: writes a synthetic hull-part cloud (as a top-down depth camera sees it) and its ground truth.
#include "sim/partgen/presets.hpp"
#include "sim/partgen/shapes.hpp"
#include "sim/partgen/synth.hpp"
#include "sim/partgen/writers.hpp"

#include <chrono>
#include <cmath>
#include <cstdio>
#include <filesystem>
#include <iostream>
#include <limits>
#include <numbers>
#include <optional>
#include <stdexcept>
#include <string>
#include <vector>
#include "runtime/params.hpp"

using namespace hg::partgen;

namespace {

// What --help says before and after the options (the options themselves come from their declarations).
constexpr const char* kUsageHead = R"(hg-gen: synthetic hull-part point clouds as a top-down depth camera sees them.

Usage:
  hg-gen (--shape NAME | --preset NAME | --scene demo) [options] -o OUT
  hg-gen --all DIR [--format xyz|pcd|pcd-ascii] [noise options]
  hg-gen --list | --fit-presets | --help

Writes OUT (the cloud) and OUT.truth.json (ground truth: every part's polygon with holes in the same
frame and units as the cloud, exact area and perimeter, pixel grid, noise settings, point count).
Points are in metres in the table frame (x right, y up, z = plate thickness above the table), in
SCAN-LINE order: pixel rows from the top (largest y) down, left to right within a row.

Source: exactly one of --shape, --preset, --scene (or --all, --list, --fit-presets).
Options (command line > --config FILE > default):
)";

constexpr const char* kUsageTail =
    R"(  --config FILE                    a YAML file with any of these options as keys (the command line wins)
  --help                           this text; --help-markdown: the options as a table; --version
Exit status: 0 on success, 2 on bad usage or input, 1 when a file cannot be written.
)";

struct UsageError : std::runtime_error {
  using std::runtime_error::runtime_error;
};

struct Args {
  std::optional<std::string> shape, preset, scene, out, all, format;
  std::optional<double> scale, pitch, rotate, thickness;
  double noise = 0, depth_noise = 0, dropout = 0;
  bool jagged = false, list = false, fit = false;
  std::uint64_t seed = 1;
};

// The options, declared once (runtime::Params: parsing, types and ranges, --help and --help-markdown).
std::vector<hg::runtime::Param> gen_params() {
  using namespace hg::runtime;
  constexpr double inf = std::numeric_limits<double>::infinity();
  Param out = text_param("output", "", "output cloud file");
  out.alias = "-o";
  std::vector<Param> params = {
      text_param("shape", "", "one part of the catalogue (see --list), bounding-box centre at the origin"),
      text_param("preset", "",
                 "a paper-sized cloud: low-1..6 (Table 1), high-1..6 (Table 4), down-1..6 (Table 6); sets shape, "
                 "rotation and pitch (the options below override)"),
      text_param("scene", "", "four different parts on one table", {"demo"}),
      number_param("scale", "", "multiply every length of the shape (default 1; --shape and --scene only)", 0, inf,
                   true),
      number_param("pitch", "", "pixel spacing on the table, m (default 0.002 for --shape/--scene)", 0, inf, true),
      number_param("rotate", "", "rotation of the part against the pixel grid, deg (--shape, --preset)"),
      number_param("thickness", "", "plate thickness, m (default: the shape's own)", 0.006, 0.030),
      number_param("noise", "0", "Gaussian in-plane noise sigma added to x and y, m", 0),
      number_param("depth-noise", "0", "Gaussian noise sigma added to z, m", 0),
      number_param("dropout", "0", "fraction of pixels lost at random", 0, 1),
      flag_param("jagged", "edge pixels kept with probability equal to the pixel's covered fraction"),
      integer_param("seed", "1", "random seed; the same seed and options give the same file", 0),
      text_param("format", "",
                 "xyz (text \"x y z\" lines, 7 decimals), pcd (binary float32), pcd-ascii; default: from OUT's "
                 "extension (.pcd: pcd, else xyz); --all defaults to pcd",
                 {"xyz", "pcd", "pcd-ascii"}),
      out,
      text_param("all", "", "write every preset into DIR as <preset>.<ext> plus <preset>.<ext>.truth.json"),
      flag_param("list", "list shapes (with exact area and perimeter) and presets"),
      flag_param("fit-presets", "fit every preset's pitch to the paper's point count and print the table")};
  set_value_names(params, {{"shape", "NAME"},
                           {"preset", "NAME"},
                           {"scene", "NAME"},
                           {"scale", "S"},
                           {"pitch", "M"},
                           {"rotate", "DEG"},
                           {"thickness", "M"},
                           {"noise", "M"},
                           {"depth-noise", "M"},
                           {"dropout", "F"},
                           {"seed", "N"},
                           {"format", "F"},
                           {"output", "OUT"},
                           {"all", "DIR"}});
  return params;
}

void usage(std::FILE* f, const hg::runtime::Params& params) {
  std::fputs(kUsageHead, f);
  params.print_options(f);
  std::fputs(kUsageTail, f);
}

Args args_from(const hg::runtime::Params& p) {
  Args a;
  if (!p.positional().empty()) throw UsageError("unexpected argument '" + p.positional()[0] + "' (see --help)");
  auto text = [&](const char* name, std::optional<std::string>& to) {
    if (p.given(name)) to = p.text(name);
  };
  auto number = [&](const char* name, std::optional<double>& to) {
    if (p.given(name)) to = p.number(name);
  };
  text("shape", a.shape), text("preset", a.preset), text("scene", a.scene), text("output", a.out), text("all", a.all);
  text("format", a.format);
  number("scale", a.scale), number("pitch", a.pitch), number("rotate", a.rotate), number("thickness", a.thickness);
  a.noise = p.number("noise"), a.depth_noise = p.number("depth-noise"), a.dropout = p.number("dropout");
  a.jagged = p.flag("jagged"), a.list = p.flag("list"), a.fit = p.flag("fit-presets");
  a.seed = std::uint64_t(p.integer("seed"));
  return a;
}

std::string format_for(const Args& a, const std::string& out, const char* fallback) {
  if (a.format) {
    if (*a.format != "xyz" && *a.format != "pcd" && *a.format != "pcd-ascii")
      throw UsageError("--format: '" + *a.format + "' is not one of xyz, pcd, pcd-ascii");
    return *a.format;
  }
  return std::filesystem::path(out).extension() == ".pcd" ? "pcd" : fallback;
}

CloudOptions noise_options(const Args& a, CloudOptions o) {
  o.in_plane_sigma = a.noise;
  o.depth_sigma = a.depth_noise;
  o.dropout = a.dropout;
  o.jagged = a.jagged;
  o.seed = a.seed;
  return o;
}

void apply_thickness(const Args& a, Scene& scene) {
  if (!a.thickness) return;
  if (!(*a.thickness >= 0.006 && *a.thickness <= 0.030))
    throw UsageError("--thickness: " + std::to_string(*a.thickness) + " m is outside 0.006..0.030 m");
  for (PlacedPart& p : scene.parts) p.shape.thickness = *a.thickness;
}

void generate(const Scene& scene, const CloudOptions& o, const std::string& out, const std::string& format,
              const std::optional<Preset>& preset) {
  const auto t0 = std::chrono::steady_clock::now();
  const Cloud cloud = synthesize(scene, o);
  const auto t1 = std::chrono::steady_clock::now();
  if (format == "xyz") write_xyz(cloud, out);
  else
    write_pcd(cloud, out, format == "pcd");
  nlohmann::json truth = truth_json(scene, o, cloud);
  truth["cloud_file"] = std::filesystem::path(out).filename().string();
  truth["cloud_format"] = format;
  if (preset) {
    truth["preset"] = {{"name", preset->name},
                       {"table", preset->table},
                       {"piece", preset->piece},
                       {"paper_points", preset->paper_points}};
  }
  write_json(truth, out + ".truth.json");
  const auto t2 = std::chrono::steady_clock::now();
  const auto ms = [](auto d) { return std::chrono::duration<double, std::milli>(d).count(); };
  std::printf(
      "%s: %zu points (pitch %.6g m, %d x %d grid), area %.6g m2, perimeter %.6g m; "
      "synthesize %.1f ms, write %.1f ms\n",
      out.c_str(), cloud.size(), o.pitch, cloud.grid.cols, cloud.grid.rows, scene.total_area(), scene.total_perimeter(),
      ms(t1 - t0), ms(t2 - t1));
}

void list() {
  std::printf("shapes (scale 1; area m2, perimeter m, holes, thickness m):\n");
  for (const Shape& s : catalogue())
    std::printf("  %-16s %9.6f %8.5f %d %.3f  %s\n", s.name.c_str(), s.exact_area, s.exact_perimeter,
                s.exact_hole_count, s.thickness, s.description.c_str());
  std::printf("fixtures (not hull parts):\n");
  for (const std::string& name : fixture_names()) {
    const Shape s = make_shape(name);
    std::printf("  %-16s %9.6f %8.5f %d %.3f  %s\n", s.name.c_str(), s.exact_area, s.exact_perimeter,
                s.exact_hole_count, s.thickness, s.description.c_str());
  }
  std::printf("scenes:\n  demo             plate-hole-slot, l-bracket, knee-scallop, ring-flange on one table\n");
  std::printf("presets (name, paper table, piece, shape, rotation deg, pitch m, paper points):\n");
  for (const Preset& p : presets())
    std::printf("  %-8s %-8s %d %-16s %5.1f %.8f %zu\n", p.name.c_str(), p.table.c_str(), p.piece, p.shape.c_str(),
                p.rotation_deg, p.pitch, p.paper_points);
}

void fit_presets() {
  std::printf("preset    paper     fitted pitch (m)  points   deviation\n");
  for (const Preset& p : presets()) {
    const Scene scene = preset_scene(p);
    const double pitch = fit_pitch(scene, p.paper_points);
    const std::size_t n = count_pixel_centres(scene, pitch);
    std::printf("%-8s %8zu  %.8e  %8zu  %+.3f%%\n", p.name.c_str(), p.paper_points, pitch, n,
                100.0 * (double(n) - double(p.paper_points)) / double(p.paper_points));
  }
}

int run(int argc, char** argv) {
  hg::runtime::Params params(gen_params());
  const auto action = params.parse(argc, argv);  // throws runtime::ConfigError naming the option
  if (action != hg::runtime::Params::Action::Run) return hg::runtime::answer(action, "hg-gen", params, usage);
  if (argc == 1) {
    usage(stderr, params);
    return 2;
  }
  const Args a = args_from(params);
  if (a.list) {
    list();
    return 0;
  }
  if (a.fit) {
    fit_presets();
    return 0;
  }
  if (a.all) {
    if (a.shape || a.preset || a.scene || a.out) throw UsageError("--all takes no --shape/--preset/--scene/-o");
    if (a.pitch || a.rotate || a.scale) throw UsageError("--all keeps every preset's own pitch, rotation and size");
    const std::string fmt = format_for(a, "", "pcd");
    Scene probe = preset_scene(presets().front());
    apply_thickness(a, probe);  // bad options are refused before anything is created
    std::filesystem::create_directories(*a.all);
    const std::string ext = fmt == "xyz" ? ".xyz" : ".pcd";
    for (const Preset& p : presets()) {
      Scene scene = preset_scene(p);
      apply_thickness(a, scene);
      generate(scene, noise_options(a, preset_options(p)), (std::filesystem::path(*a.all) / (p.name + ext)).string(),
               fmt, p);
    }
    return 0;
  }
  if ((a.shape ? 1 : 0) + (a.preset ? 1 : 0) + (a.scene ? 1 : 0) != 1)
    throw UsageError("give exactly one of --shape, --preset, --scene (see --help)");
  if (!a.out) throw UsageError("-o OUT is required");
  Scene scene;
  CloudOptions o;
  std::optional<Preset> preset;
  if (a.preset) {
    preset = find_preset(*a.preset);
    if (a.scale) throw UsageError("--scale does not apply to a preset (its size is the paper's)");
    if (a.rotate) preset->rotation_deg = *a.rotate;
    scene = preset_scene(*preset);
    o = preset_options(*preset);
  } else if (a.shape) {
    scene = single_part_scene(make_shape(*a.shape, a.scale.value_or(1.0)),
                              a.rotate.value_or(0.0) * std::numbers::pi / 180.0);
    o.pitch = 0.002;
  } else {
    if (*a.scene != "demo") throw UsageError("--scene: unknown scene '" + *a.scene + "' (valid: demo)");
    if (a.rotate) throw UsageError("--rotate does not apply to a scene (each part has its own pose)");
    scene = demo_scene(a.scale.value_or(1.0));
    o.pitch = 0.002;
  }
  if (a.pitch) o.pitch = *a.pitch;
  apply_thickness(a, scene);
  generate(scene, noise_options(a, o), *a.out, format_for(a, *a.out, "xyz"), preset);
  return 0;
}

}  // namespace

int main(int argc, char** argv) {
  try {
    return run(argc, argv);
  } catch (const UsageError& e) {
    std::fprintf(stderr, "hg-gen: %s\n", e.what());
    return 2;
  } catch (const hg::runtime::ConfigError& e) {  // a bad option: names it
    std::fprintf(stderr, "hg-gen: %s\n", e.what());
    return 2;
  } catch (const std::invalid_argument& e) {
    std::fprintf(stderr, "hg-gen: %s\n", e.what());
    return 2;
  } catch (const std::exception& e) {
    std::fprintf(stderr, "hg-gen: %s\n", e.what());
    return 1;
  }
}
