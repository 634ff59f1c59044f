// hg-core-timing: times the outline core (triangulate, alpha, loops) on one cloud file in several
// insertion orders, median of runs in one process, with the search counters per inserted point.
// Not a test (no timed assertions anywhere); the figures of docs/outline-core-performance.md.
//   hg-core-timing FILE [--runs N] [--only scan-asis|scan-hilbert|scan-brio|shuf-asis|shuf-hilbert|shuf-brio]
//   hg-core-timing FILE --profile [--threads N] [--runs N]: CPU time per stage (docs/BENCHMARKS-core.md)
#include <algorithm>
#include <chrono>
#include <cstdio>
#include <cstring>
#include <random>
#include <string>
#include <thread>
#include <vector>

#include <sys/resource.h>

#include "outline_core/alpha.hpp"
#include "outline_core/delaunay.hpp"
#include "outline_io/cloud.hpp"
#include "outline_core/outline.hpp"
#include "outline_core/threads.hpp"
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
    "Times the outline core's stages on a point-cloud file per insertion order; with --profile, what each\n"
    "stage costs each thread; with --pair, two one-thread outlines at once against one alone\n"
    "(docs/outline-core-performance.md, docs/BENCHMARKS-core.md).\n";

std::vector<hg::runtime::Param> timing_params() {
  using namespace hg::runtime;
  std::vector<Param> params = {
      positional(text_param("file", "", "the point-cloud file (xyz, csv, pcd, ply)")),
      integer_param("runs", "5", "runs per insertion order (median)", 1, 1e6),
      text_param("only", "", "only this insertion order (shuf-asis runs only when asked for)",
                 {"scan-asis", "scan-hilbert", "scan-brio", "shuf-asis", "shuf-hilbert", "shuf-brio"}),
      text_param("mode", "dshi", "the triangulation's point location", {"ordinary", "ds", "dshi"}),
      flag_param("profile",
                 "instead: the CPU time (user + system, per thread), page faults and wall time of each stage of the "
                 "default outline (scan order, BRIO) on --threads strips, medians of --runs"),
      integer_param("threads", "1", "strips of --profile (1: the one-thread path)", 1, 64),
      flag_param("pair",
                 "instead: the default one-thread outline alone, then two of them at once on two threads, "
                 "alternated --runs times: what a second core gives this workload on this machine")};
  set_value_names(params, {{"file", "FILE"}, {"runs", "N"}, {"only", "CONFIG"}, {"mode", "M"}, {"threads", "N"}});
  return params;
}

// The calling thread's CPU time, faults and wall clock, as the split's StageCost counts them.
struct Mark {
  rusage r;
  std::chrono::steady_clock::time_point w;
  static Mark now() {
    Mark m;
    getrusage(RUSAGE_THREAD, &m.r);
    m.w = std::chrono::steady_clock::now();
    return m;
  }
};
StageCost between(const Mark& a, const Mark& b) {
  auto ms = [](const timeval& x, const timeval& y) {
    return static_cast<double>(y.tv_sec - x.tv_sec) * 1e3 + static_cast<double>(y.tv_usec - x.tv_usec) * 1e-3;
  };
  return {ms(a.r.ru_utime, b.r.ru_utime), ms(a.r.ru_stime, b.r.ru_stime),
          std::chrono::duration<double, std::milli>(b.w - a.w).count(), b.r.ru_minflt - a.r.ru_minflt,
          b.r.ru_nvcsw - a.r.ru_nvcsw};
}

// Per stage name, one StageCost a run; printed as medians.
using Stages = std::vector<std::pair<std::string, std::vector<StageCost>>>;
void add(Stages& st, std::size_t& k, const std::string& name, const StageCost& c) {
  if (k == st.size()) st.push_back({name, {}});
  st[k++].second.push_back(c);
}

void print_stages(const Stages& st) {
  std::printf("%-26s %9s %9s %9s %9s %9s\n", "stage", "cpu_ms", "sys_ms", "faults", "blocked", "wall_ms");
  for (const auto& [name, runs] : st) {
    std::vector<double> cpu, sys, flt, blk, wall;
    for (const StageCost& c : runs) {
      cpu.push_back(c.cpu_ms()), sys.push_back(c.sys_ms), flt.push_back(double(c.faults));
      blk.push_back(double(c.blocked)), wall.push_back(c.wall_ms);
    }
    std::printf("%-26s %9.1f %9.1f %9.0f %9.0f %9.1f\n", name.c_str(), median(cpu), median(sys), median(flt),
                median(blk), median(wall));
  }
}

// The one-thread path's stages as compute_outline runs them (the insertion order also alone, first).
void profile_one_thread(const std::vector<Vec2>& pts, const Options& o, Stages& st) {
  std::size_t k = 0;
  const Mark m0 = Mark::now();
  { const std::vector<std::uint32_t> order = insertion_order(pts, o.order); }
  const Mark m1 = Mark::now();
  const Triangulation T = triangulate(pts, o.mode, o.order);
  const Mark m2 = Mark::now();
  const double nn = median_nn_spacing(T);
  const TriangleScan scan = scan_triangles(T);
  const Mark m3 = Mark::now();
  const double R = o.alpha_radius > 0 ? o.alpha_radius : automatic_factor(nn / scan.spacing, T.inserted) * scan.spacing;
  const std::vector<std::uint8_t> inside = classify_alpha(T, R, false, scan);
  const Mark m4 = Mark::now();
  const std::vector<Loop> loops = extract_loops(T, inside, pts);
  const Mark m5 = Mark::now();
  add(st, k, "order alone (not in total)", between(m0, m1));
  add(st, k, "triangulate (order+insert)", between(m1, m2));
  add(st, k, "medians, scan", between(m2, m3));
  add(st, k, "classify", between(m3, m4));
  add(st, k, "loops", between(m4, m5));
  add(st, k, "total", between(m1, m5));
}

