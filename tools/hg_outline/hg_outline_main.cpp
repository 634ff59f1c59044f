// hg-outline: the plate's outline from a point-cloud file, as JSON (+ optional pictures and triangles).
#include <chrono>
#include <cmath>
#include <cstdio>
#include <cstring>
#include <iostream>
#include <new>
#include <string>
#include <string_view>
#include <limits>
#include <vector>

#include "outline_io/cloud.hpp"
#include "outline_io/outline_writers.hpp"
#include "outline_core/alpha.hpp"  // kDefaultAutoFactor, for --help
#include "outline_core/outline.hpp"
#include "runtime/params.hpp"

namespace {

// What --help says before and after the options (the options themselves come from their declarations).
constexpr const char* kUsageHead = R"(usage: hg-outline INPUT [options]

Finds the outline of a flat part (outer edges and cut-outs) in a point cloud: Delaunay triangulation
(DSHI point location), alpha shape by circumradius, boundary loops with holes.

INPUT  .xyz .txt .csv  one point per line: x y [z] (blanks or commas; '#' comments; an all-text
                       header line is skipped; columns after the third are ignored)
       .pcd            DATA ascii, binary or binary_compressed; fields x y [z] of any type
       .ply            ascii or binary_little_endian; vertex x y [z]; other elements skipped
       3-D input is projected onto its least-squares plane; loops are then in plane coordinates
       (plus "points_3d" and "plane" in the JSON). Planar input (no z, or all z equal) keeps x, y.
       Points with a NaN or infinite coordinate (no-return pixels, e.g. of an organized PCD with
       is_dense false) are skipped and counted: "points_skipped" in the JSON and the summary line;
       indices (loops, --triangles) stay positions in the file. Error: fewer than 3 distinct finite
       points, or all of them collinear (in the plane or in space).

options (command line > --config FILE > default); h is the point spacing, sqrt(2 x median Delaunay
triangle area), which in-plane noise does not shrink:
)";

constexpr const char* kUsageTail =
    R"(  --config FILE                    a YAML file with any of these options as keys (the command line wins)
  -h, --help                       this text; --help-markdown: the options as a table; --version
Long options that take a value also accept --option=VALUE.

The JSON holds the loops and the run's figures; search_cost (triangles visited, the paper's measure) is
search_cost_locate (point location: the walk, or ordinary's test of every triangle) + search_cost_cavity
(the cavity search); incircle_tests, orient_tests; time_ms per stage.
Every output file is written whole or not at all; on any error nothing is written.
exit status: 0 done, 1 processing failed (out of memory, an output not written), 2 a bad option or input file
(one line naming the file and line/byte)
)";

struct Args {
  std::string input, json_out, svg_out, png_out, tri_out;
  hg::outline::Options opt;
  bool draw_triangles = false;
};

struct UsageError : std::runtime_error {
  using std::runtime_error::runtime_error;
};

std::string number_text(double v) {
  char text[32];
  std::snprintf(text, sizeof text, "%g", v);
  return text;
}

