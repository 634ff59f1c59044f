// hg-core-timing: times the outline core (triangulate, alpha, loops) on one cloud file in several
// insertion orders, median of runs in one process, with the search counters per inserted point.
// Not a test (no timed assertions anywhere); the figures of docs/outline-core-performance.md.
//   hg-core-timing FILE [--runs N] [--only scan-asis|scan-hilbert|scan-brio|shuf-asis|shuf-hilbert|shuf-brio]
#include <algorithm>
#include <chrono>
#include <cstdio>
#include <cstring>
#include <random>
#include <string>
#include <vector>

#include "outline_io/cloud.hpp"
#include "outline_core/outline.hpp"
#include "runtime/params.hpp"

using namespace hg::outline;

namespace {

struct Config {
  const char* name;
  bool shuffled;
  Order order;
};

double median(std::vector<double> v) {
  std::sort(v.begin(), v.end());
  return v.empty() ? 0 : v[v.size() / 2];
}

constexpr const char* kUsageHead =
    "usage: hg-core-timing FILE [options]\n"
    "Times the outline core's stages on a point-cloud file per insertion order (docs/BENCHMARKS.md).\n";

std::vector<hg::runtime::Param> timing_params() {
  using namespace hg::runtime;
  std::vector<Param> params = {
      positional(text_param("file", "", "the point-cloud file (xyz, csv, pcd, ply)")),
      integer_param("runs", "5", "runs per insertion order (median)", 1, 1e6),
      text_param("only", "", "only this insertion order (shuf-asis runs only when asked for)",
                 {"scan-asis", "scan-hilbert", "scan-brio", "shuf-asis", "shuf-hilbert", "shuf-brio"}),
      text_param("mode", "dshi", "the triangulation's point location", {"ordinary", "ds", "dshi"})};
  set_value_names(params, {{"file", "FILE"}, {"runs", "N"}, {"only", "CONFIG"}, {"mode", "M"}});
  return params;
}

}  // namespace

int main(int argc, char** argv) {
  hg::runtime::Params p(timing_params());
  if (const int rc = hg::runtime::parse_tool(p, argc, argv, "hg-core-timing", hg::runtime::usage_with(kUsageHead));
      rc >= 0)
    return rc;
  if (!p.given("file")) {  // one line (the failure contract, docs/RUNNING.md)
    std::fprintf(stderr, "hg-core-timing: command line: give FILE (see --help)\n");
    return 2;
  }
  const std::string file = p.text("file"), only = p.given("only") ? p.text("only") : "";
  const int runs = int(p.integer("runs"));
  const Mode mode = parse_mode(p.text("mode"));
  std::vector<Vec2> scan, shuf;
  try {
    io::Cloud cloud = io::read_cloud_file(file);
    scan = io::to_plane(cloud, file).points;
  } catch (const std::exception& e) {  // a bad input file (ReadError names the file)
    std::fprintf(stderr, "hg-core-timing: %s\n", e.what());
    return 2;
  }
  shuf = scan;
  std::mt19937_64 rng(12345);
  std::shuffle(shuf.begin(), shuf.end(), rng);

  const Config configs[] = {{"scan-asis", false, Order::AsIs}, {"scan-hilbert", false, Order::Hilbert},
                            {"scan-brio", false, Order::Brio}, {"shuf-hilbert", true, Order::Hilbert},
                            {"shuf-brio", true, Order::Brio},  {"shuf-asis", true, Order::AsIs}};
  std::printf("%s: %zu points, %d runs, mode %s\n", file.c_str(), scan.size(), runs, to_string(mode));
  std::printf("%-13s %9s %9s %8s %8s %9s | %7s %7s %7s %7s\n", "config", "total_ms", "tri_ms", "alpha_ms", "loops_ms",
              "loops", "cav/pt", "inc/pt", "ori/pt", "loc/pt");
  for (const Config& c : configs) {
    if (!only.empty() && only != c.name) continue;
    if (only.empty() && !std::strcmp(c.name, "shuf-asis")) continue;  // minutes on 1.5 M points: on request only
    std::vector<double> tot, tri, alp, lop;
    Result r;
    Options o;
    o.mode = mode;
    o.order = c.order;
    o.threads = 1;  // the one-thread core, as outline-core-performance.md measures it
    for (int k = 0; k < runs; ++k) {
      r = compute_outline(c.shuffled ? shuf : scan, o);
      tot.push_back(r.time.total_ms);
      tri.push_back(r.time.triangulate_ms);
      alp.push_back(r.time.alpha_ms);
      lop.push_back(r.time.loops_ms);
    }
    const double n = static_cast<double>(r.points_used);
    std::printf("%-13s %9.1f %9.1f %8.1f %8.1f %9zu | %7.2f %7.2f %7.2f %7.2f\n", c.name, median(tot), median(tri),
                median(alp), median(lop), r.loops.size(), r.stats.cavity_triangles / n, r.stats.incircle_tests / n,
                r.stats.orient_tests / n, r.stats.search_cost_locate / n);
  }
  return 0;
}