// The split's stages per strip, then the serial ones, as run_threaded reports them.
bool profile_strips(const std::vector<Vec2>& pts, const Options& o, int threads, Stages& st) {
  std::size_t k = 0;
  Result r;
  StripSurvey sv;
  const Mark m0 = Mark::now();
  if (!run_threaded(pts, o, threads, r, &sv)) return false;
  const Mark m1 = Mark::now();
  const SplitProfile& p = sv.profile;
  add(st, k, "serial: split", p.split);
  for (std::size_t i = 0; i < p.strips.size(); ++i) {
    const StripProfile& s = p.strips[i];
    const std::string n = "strip " + std::to_string(i) + ": ";
    const std::pair<const char*, const StageCost*> parts[] = {{"zone", &s.zone},
                                                              {"order+copy", &s.order},
                                                              {"wait (points)", &s.wait_points},
                                                              {"insert", &s.insert},
                                                              {"nn", &s.nn},
                                                              {"wait (nn)", &s.wait_nn},
                                                              {"survey", &s.survey},
                                                              {"cells", &s.cells},
                                                              {"check", &s.check},
                                                              {"edges", &s.edges}};
    for (const auto& [name, c] : parts) add(st, k, n + name, *c);
  }
  add(st, k, "serial: merge", p.merge);
  add(st, k, "serial: chain", p.chain);
  add(st, k, "total (calling thread)", between(m0, m1));
  return true;
}

int run_profile(const std::vector<Vec2>& scan, Mode mode, int threads, int runs) {
  Options o;
  o.mode = mode;
  o.order = Order::Brio;
  o.threads = threads;
  o.min_points_per_thread = 1;
  Stages st;
  for (int k = 0; k < runs; ++k) {
    if (threads == 1) {
      profile_one_thread(scan, o, st);
    } else if (!profile_strips(scan, o, threads, st)) {
      std::fprintf(stderr, "hg-core-timing: the split on %d strips fell back to one thread for this cloud\n", threads);
      return 1;
    }
  }
  std::printf("profile: %zu points, %d runs, %d thread(s), medians\n", scan.size(), runs, threads);
  print_stages(st);
  return 0;
}

// Wall and thread CPU time (user + system) of one default one-thread outline, ms.
StageCost one_outline(const std::vector<Vec2>& pts, const Options& o) {
  const Mark a = Mark::now();
  const Result r = compute_outline(pts, o);
  return between(a, Mark::now());
}

// One outline alone, then two at once (each the whole cloud, on its own thread): with the two at once
// taking `together`, a perfect split of one outline over the two cores would take together / 2, so
// together / (2 alone) is the best ratio of 2 threads to 1 that any design reaches here. The CPU times
// say the same on a loaded machine, where the wall times do not: a copy's CPU time grows when the other
// core's work slows it (shared caches, memory, a shared physical core).
int run_pair(const std::vector<Vec2>& scan, Mode mode, int runs) {
  Options o;
  o.mode = mode;
  o.order = Order::Brio;
  o.threads = 1;
  std::vector<double> alone, together, cpu_alone, cpu_together;
  for (int k = 0; k < runs; ++k) {
    const StageCost one = one_outline(scan, o);
    alone.push_back(one.wall_ms), cpu_alone.push_back(one.cpu_ms());
    StageCost a, b;
    std::thread other([&] { a = one_outline(scan, o); });
    b = one_outline(scan, o);
    other.join();
    together.push_back(std::max(a.wall_ms, b.wall_ms));
    cpu_together.push_back(a.cpu_ms()), cpu_together.push_back(b.cpu_ms());
  }
  const double m1 = median(alone), m2 = median(together), c1 = median(cpu_alone), c2 = median(cpu_together);
  std::printf("pair: %zu points, %d runs (medians)\n", scan.size(), runs);
  std::printf(
      "  wall: one outline alone %.1f ms, two at once %.1f ms (the slower): %.2f x, best 2-thread / 1-thread "
      "ratio %.2f\n",
      m1, m2, m2 / m1, m2 / (2 * m1));
  std::printf("  thread CPU: alone %.1f ms, each of two at once %.1f ms: %.2f x\n", c1, c2, c2 / c1);
  return 0;
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
    hg::outline_io::Cloud cloud = hg::outline_io::read_cloud_file(file);
    scan = hg::outline_io::to_plane(cloud, file).points;
  } catch (const std::exception& e) {  // a bad input file (ReadError names the file)
    std::fprintf(stderr, "hg-core-timing: %s\n", e.what());
    return 2;
  }
  if (p.flag("pair")) return run_pair(scan, mode, runs);
  if (p.flag("profile")) return run_profile(scan, mode, int(p.integer("threads")), runs);
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