// The options, declared once (runtime::Params parses them, checks types and ranges, and prints --help and
// --help-markdown from these declarations).
std::vector<hg::runtime::Param> outline_params() {
  using namespace hg::runtime;
  constexpr double inf = std::numeric_limits<double>::infinity();
  Param output = text_param("output", "", "write the outline JSON to FILE (default: print it on stdout)");
  output.alias = "-o";
  std::vector<Param> params = {
      number_param("alpha-radius", "",
                   "triangles with circumradius > R are outside (input units); default: automatic, K x point "
                   "spacing h",
                   0, inf, true),
      number_param("auto-factor", "",
                   "the K of the automatic radius (default: " + number_text(hg::outline::kDefaultAutoFactor) +
                       " for a regular cloud, rising to 2.1-2.8 as the cloud gets as irregular as a random point "
                       "set, measured by median nearest-neighbour distance / h; docs/outline-auto-radius.md)",
                   0, inf, true),
      text_param("alpha-mode", "global",
                 "global: one automatic radius; local: each triangle its own radius, K x the spacing around its "
                 "vertices, for clouds whose spacing varies (tilted camera); not with --alpha-radius",
                 {"global", "local"}),
      number_param("min-hole-spacings", "",
                   "drop holes smaller in area than (M x h)^2 as dropout gaps (default " +
                       number_text(hg::outline::kDefaultMinHoleSpacings) +
                       ": a 3x3 gap of missing points is dropped; 0 keeps every hole)",
                   0),
      text_param("mode", "dshi", "point location", {"ordinary", "ds", "dshi"}),
      text_param("order", "brio",
                 "insertion order: brio (biased randomized rounds along a Hilbert curve), hilbert, or as-is (file "
                 "order, slow on scan-order grids; docs/outline-core-performance.md)",
                 {"brio", "hilbert", "as-is"}),
      flag_param("outer-only", "remove only big triangles connected to the outside (no holes)"),
      integer_param("threads", "0",
                    "threads (0: all cores): the cloud is split into vertical strips, one per thread, with loops "
                    "identical to one thread's; one thread below 100 k points per strip, with --outer-only, "
                    "--alpha-mode local or --mode other than dshi, and when the strips' checks find the split unsafe "
                    "for the cloud; \"threads\" in the JSON and the summary line say how many ran",
                    0, 1024),
      output,
      text_param("svg", "",
                 "write an SVG picture: points, outer loops white, holes light blue (the station's colours)"),
      text_param("png", "", "write a PNG picture of the same"),
      flag_param("draw-triangles", "also draw the Delaunay triangles in the SVG/PNG"),
      text_param("triangles", "",
                 "write the Delaunay triangles, one \"i j k\" per line, 0-based indices into the points as read (a "
                 "merged duplicate is its first occurrence)")};
  set_value_names(params, {{"alpha-radius", "R"},
                           {"auto-factor", "K"},
                           {"min-hole-spacings", "M"},
                           {"threads", "N"},
                           {"output", "FILE"},
                           {"svg", "FILE"},
                           {"png", "FILE"},
                           {"triangles", "FILE"}});
  return params;
}

Args args_from(const hg::runtime::Params& p) {
  Args a;
  if (p.positional().size() != 1)
    throw UsageError(p.positional().empty()
                         ? "no input file"
                         : "more than one input file ('" + p.positional()[0] + "', '" + p.positional()[1] + "')");
  a.input = p.positional()[0];
  const bool have_alpha = p.given("alpha-radius"), have_factor = p.given("auto-factor");
  if (have_alpha) a.opt.alpha_radius = p.number("alpha-radius");
  if (have_factor) a.opt.auto_factor = p.number("auto-factor");
  if (p.given("min-hole-spacings")) a.opt.min_hole_spacings = p.number("min-hole-spacings");
  a.opt.alpha_mode = hg::outline::parse_alpha_mode(p.text("alpha-mode"));
  a.opt.mode = hg::outline::parse_mode(p.text("mode"));
  a.opt.order = hg::outline::parse_order(p.text("order"));
  a.opt.outer_only = p.flag("outer-only");
  a.opt.threads = static_cast<int>(p.integer("threads"));
  a.draw_triangles = p.flag("draw-triangles");
  a.json_out = p.text("output"), a.svg_out = p.text("svg"), a.png_out = p.text("png"), a.tri_out = p.text("triangles");
  if (have_alpha && have_factor) throw UsageError("give --alpha-radius or --auto-factor, not both");
  if (have_alpha && a.opt.alpha_mode == hg::outline::AlphaMode::Local)
    throw UsageError("--alpha-mode local sets the radius per triangle: not with --alpha-radius");
  for (const std::string* out : {&a.json_out, &a.svg_out, &a.png_out, &a.tri_out})
    if (!out->empty() && *out == a.input) throw UsageError("output file '" + *out + "' is the input file");
  return a;
}

void usage(std::FILE* f, const hg::runtime::Params& params) {
  std::fputs(kUsageHead, f);
  params.print_options(f);
  std::fputs(kUsageTail, f);
}

double ms_since(std::chrono::steady_clock::time_point t0) {
  return std::chrono::duration<double, std::milli>(std::chrono::steady_clock::now() - t0).count();
}

