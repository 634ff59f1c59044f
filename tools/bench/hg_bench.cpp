// hg-bench: reproduces the paper's Tables 2, 3, 7 and 8 (search cost and time per point-location mode) on
// generated clouds of the paper's sizes, times our other insertion orders on a shuffled copy, and runs the
// peers (CGAL, PCL) on the same points with the same R when they were built in. Writes a markdown report
// and a PNG plot. A benchmark, not a test: it asserts nothing about time, it prints figures.
#include <fcntl.h>
#include <sys/resource.h>
#include <sys/utsname.h>
#include <sys/wait.h>
#include <unistd.h>

#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <cstring>
#include <ctime>
#include <filesystem>
#include <fstream>
#include <functional>
#include <iostream>
#include <random>
#include <set>
#include <sstream>
#include <stdexcept>
#include <string>
#include <vector>

#include <nlohmann/json.hpp>

#include "bench.hpp"
#include "outline_core/alpha.hpp"
#include "outline_core/delaunay.hpp"
#include "outline_io/cloud.hpp"
#include "outline_core/outline.hpp"
#include "sim/partgen/presets.hpp"
#include "sim/partgen/synth.hpp"
#include "sim/partgen/writers.hpp"
#include "peers.hpp"
#include "runtime/params.hpp"

namespace hg::bench {
namespace {

using outline::Vec2;
using Clock = std::chrono::steady_clock;

constexpr bool kHaveCgal =
#ifdef HG_BENCH_CGAL
    true;
#else
    false;
#endif
constexpr bool kHaveDelaunator =
#ifdef HG_BENCH_DELAUNATOR
    true;
#else
    false;
#endif
constexpr bool kHavePcl =
#ifdef HG_BENCH_PCL
    true;
#else
    false;
#endif

struct Args {
  std::set<std::string> sets{"low", "down", "high"};
  std::vector<std::string> only;  // preset names; overrides sets
  int runs = 5, slow_runs = 3, slow_runs_high = 1, ordinary_runs = 3;
  double noise = 0.05;  // in-plane sigma as a fraction of the pitch
  bool jagged = true;
  double dropout = 0;
  std::uint64_t seed = 7;
  int band_rows = 8;
  int threads = 2;  // of the multi-thread column (Options::threads)
  bool cgal = true, alpha_shape = true, delaunator = true, pcl = true, memory = true;
  std::string memory_preset = "high-4";
  std::string md, png, include, tmp = "/tmp";
};

void usage(std::FILE* f, const runtime::Params& params) {
  std::fprintf(f,
               "usage: hg-bench [options]\n"
               "Reproduces the paper's Tables 2, 3, 7, 8 (search cost and time per point-location mode) on generated\n"
               "clouds of the paper's sizes, times our insertion orders, and runs the peers built in on the same\n"
               "points with the same R, all in one run; writes a markdown report (and a PNG plot). Clouds come from\n"
               "hg_partgen's presets (low-*: paper Table 1, down-*: Table 6, high-*: Table 4), in scan-line order;\n"
               "ordinary (O(n^2)) and ds run on low and down only, as in the paper.\n"
               "Peers: CGAL %s, delaunator-cpp %s, PCL %s.\n\n"
               "options (command line > --config FILE > default):\n",
               kHaveCgal ? "built in" : "not built", kHaveDelaunator ? "built in" : "not built",
               kHavePcl ? "built in" : "not built");
  params.print_options(f);
  std::fprintf(f,
               "  --config FILE                      YAML config file (keys as the options above, without --)\n"
               "  --help, --help-markdown, --version this text, the options as a Markdown table, the version\n");
}

std::vector<std::string> split(const std::string& s) {
  std::vector<std::string> out;
  std::stringstream ss(s);
  for (std::string item; std::getline(ss, item, ',');)
    if (!item.empty()) out.push_back(item);
  return out;
}

// The options, declared once (runtime::Params checks types and ranges; --help-markdown lists them).
std::vector<runtime::Param> bench_params() {
  using namespace runtime;
  return {
      text_param("sets", "low,down,high", "the preset sets to run, comma-separated: low, down, high"),
      text_param("only", "", "preset names, comma-separated (e.g. high-4); overrides --sets"),
      integer_param("runs", "5", "timed runs per method", 1, 1000),
      integer_param("slow-runs", "3", "runs of CGAL Alpha_shape_2 and PCL on low and down", 0, 1000),
      integer_param("slow-runs-high", "1", "runs of CGAL Alpha_shape_2 and PCL on high", 0, 1000),
      integer_param("ordinary-runs", "3", "runs of the O(n^2) ordinary mode", 0, 1000),
      number_param("noise", "0.05", "in-plane Gaussian noise, sigma = F x pitch", 0, 10),
      flag_param("no-jagged", "pixel-centre rule at the edges (default: jagged edges, like a camera)"),
      number_param("dropout", "0", "fraction of pixels lost at random", 0, 0.9),
      integer_param("seed", "7", "random seed of the clouds and of the shuffle", 0, 1e15),
      integer_param("band-rows", "8", "rows per band of the banded-order experiment", 1, 4096),
      integer_param("threads", "2", "threads of our multi-thread column (one thread is always measured too)", 2, 256),
      flag_param("no-cgal", "leave out the CGAL peers"),
      flag_param("no-alpha-shape", "leave out CGAL Alpha_shape_2"),
      flag_param("no-delaunator", "leave out the delaunator-cpp peer"),
      flag_param("no-pcl", "leave out PCL ConcaveHull"),
      flag_param("no-memory", "skip the peak-memory measurement of whole processes"),
      text_param("memory-preset", "high-4", "the preset whose cloud the memory measurement uses"),
      text_param("md", "", "write the markdown report here (default: standard output)"),
      text_param("png", "", "write the PNG plot here"),
      text_param("include", "", "a markdown file appended to the report (a profile, by hand)"),
      text_param("tmp", "/tmp", "directory for the memory measurement's cloud file")};
}

Args args_from(const runtime::Params& p) {
  if (!p.positional().empty()) throw p.error("sets", "unexpected argument '" + p.positional()[0] + "'");
  Args a;
  a.sets.clear();
  for (const auto& s : split(p.text("sets"))) {
    if (s != "low" && s != "down" && s != "high") throw p.error("sets", "unknown set '" + s + "' (low, down, high)");
    a.sets.insert(s);
  }
  a.only = split(p.text("only"));
  a.runs = static_cast<int>(p.integer("runs"));
  a.slow_runs = static_cast<int>(p.integer("slow-runs"));
  a.slow_runs_high = static_cast<int>(p.integer("slow-runs-high"));
  a.ordinary_runs = static_cast<int>(p.integer("ordinary-runs"));
  a.noise = p.number("noise");
  a.jagged = !p.flag("no-jagged");
  a.dropout = p.number("dropout");
  a.seed = static_cast<std::uint64_t>(p.integer("seed"));
  a.band_rows = static_cast<int>(p.integer("band-rows"));
  a.threads = static_cast<int>(p.integer("threads"));
  a.cgal = !p.flag("no-cgal") && kHaveCgal;
  a.alpha_shape = !p.flag("no-alpha-shape") && a.cgal;
  a.delaunator = !p.flag("no-delaunator") && kHaveDelaunator;
  a.pcl = !p.flag("no-pcl") && kHavePcl;
  a.memory = !p.flag("no-memory");
  a.memory_preset = p.text("memory-preset");
  a.md = p.text("md"), a.png = p.text("png"), a.include = p.text("include"), a.tmp = p.text("tmp");
  return a;
}

std::string read_first_line(const std::string& path) {
  std::ifstream f(path);
  std::string line;
  std::getline(f, line);
  return line;
}

std::string machine_facts() {
  std::string model;
  std::ifstream cpu("/proc/cpuinfo");
  for (std::string line; std::getline(cpu, line);)
    if (line.rfind("model name", 0) == 0) {
      model = line.substr(line.find(':') + 2);
      break;
    }
  long mem_kb = 0;
  std::ifstream mi("/proc/meminfo");
  for (std::string line; std::getline(mi, line);)
    if (line.rfind("MemTotal:", 0) == 0) mem_kb = std::atol(line.c_str() + 9);
  utsname u{};
  uname(&u);
  char buf[512];
  std::snprintf(buf, sizeof buf, "%s, %ld logical CPUs, %.1f GB RAM, Linux %s", model.c_str(),
                sysconf(_SC_NPROCESSORS_ONLN), mem_kb / 1048576.0, u.release);
  return buf;
}

// ---- clouds ----

struct BenchCloud {
  partgen::Preset preset;
  std::vector<Vec2> scan;      // scan-line order, as the camera gives them
  std::vector<Vec2> shuffled;  // the same points in a random order
  std::vector<std::int32_t> row, col;
};

partgen::CloudOptions cloud_options(const partgen::Preset& p, const Args& a) {
  partgen::CloudOptions o = partgen::preset_options(p);
  o.in_plane_sigma = a.noise * o.pitch;
  o.jagged = a.jagged;
  o.dropout = a.dropout;
  o.seed = a.seed;
  return o;
}

BenchCloud make_cloud(const partgen::Preset& p, const Args& a) {
  const partgen::Cloud c = partgen::synthesize(partgen::preset_scene(p), cloud_options(p, a));
  BenchCloud b;
  b.preset = p;
  b.scan.resize(c.size());
  for (std::size_t i = 0; i < c.size(); ++i) b.scan[i] = {c.xyz[3 * i], c.xyz[3 * i + 1]};
  b.row = c.pixel_row;
  b.col = c.pixel_col;
  b.shuffled = b.scan;
  std::mt19937_64 rng(a.seed + 1000);
  std::shuffle(b.shuffled.begin(), b.shuffled.end(), rng);
  return b;
}

// Banded order (an experiment the issue asks to measure): the rows are cut into bands of B rows; each band
// is swept column by column (alternating direction from band to band), top to bottom within a column. Keeps
// the locality heritable initial needs while each new point falls next to the mesh, not beyond a straight
// row front. Computed from the pixel rows and columns an organised camera cloud carries.
std::vector<std::uint32_t> banded_order(const BenchCloud& c, int B) {
  const std::size_t n = c.scan.size();
  std::int32_t min_col = INT32_MAX, max_col = INT32_MIN, min_row = INT32_MAX, max_row = INT32_MIN;
  for (std::size_t i = 0; i < n; ++i) {
    min_col = std::min(min_col, c.col[i]);
    max_col = std::max(max_col, c.col[i]);
    min_row = std::min(min_row, c.row[i]);
    max_row = std::max(max_row, c.row[i]);
  }
  const std::size_t cols = static_cast<std::size_t>(max_col - min_col + 1);
  const std::size_t bands = static_cast<std::size_t>((max_row - min_row) / B + 1);
  std::vector<std::uint32_t> count(bands * cols + 1, 0), key(n), order(n);
  for (std::size_t i = 0; i < n; ++i) {
    const std::size_t band = static_cast<std::size_t>((c.row[i] - min_row) / B);
    const std::size_t cc = static_cast<std::size_t>(c.col[i] - min_col);
    key[i] = static_cast<std::uint32_t>(band * cols + (band % 2 ? cols - 1 - cc : cc));
    ++count[key[i] + 1];
  }
  for (std::size_t k = 1; k < count.size(); ++k) count[k] += count[k - 1];
  for (std::size_t i = 0; i < n; ++i)
    order[count[key[i]]++] = static_cast<std::uint32_t>(i);  // stable: rows stay in order
  return order;
}

// ---- our methods ----

OurStats stats_of(const outline::Result& r) {
  OurStats s;
  s.tri = r.stats;
  s.points_used = r.points_used;
  for (const auto& l : r.loops) {
    (l.hole ? s.holes : s.outer_loops) += 1;
    s.boundary_edges += l.points.size();
    s.area += l.hole ? -l.area : l.area;
  }
  return s;
}

// The same pipeline as compute_outline (triangulate, classify, loops) with a custom insertion order that
// is computed inside the timed region.
outline::Result outline_with_order(std::span<const Vec2> pts, double R,
                                   const std::function<std::vector<std::uint32_t>()>& make_order) {
  outline::Result res;
  outline::Triangulation T = outline::triangulate(pts, outline::Mode::DSHI, outline::Order::AsIs, make_order());
  res.points_used = T.inserted;
  res.stats = outline::triangulation_stats(T);
  res.nn_spacing_median = outline::median_nn_spacing(T);
  const auto inside = outline::classify_alpha(T, R, false);
  res.loops = outline::extract_loops(T, inside, pts);
  return res;
}

struct Job {
  std::string key;
  int runs;
  bool is_peer;
  std::function<void(Method&)> run;  // one timed run: appends to m.time, fills stats
};

double now_ms_since(Clock::time_point t0) {
  return std::chrono::duration<double, std::milli>(Clock::now() - t0).count();
}

// The methods timed on cloud c, all with the same radius R: our orders and modes (DS, as-is on the
// shuffled cloud and ordinary only on the small clouds) and the peers that are built and asked for.
std::vector<Job> bench_jobs(const BenchCloud& c, const Args& a, double R, bool small) {
  auto ours = [&](std::span<const Vec2> pts, outline::Mode mode, outline::Order order, int threads = 1) {
    return [pts, mode, order, R, threads](Method& m) {
      outline::Options o;
      o.alpha_radius = R;
      o.mode = mode;
      o.order = order;
      o.threads = threads;
      o.min_hole_spacings = 0;  // the raw alpha shape, comparable edge for edge with the peers'
      const auto t0 = Clock::now();
      const outline::Result r = outline::compute_outline(pts, o);
      m.time.ms.push_back(now_ms_since(t0));
      m.stats = stats_of(r);
    };
  };
  std::vector<Job> jobs;
  using outline::Mode;
  using outline::Order;
  jobs.push_back({key::ours_1t, a.runs, false, ours(c.scan, Mode::DSHI, Order::Brio, 1)});
  jobs.push_back({key::ours_nt, a.runs, false, ours(c.scan, Mode::DSHI, Order::Brio, a.threads)});
  jobs.push_back({key::dshi, a.runs, false, ours(c.scan, Mode::DSHI, Order::AsIs)});
  jobs.push_back({key::dshi_hilbert_scan, a.runs, false, ours(c.scan, Mode::DSHI, Order::Hilbert)});
  jobs.push_back({key::dshi_hilbert_shuf, a.runs, false, ours(c.shuffled, Mode::DSHI, Order::Hilbert)});
  jobs.push_back({key::dshi_brio_shuf, a.runs, false, ours(c.shuffled, Mode::DSHI, Order::Brio)});
  const int B = a.band_rows;
  jobs.push_back({key::dshi_band, a.runs, false, [&c, R, B](Method& m) {
                    const auto t0 = Clock::now();
                    const outline::Result r = outline_with_order(c.scan, R, [&] { return banded_order(c, B); });
                    m.time.ms.push_back(now_ms_since(t0));
                    m.stats = stats_of(r);
                  }});
  if (small) {
    jobs.push_back({key::ds, a.runs, false, ours(c.scan, Mode::DS, Order::AsIs)});
    jobs.push_back({key::dshi_asis_shuf, a.runs, false, ours(c.shuffled, Mode::DSHI, Order::AsIs)});
    jobs.push_back({key::ordinary, a.ordinary_runs, false, ours(c.scan, Mode::Ordinary, Order::AsIs)});
  }
  auto peer = [&](PeerOutline (*fn)(std::span<const Vec2>, double)) {
    return [&c, R, fn](Method& m) {
      const auto t0 = Clock::now();
      m.peer = fn(c.scan, R);
      m.time.ms.push_back(now_ms_since(t0));
    };
  };
  const int slow = small ? a.slow_runs : a.slow_runs_high;
#ifdef HG_BENCH_CGAL
  if (a.cgal) jobs.push_back({key::cgal_dt, a.runs, true, peer(&cgal_dt_loops)});
  if (a.alpha_shape && slow > 0) jobs.push_back({key::cgal_alpha, slow, true, peer(&cgal_alpha_shape)});
#endif
#ifdef HG_BENCH_DELAUNATOR
  if (a.delaunator) jobs.push_back({key::delaunator, a.runs, true, peer(&delaunator_dt_loops)});
#endif
#ifdef HG_BENCH_PCL
  if (a.pcl && slow > 0) jobs.push_back({key::pcl, slow, true, peer(&pcl_concave_hull)});
#endif
  (void)peer;
  (void)slow;

  return jobs;
}

// Round robin over the methods, so a burst of load from the shared machine spreads over all of them.
void run_round_robin(const std::vector<Job>& jobs, const std::string& cloud_name, CloudResult& res) {
  for (const auto& j : jobs) {
    Method m;
    m.key = j.key;
    m.is_peer = j.is_peer;
    res.methods.push_back(m);
  }
  int max_runs = 0;
  for (const auto& j : jobs) max_runs = std::max(max_runs, j.runs);
  for (int r = 0; r < max_runs; ++r)
    for (std::size_t k = 0; k < jobs.size(); ++k) {
      if (r >= jobs[k].runs) continue;
      jobs[k].run(res.methods[k]);
      std::fprintf(stderr, "  %-8s %-26s run %d: %10.2f ms\n", cloud_name.c_str(), jobs[k].key.c_str(), r + 1,
                   res.methods[k].time.ms.back());
    }
}

CloudResult bench_cloud(const BenchCloud& c, const Args& a) {
  const auto& p = c.preset;
  const bool small = p.name.rfind("high", 0) != 0;
  CloudResult res;
  res.preset = p.name;
  res.table = p.table;
  res.piece = p.piece;
  res.paper_points = p.paper_points;
  res.points = c.scan.size();
  res.pitch = p.pitch;

  // R: the product's automatic radius on the scan-order cloud; every method then gets this same R.
  {
    outline::Options o;
    const outline::Result r = outline::compute_outline(c.scan, o);
    res.alpha_radius = r.alpha_radius;
    res.nn_spacing = r.nn_spacing_median;
  }
  run_round_robin(bench_jobs(c, a, res.alpha_radius, small), p.name, res);
  return res;
}

// ---- peak memory of whole processes ----

// Runs argv through hg-bench-rss (a small parent, see rss_wrapper.c) and reads back the child's peak RSS
// (kB) and wall time; max_rss_kb = -1 if it failed.
MemoryResult run_child(const std::string& what, const std::vector<std::string>& argv_in, const std::string& dir) {
  MemoryResult m;
  m.what = what;
  for (const auto& s : argv_in) m.command += (m.command.empty() ? "" : " ") + s;
#ifdef HG_BENCH_RSS_EXE
  const std::string result_file = dir + "/rss.txt";
  std::vector<std::string> argv = {HG_BENCH_RSS_EXE, result_file};
  argv.insert(argv.end(), argv_in.begin(), argv_in.end());
  std::vector<char*> cargv;
  for (const auto& s : argv) cargv.push_back(const_cast<char*>(s.c_str()));
  cargv.push_back(nullptr);
  const pid_t pid = fork();
  if (pid < 0) {
    m.note = std::string("fork failed: ") + std::strerror(errno);
    return m;
  }
  if (pid == 0) {
    execv(cargv[0], cargv.data());
    std::fprintf(stderr, "hg-bench: cannot run %s: %s\n", cargv[0], std::strerror(errno));
    _exit(127);
  }
  int status = 0;
  if (waitpid(pid, &status, 0) < 0) {
    m.note = std::string("waitpid failed: ") + std::strerror(errno);
    return m;
  }
  std::ifstream f(result_file);
  long kb = -1;
  double wall = 0;
  int code = -1;
  if (!(f >> kb >> wall >> code)) {
    m.note = "hg-bench-rss wrote no result";
    return m;
  }
  m.wall_ms = wall;
  if (code == 0) m.max_rss_kb = kb;
  else
    m.note = "exit status " + std::to_string(code);
#else
  (void)dir;
  m.note = "hg-bench-rss not built";
#endif
  return m;
}

std::string self_exe() {
  std::error_code ec;
  const auto p = std::filesystem::read_symlink("/proc/self/exe", ec);
  return ec ? std::string("hg-bench") : p.string();
}

// Child modes (hg-bench --child-WHAT FILE R): read the file as hg-outline does, then run one method, so
// the child's peak RSS is that of a whole process doing the job.
int child_main(const std::string& what, const std::string& file, double R) {
  const outline_io::Cloud cloud = outline_io::read_cloud_file(file);
  const outline_io::PlanarPoints planar = outline_io::to_plane(cloud, file);
  if (what == "--child-read") return planar.points.size() > 2 ? 0 : 1;
#ifdef HG_BENCH_CGAL
  if (what == "--child-cgal-dt") return cgal_dt_loops(planar.points, R).boundary_edges > 0 ? 0 : 1;
#endif
#ifdef HG_BENCH_DELAUNATOR
  if (what == "--child-delaunator") return delaunator_dt_loops(planar.points, R).boundary_edges > 0 ? 0 : 1;
#endif
#ifdef HG_BENCH_PCL
  if (what == "--child-pcl") return pcl_concave_hull(planar.points, R).boundary_edges > 0 ? 0 : 1;
#endif
  (void)R;
  std::fprintf(stderr, "hg-bench: %s not available in this build\n", what.c_str());
  return 3;
}

std::vector<MemoryResult> measure_memory(const Args& a, Report& report) {
  std::vector<MemoryResult> out;
  const partgen::Preset& p = partgen::find_preset(a.memory_preset);
  const partgen::Scene scene = partgen::preset_scene(p);
  const partgen::CloudOptions opts = cloud_options(p, a);
  const partgen::Cloud c = partgen::synthesize(scene, opts);
  const std::string dir = a.tmp + "/hg-bench-" + std::to_string(getpid());
  std::filesystem::create_directories(dir);
  const std::string pcd = dir + "/" + p.name + ".pcd";
  partgen::write_pcd(c, pcd, true);
  report.memory_cloud = p.name + " (" + std::to_string(c.size()) + " points, binary PCD float32, " +
                        std::to_string(std::filesystem::file_size(pcd) / 1000000) + " MB)";
  // R for the peers: what hg-outline chose itself (read back from its JSON).
  double R = 0;
#ifdef HG_OUTLINE_EXE
  const std::string json = dir + "/outline.json";
  MemoryResult ours = run_child("hg-outline (whole process, 1 thread: read, plane, outline, write JSON)",
                                {HG_OUTLINE_EXE, pcd, "--threads", "1", "-o", json}, dir);
  try {
    std::ifstream f(json);
    const auto j = nlohmann::json::parse(f);
    R = j.at("alpha_radius").get<double>();
    char buf[200];
    std::snprintf(buf, sizeof buf, "its own time_ms: read %.0f, total (after reading) %.0f; R = %.4g",
                  j.at("time_ms").at("read").get<double>(), j.at("time_ms").at("total").get<double>(), R);
    ours.note = buf;
  } catch (const std::exception& e) {
    ours.note += std::string(" (JSON not readable: ") + e.what() + ")";
  }
  out.push_back(ours);
  // The default, all cores: each strip holds its own triangulation arrays.
  out.push_back(
      run_child("hg-outline --threads 0 (all cores)", {HG_OUTLINE_EXE, pcd, "--threads", "0", "-o", json}, dir));
  out.push_back(run_child("hg-outline --threads 1 --order hilbert",
                          {HG_OUTLINE_EXE, pcd, "--threads", "1", "--order", "hilbert", "-o", json}, dir));
#endif
  if (R <= 0) R = 1.7 * p.pitch;
  char rbuf[64];
  std::snprintf(rbuf, sizeof rbuf, "%.17g", R);
  const std::string me = self_exe();
  out.push_back(run_child("reading the file only (hg_outline_io reader + plane, in hg-bench)",
                          {me, "--child-read", pcd, rbuf}, dir));
  if (a.cgal)
    out.push_back(
        run_child("CGAL DT + circumradius + loops (after the same reader)", {me, "--child-cgal-dt", pcd, rbuf}, dir));
  if (a.pcl) out.push_back(run_child("PCL ConcaveHull (after the same reader)", {me, "--child-pcl", pcd, rbuf}, dir));
  std::filesystem::remove_all(dir);
  return out;
}

std::string load_average() { return read_first_line("/proc/loadavg"); }

}  // namespace
}  // namespace hg::bench