// The one line hg-outline prints when the JSON goes to a file.
void print_summary(const Args& args, const hg::outline::Result& result, double ms) {
  std::size_t holes = 0;
  for (auto& l : result.loops) holes += l.hole;
  std::printf(
      "hg-outline: %s: %zu points (%zu skipped, %zu used), %zu outer loops, %zu holes (%zu small dropped), R = %g%s, %d thread%s, %.1f ms -> %s\n",
      args.input.c_str(), result.points_read, result.points_skipped, result.points_used, result.loops.size() - holes,
      holes, result.holes_dropped, result.alpha_radius,
      result.alpha_mode == hg::outline::AlphaMode::Local ? " (local, per triangle)"
      : result.alpha_automatic                           ? " (automatic)"
                                                         : "",
      result.threads_used, result.threads_used == 1 ? "" : "s", ms, args.json_out.c_str());
}

}  // namespace

int main(int argc, char** argv) {
  namespace io = hg::outline_io;
  Args args;
  try {
    hg::runtime::Params params(outline_params());
    const auto action = params.parse(argc, argv);
    if (action != hg::runtime::Params::Action::Run) return hg::runtime::answer(action, "hg-outline", params, usage);
    args = args_from(params);
  } catch (const std::exception& e) {  // UsageError, runtime::ConfigError
    std::fprintf(stderr, "hg-outline: %s (see --help)\n", e.what());
    return hg::runtime::kExitBadInput;
  }

  try {
    auto t0 = std::chrono::steady_clock::now();
    io::Cloud cloud = io::read_cloud_file(args.input);
    io::RunInfo info;
    info.input = args.input;
    info.format = cloud.format;
    info.has_z = cloud.has_z;
    info.read_ms = ms_since(t0);

    auto t1 = std::chrono::steady_clock::now();
    io::PlanarPoints planar = io::to_plane(cloud, args.input);
    cloud = io::Cloud{};  // the 3-D copy is no longer needed: give its memory back before triangulating
    info.project_ms = ms_since(t1);

    args.opt.keep_triangles =
        !args.tri_out.empty() || (args.draw_triangles && (!args.svg_out.empty() || !args.png_out.empty()));
    hg::outline::Result result;
    try {
      // Without pictures the points are not needed afterwards: the core takes them over and frees them
      // once it holds its exact copy (lower peak memory on big clouds).
      if (args.svg_out.empty() && args.png_out.empty())
        result = hg::outline::compute_outline(std::move(planar.points), args.opt);
      else
        result = hg::outline::compute_outline(planar.points, args.opt);
    } catch (const hg::outline::OutlineError& e) {
      throw io::ReadError(args.input + ": " + e.what());
    }

    // Everything is produced before anything is renamed into place.
    io::StagedFiles files;
    const std::string json =
        io::outline_json(result, planar, info).dump(2, ' ', false, nlohmann::json::error_handler_t::replace) + "\n";
    if (!args.json_out.empty()) files.stage(args.json_out, json);
    if (!args.tri_out.empty()) files.stage(args.tri_out, io::triangles_text(result));
    if (!args.svg_out.empty()) files.stage(args.svg_out, io::render_svg(planar.points, result, args.draw_triangles));
    if (!args.png_out.empty()) {
      auto png = io::render_png(planar.points, result, args.draw_triangles);
      files.stage(args.png_out, png.data(), png.size());
    }
    files.commit();

    if (args.json_out.empty()) std::fwrite(json.data(), 1, json.size(), stdout);
    else
      print_summary(args, result, info.project_ms + result.time.total_ms);
    if (std::fflush(stdout) != 0) {
      std::fprintf(stderr, "hg-outline: error: writing to stdout failed\n");
      return 1;
    }
    return 0;
  } catch (const std::bad_alloc&) {
    std::fprintf(stderr, "hg-outline: error: %s: out of memory\n", args.input.c_str());
  } catch (const io::ReadError& e) {  // a bad input file: names the file itself
    std::fprintf(stderr, "hg-outline: error: %s\n", e.what());
    return hg::runtime::kExitBadInput;
  } catch (const hg::outline::OutlineError& e) {  // the input's points cannot be outlined (collinear, too few)
    std::fprintf(stderr, "hg-outline: error: %s: %s\n", args.input.c_str(), e.what());
    return hg::runtime::kExitBadInput;
  } catch (const io::WriteError& e) {  // names the output file
    std::fprintf(stderr, "hg-outline: error: %s\n", e.what());
  } catch (const std::exception& e) {
    std::fprintf(stderr, "hg-outline: error: %s: %s\n", args.input.c_str(), e.what());
  }
  return hg::runtime::kExitFailed;
}