namespace hg::bench {

// The report's header: command, date, machine, compiler, run counts, cloud options, peers, --include.
Report report_header(int argc, char** argv, const Args& a) {
  Report report;
  for (int i = 0; i < argc; ++i) {
    std::string s = argv[i];
    if (i == 0) s = "hg-bench";
    report.command += (i ? " " : "") + s;
  }
  {
    const std::time_t t = std::time(nullptr);
    char buf[64];
    std::strftime(buf, sizeof buf, "%Y-%m-%d %H:%M %Z", std::localtime(&t));
    report.date = buf;
  }
  report.machine = machine_facts();
  report.compiler = std::string("GCC ") + __VERSION__;
#ifdef NDEBUG
  report.compiler += ", NDEBUG";
#endif
  report.runs = a.runs;
  report.slow_runs = a.slow_runs;
  report.slow_runs_high = a.slow_runs_high;
  report.ordinary_runs = a.ordinary_runs;
  report.band_rows = a.band_rows;
  report.threads = a.threads;
  {
    char buf[256];
    std::snprintf(
        buf, sizeof buf,
        "hg_partgen presets, scan-line order, in-plane noise sigma = %.3g x pitch, %s, dropout %.3g, seed %llu",
        a.noise, a.jagged ? "jagged edges" : "pixel-centre edges", a.dropout, static_cast<unsigned long long>(a.seed));
    report.cloud_options = buf;
  }
  report.cgal_version = a.cgal ? "built in" : (kHaveCgal ? "disabled" : "not installed at configure time");
  report.delaunator_version =
      a.delaunator ? "built in" : (kHaveDelaunator ? "disabled" : "not built (no delaunator.hpp at configure time)");
  report.pcl_version = a.pcl ? "built in" : (kHavePcl ? "disabled" : "not installed at configure time");
  if (!a.include.empty()) {
    std::ifstream f(a.include);
    if (!f) {
      throw std::runtime_error("cannot read --include " + a.include);
    }
    std::stringstream ss;
    ss << f.rdbuf();
    report.include_text = ss.str();
  }
  return report;
}

}  // namespace hg::bench

int main(int argc, char** argv) {
  using namespace hg::bench;
  if (argc == 4 && std::string(argv[1]).rfind("--child-", 0) == 0) {
    try {
      return child_main(argv[1], argv[2], std::strtod(argv[3], nullptr));
    } catch (const std::exception& e) {
      std::fprintf(stderr, "hg-bench child: %s\n", e.what());
      return 1;
    }
  }
  Args a;
  try {
    hg::runtime::Params params(bench_params());
    const auto action = params.parse(argc, argv);
    if (action != hg::runtime::Params::Action::Run) return hg::runtime::answer(action, "hg-bench", params, usage);
    a = args_from(params);
  } catch (const std::exception& e) {  // runtime::ConfigError
    std::fprintf(stderr, "hg-bench: %s (see --help)\n", e.what());
    return 2;
  }
  Report report;
  try {
    report = report_header(argc, argv, a);
  } catch (const std::exception& e) {
    std::fprintf(stderr, "hg-bench: %s\n", e.what());
    return 2;
  }
  report.load_start = load_average();

  std::vector<const hg::partgen::Preset*> todo;
  try {
    if (!a.only.empty()) {
      for (const auto& name : a.only) todo.push_back(&hg::partgen::find_preset(name));
    } else {
      for (const auto& set : {"low", "down", "high"})
        if (a.sets.count(set))
          for (const auto& p : hg::partgen::presets())
            if (p.name.rfind(std::string(set) + "-", 0) == 0) todo.push_back(&p);
    }
  } catch (const std::exception& e) {
    std::fprintf(stderr, "hg-bench: %s\n", e.what());
    return 2;
  }
  try {
    for (const auto* p : todo) {
      std::fprintf(stderr, "%s (%s piece %d): generating...\n", p->name.c_str(), p->table.c_str(), p->piece);
      const BenchCloud c = make_cloud(*p, a);
      report.clouds.push_back(bench_cloud(c, a));
    }
    if (a.memory) report.memory = measure_memory(a, report);
  } catch (const std::exception& e) {
    std::fprintf(stderr, "hg-bench: %s\n", e.what());
    return 1;
  }
  report.load_end = load_average();
  if (!a.md.empty()) write_markdown(report, a.md);
  if (!a.png.empty()) write_plot(report, a.png);
  if (a.md.empty()) write_markdown(report, "/dev/stdout");
  return 0;
}
