// hg-bench's report: markdown tables (the paper's numbers beside ours, targets of issue 3) and a PNG plot.
#include <opencv2/core.hpp>
#include <opencv2/imgcodecs.hpp>
#include <opencv2/imgproc.hpp>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <fstream>
#include <limits>
#include <map>
#include <stdexcept>
#include <string>

#include "bench.hpp"

namespace hg::bench {

double Timing::median() const {
  if (ms.empty()) return std::numeric_limits<double>::quiet_NaN();
  std::vector<double> v = ms;
  std::sort(v.begin(), v.end());
  const std::size_t k = v.size();
  return k % 2 ? v[k / 2] : (v[k / 2 - 1] + v[k / 2]) / 2;
}
double Timing::min() const { return ms.empty() ? NAN : *std::min_element(ms.begin(), ms.end()); }
double Timing::max() const { return ms.empty() ? NAN : *std::max_element(ms.begin(), ms.end()); }

namespace {

// The paper's figures (section 4), by piece 1..6, typed from its Tables 2, 3, 5, 7, 8.
struct PaperCost {
  double ordinary, ds, dshi;
};
const PaperCost kTable2[6] = {{11410445, 255881, 29881}, {9215350, 345249, 25599},  {4096232, 212507, 12761},
                              {62778422, 722185, 72733}, {72878539, 816222, 79815}, {69991500, 1112193, 77474}};
const PaperCost kTable7[6] = {{301184708, 4067904, 106970}, {259483564, 2737748, 104982}, {146277609, 2410395, 74661},
                              {285813272, 1504871, 94157},  {232072475, 2795457, 82272},  {211203409, 2815502, 83908}};
struct PaperTime {
  double dshi, pcl, ordinary;
};
const PaperTime kTable3[6] = {{24.03, 34.8, 96.12},   {44.05, 32.81, 216.3}, {40.05, 18.77, 156.2},
                              {48.06, 96.52, 374.67}, {44.05, 86.5, 336.54}, {36.05, 106.9, 196.26}};
const PaperTime kTable5[6] = {{2854.14, 10267.7, NAN}, {3173.56, 7072.56, NAN}, {1818.06, 5323.69, NAN},
                              {9970.89, 27544.8, NAN}, {6987.71, 13908.4, NAN}, {3189.75, 13399.7, NAN}};
const PaperTime kTable8[6] = {{104.28, 220.35, 925.43}, {78.53, 165.68, 1325.7},  {47.33, 143.52, 492.26},
                              {94.16, 207.7, 926.27},   {90.14, 164.04, 1106.24}, {63.55, 163.06, 455.05}};

std::string fmt(const char* f, double v) {
  if (std::isnan(v)) return "–";
  char buf[64];
  std::snprintf(buf, sizeof buf, f, v);
  return buf;
}
// Thousands separators, like the paper.
std::string big(double v) {
  if (std::isnan(v)) return "–";
  // Built forwards digit by digit (GCC 12 gives a false -Wrestrict on std::string::insert here).
  const std::string digits = std::to_string(static_cast<long long>(std::llround(v)));
  const std::size_t sign = digits[0] == '-' ? 1 : 0;
  std::string out = digits.substr(0, sign);
  for (std::size_t i = sign; i < digits.size(); ++i) {
    if (i > sign && (digits.size() - i) % 3 == 0) out.push_back(',');
    out.push_back(digits[i]);
  }
  return out;
}
std::string ms(double v) {
  if (std::isnan(v)) return "–";
  return v < 10 ? fmt("%.2f", v) : v < 100 ? fmt("%.1f", v) : fmt("%.0f", v);
}
double med(const CloudResult& c, const std::string& k) {
  const Method* m = c.find(k);
  return m ? m->time.median() : NAN;
}
const OurStats* stats(const CloudResult& c, const std::string& k) {
  const Method* m = c.find(k);
  return m && !m->is_peer && !m->time.empty() ? &m->stats : nullptr;
}
// A peer's median time, or "not built" when the peer was not compiled in ("–": built, not run here).
std::string peer_ms(const Report& r, const CloudResult& c, const std::string& k) {
  const double v = med(c, k);
  if (!std::isnan(v)) return ms(v);
  const std::string& why = k == key::delaunator ? r.delaunator_version : k == key::pcl ? r.pcl_version : r.cgal_version;
  return why.rfind("not", 0) == 0 ? "not built" : "–";
}
std::string set_of(const CloudResult& c) { return c.preset.substr(0, c.preset.find('-')); }

std::string verdict(double value, double limit) {
  if (std::isnan(value) || std::isnan(limit)) return "not measured";
  if (value <= limit) return "met";
  return "MISSED by " + fmt("%.0f", 100 * (value / limit - 1)) + " %";
}

void search_cost_table(std::ostream& o, const Report& r, const std::string& set, const PaperCost* paper) {
  o << "| piece | points (paper) | ordinary | DS | DS/ord. | DSHI | DSHI/DS | DSHI/ord. | paper DSHI/ord. | DSHI locate only / ord. | "
       "mean visits per insertion: DS / DSHI |\n|---|---|---|---|---|---|---|---|---|---|---|\n";
  for (const auto& c : r.clouds) {
    if (set_of(c) != set) continue;
    const OurStats *ord = stats(c, key::ordinary), *ds = stats(c, key::ds), *dshi = stats(c, key::dshi);
    if (!dshi) continue;
    const PaperCost& p = paper[c.piece - 1];
    const double o_ = ord ? ord->tri.search_cost : NAN, d_ = ds ? ds->tri.search_cost : NAN, h = dshi->tri.search_cost;
    const double n = static_cast<double>(dshi->points_used);
    o << "| " << c.piece << " | " << big(c.points) << " (" << big(c.paper_points) << ") | " << big(o_) << " | "
      << big(d_) << " | " << fmt("%.2f %%", 100 * d_ / o_) << " | " << big(h) << " | " << fmt("%.2f %%", 100 * h / d_)
      << " | " << fmt("%.3f ‰", 1000 * h / o_) << " | " << fmt("%.2f ‰", 1000 * p.dshi / p.ordinary) << " | "
      << fmt("%.3f ‰", 1000 * dshi->tri.search_cost_locate / o_) << " | " << fmt("%.1f", d_ / n) << " / "
      << fmt("%.2f", h / n) << " |\n";
  }
}

void small_time_table(std::ostream& o, const Report& r, const std::string& set, const PaperTime* paper) {
  o << "| piece | points | DSHI | DS | ordinary | CGAL DT + loops | DSHI / CGAL DT | delaunator + loops | DSHI / "
       "delaunator | CGAL Alpha_shape_2 | PCL ConcaveHull | DSHI hilbert (shuffled) | paper: DSHI / PCL / ordinary |\n"
       "|---|---|---|---|---|---|---|---|---|---|---|---|---|\n";
  for (const auto& c : r.clouds) {
    if (set_of(c) != set) continue;
    const PaperTime& p = paper[c.piece - 1];
    const double d = med(c, key::dshi), cg = med(c, key::cgal_dt), dl = med(c, key::delaunator);
    o << "| " << c.piece << " | " << big(c.points) << " | " << ms(d) << " | " << ms(med(c, key::ds)) << " | "
      << ms(med(c, key::ordinary)) << " | " << peer_ms(r, c, key::cgal_dt) << " | " << fmt("%.2f", d / cg) << " | "
      << peer_ms(r, c, key::delaunator) << " | " << fmt("%.2f", d / dl) << " | " << peer_ms(r, c, key::cgal_alpha)
      << " | " << peer_ms(r, c, key::pcl) << " | " << ms(med(c, key::dshi_hilbert_shuf)) << " | " << ms(p.dshi) << " / "
      << ms(p.pcl) << " / " << ms(p.ordinary) << " |\n";
  }
}

// Title, how the figures were measured, and what the method names mean.
void header_section(std::ostream& o, const Report& r) {
  o << "# Outline core benchmark: the paper's tables, our insertion orders, CGAL and PCL\n\n"
    << "The paper: Hang Yu, Yixi Zhao, Chongben Ni, Jinhong Ding, Tao Zhang, Ran Zhang and Xintian Jiang, \"A Novel "
       "Vision-Based Outline Extraction Method for Hull Components in Shipbuilding\", *Journal of Marine Science and "
       "Engineering* 12(3), 453, MDPI, 2024, doi:10.3390/jmse12030453.\n\n"
    << "Written by `hg-bench` (tools/bench/). All figures below come from ONE run of one process: times are "
       "medians of repeated runs of the whole outline (triangulation + circumradius classification + loops; "
       "reading the file excluded), one thread unless a column says otherwise, Release; methods are run round-robin so load bursts "
       "spread over all of them. Search costs and per-insertion counts are exact counters (the same on every "
       "run).\n\n"
    << "- Command: `" << r.command << "`\n"
    << "- Date: " << r.date << "\n"
    << "- Machine: " << r.machine
    << " — shared with other engineers' builds: load average (1, 5, 15 min, "
       "running/total, last pid) at start `"
    << r.load_start << "`, at end `" << r.load_end << "`\n"
    << "- Compiler: " << r.compiler << "\n"
    << "- Clouds: " << r.cloud_options << "\n"
    << "- Runs: " << r.runs << " per method (ordinary: " << r.ordinary_runs
    << "; CGAL Alpha_shape_2 and PCL: " << r.slow_runs << " on low/down, " << r.slow_runs_high << " on high)\n"
    << "- R: the product's automatic radius (k × the point spacing h = sqrt(2 × median Delaunay triangle area), k = 1.7 on regular clouds rising toward the largest empty circle of a random set on irregular ones; docs/outline-auto-radius.md), then the "
       "same R for every method and peer (CGAL Alpha_shape_2: alpha = R², REGULARIZED; PCL: setAlpha(R), "
       "which PCL compares with the circumradius)\n"
    << "- Peers: CGAL " << r.cgal_version << ", delaunator-cpp " << r.delaunator_version << ", PCL " << r.pcl_version
    << "\n\n";

  o << "Method names: `dshi brio, 1 thread` / `dshi brio, N threads` = hg-outline's defaults (BRIO order) on the "
       "scan-order cloud with `Options::threads` = 1 / N (N = "
    << r.threads
    << "); `dshi` = directive search + heritable initial, points inserted in scan order as the camera "
       "gives them (the paper's method); `dshi hilbert (shuffled)` = the cloud shuffled at random, then "
       "`--order hilbert`; `dshi brio (shuffled)` = the same with BRIO rounds; `dshi banded` = an experiment: "
       "bands of "
    << r.band_rows
    << " rows swept column by column (order computed inside the timed region from the pixel rows/columns); "
       "`CGAL DT + loops` = `Delaunay_triangulation_2` (Epick, range insertion with CGAL's spatial sort) + a "
       "squared-circumradius pass + chaining the free edges into loops; `delaunator + loops` = delaunator-cpp's "
       "`Delaunator` + the same pass (its own `circumradius`) and the same loop chaining.\n\n";
}

// Ours (hg-outline's defaults) on one and on N threads beside the Delaunay peers, every cloud of the run.
void side_by_side_table(std::ostream& o, const Report& r) {
  const std::string n = std::to_string(r.threads);
  o << "## Side by side: ours on 1 and " << n << " threads, CGAL DT + loops, delaunator + loops\n\n"
    << "Ours: hg-outline's defaults (DSHI, BRIO order) on the scan-order cloud, `Options::threads` = 1 and " << n
    << "; the peers on the same points with the same R. Medians of one run (ms).\n\n"
    << "| cloud | points | ours 1 thread | ours " << n << " threads | " << n
    << "t / 1t | CGAL DT + loops | delaunator + loops | 1t / CGAL | " << n << "t / CGAL | 1t / delaunator | " << n
    << "t / delaunator |\n|---|---|---|---|---|---|---|---|---|---|---|\n";
  for (const auto& c : r.clouds) {
    const double t1 = med(c, key::ours_1t), tn = med(c, key::ours_nt), cg = med(c, key::cgal_dt),
                 dl = med(c, key::delaunator);
    o << "| " << c.preset << " | " << big(c.points) << " | " << ms(t1) << " | " << ms(tn) << " | "
      << fmt("%.2f", tn / t1) << " | " << peer_ms(r, c, key::cgal_dt) << " | " << peer_ms(r, c, key::delaunator)
      << " | " << fmt("%.2f", t1 / cg) << " | " << fmt("%.2f", tn / cg) << " | " << fmt("%.2f", t1 / dl) << " | "
      << fmt("%.2f", tn / dl) << " |\n";
  }
}

// The issue-13 targets (ours against CGAL measured in the same run), with their verdicts.
void threads_targets_table(std::ostream& o, const Report& r) {
  const std::string n = std::to_string(r.threads);
  o << "\n## Targets (issue 13)\n\n| target | cloud | measured | limit | verdict |\n|---|---|---|---|---|\n";
  for (const auto& c : r.clouds) {
    const double t1 = med(c, key::ours_1t), tn = med(c, key::ours_nt), cg = med(c, key::cgal_dt);
    const bool high = set_of(c) == "high";
    const double k = high ? 0.30 : 0.5;
    o << "| 1 thread ≤ " << fmt("%.2f", k) << " × CGAL DT + loops | " << c.preset << " | " << ms(t1)
      << " ms = " << fmt("%.2f", t1 / cg) << " × | " << ms(k * cg) << " ms | " << verdict(t1, k * cg) << " |\n";
    if (!high) continue;
    o << "| " << n << " threads ≤ 0.6 × 1 thread | " << c.preset << " | " << ms(tn) << " ms = " << fmt("%.2f", tn / t1)
      << " × | " << ms(0.6 * t1) << " ms | " << verdict(tn, 0.6 * t1) << " |\n";
    o << "| " << n << " threads ≤ 0.20 × CGAL DT + loops | " << c.preset << " | " << ms(tn)
      << " ms = " << fmt("%.2f", tn / cg) << " × | " << ms(0.2 * cg) << " ms | " << verdict(tn, 0.2 * cg) << " |\n";
  }
}

// The search cost (Tables 2, 7) and time (Tables 3, 8) tables of the low and down-sampled clouds.
void paper_tables(std::ostream& o, const Report& r) {
  o << "## Table 2 reproduced: search cost, low-density clouds (paper Table 1 sizes)\n\n"
       "Search cost = triangles visited by point location + triangles tested by the cavity search (the "
       "paper's measure; `ordinary` tests every live triangle for every point).\n\n";
  search_cost_table(o, r, "low", kTable2);
  o << "\n## Table 7 reproduced: search cost, down-sampled clouds (paper Table 6 sizes)\n\n";
  search_cost_table(o, r, "down", kTable7);

  o << "\n## Table 3 reproduced: time (ms), low-density clouds\n\n";
  small_time_table(o, r, "low", kTable3);
  o << "\n## Table 8 reproduced: time (ms), down-sampled clouds\n\n";
  small_time_table(o, r, "down", kTable8);
}

// Times on the high-density clouds (Tables 4, 5).
void high_density_table(std::ostream& o, const Report& r) {
  o << "\n## High-density clouds (paper Table 4 sizes; Table 5 times): time (ms)\n\n"
       "| piece | points | DSHI scan | hilbert (shuffled) | hilbert/scan | brio (shuffled) | banded | CGAL DT + loops | "
       "DSHI / CGAL DT | delaunator + loops | CGAL Alpha_shape_2 | PCL ConcaveHull | DSHI / PCL | paper: DSHI / PCL |\n"
       "|---|---|---|---|---|---|---|---|---|---|---|---|---|---|\n";
  for (const auto& c : r.clouds) {
    if (set_of(c) != "high") continue;
    const PaperTime& p = kTable5[c.piece - 1];
    const double d = med(c, key::dshi), hs = med(c, key::dshi_hilbert_shuf), cg = med(c, key::cgal_dt),
                 pc = med(c, key::pcl);
    o << "| " << c.piece << " | " << big(c.points) << " | " << ms(d) << " | " << ms(hs) << " | " << fmt("%.2f", hs / d)
      << " | " << ms(med(c, key::dshi_brio_shuf)) << " | " << ms(med(c, key::dshi_band)) << " | "
      << peer_ms(r, c, key::cgal_dt) << " | " << fmt("%.2f", d / cg) << " | " << peer_ms(r, c, key::delaunator) << " | "
      << peer_ms(r, c, key::cgal_alpha) << " | " << peer_ms(r, c, key::pcl) << " | " << fmt("1/%.0f", pc / d) << " | "
      << ms(p.dshi) << " / " << ms(p.pcl) << " |\n";
  }
}

// Per-inserted-point counters of every order.
void work_table(std::ostream& o, const Report& r) {
  o << "\n## Where the insertion work goes: counts per inserted point\n\n"
       "locate = triangles visited by the walk (ordinary: all live triangles); cavity tests = neighbours tested "
       "by the cavity search; incircle = incircle tests (all of them, walk excluded); cavity = triangles "
       "deleted per insertion (new triangles = cavity + 2). Time = median ms of the whole outline.\n\n"
       "| cloud | points | order | locate | cavity tests | incircle | cavity size | search cost | time ms |\n"
       "|---|---|---|---|---|---|---|---|---|\n";
  for (const auto& c : r.clouds) {
    for (const std::string& k : {key::dshi, key::dshi_hilbert_scan, key::dshi_hilbert_shuf, key::dshi_brio_shuf,
                                 key::dshi_band, key::dshi_asis_shuf, key::ds}) {
      const OurStats* s = stats(c, k);
      if (!s) continue;
      const double n = static_cast<double>(s->points_used);
      o << "| " << c.preset << " | " << big(c.points) << " | " << k << " | "
        << fmt("%.2f", s->tri.search_cost_locate / n) << " | " << fmt("%.2f", s->tri.search_cost_cavity / n) << " | "
        << fmt("%.2f", s->tri.incircle_tests / n) << " | " << fmt("%.2f", s->tri.cavity_triangles / n) << " | "
        << fmt("%.2f", s->tri.search_cost / n) << " | " << ms(med(c, k)) << " |\n";
    }
  }
}

// Boundary edges and loops against the peers.
void same_outline_table(std::ostream& o, const Report& r) {
  o << "\n## Same outline? (sanity check against the peers, same points and R)\n\n"
       "Boundary edges of the alpha shape. Ours and `CGAL DT + loops` use the same rule (r ≤ R inside); camera "
       "grids are full of cocircular quadruples, where the Delaunay triangulation is not unique, so a few "
       "edges may differ. Alpha_shape_2 counts REGULAR edges; PCL counts the vertices of its polygons. "
       "Loops: outer + holes (PCL: polygons).\n\n"
       "| cloud | R (mm) | ours: edges, loops, area m² | CGAL DT: edges, loops, area m² | delaunator: edges, loops, "
       "area m² | Alpha_shape_2 edges | PCL: vertices, polygons |\n"
       "|---|---|---|---|---|---|---|\n";
  for (const auto& c : r.clouds) {
    const OurStats* s = stats(c, key::dshi);
    if (!s) continue;
    o << "| " << c.preset << " | " << fmt("%.3f", c.alpha_radius * 1000) << " | " << s->boundary_edges << ", "
      << s->outer_loops << "+" << s->holes << ", " << fmt("%.6f", s->area) << " | ";
    for (const std::string& k : {key::cgal_dt, key::delaunator}) {
      if (const Method* m = c.find(k); m && !m->time.empty())
        o << m->peer.boundary_edges << ", " << m->peer.outer_loops << "+" << m->peer.holes << ", "
          << fmt("%.6f", m->peer.area);
      else
        o << "–";
      o << " | ";
    }
    if (const Method* m = c.find(key::cgal_alpha); m && !m->time.empty()) o << m->peer.boundary_edges;
    else
      o << "–";
    o << " | ";
    if (const Method* m = c.find(key::pcl); m && !m->time.empty())
      o << m->peer.boundary_edges << ", " << m->peer.outer_loops;
    else
      o << "–";
    o << " |\n";
  }
}

// Peak memory of the measured processes (when measured).
void memory_table(std::ostream& o, const Report& r) {
  if (r.memory.empty()) return;
  o << "\n## Peak memory (max RSS of the whole process, getrusage via wait4)\n\n"
    << "Cloud: " << r.memory_cloud
    << ". The hg-bench children load CGAL, PCL (with VTK) and OpenCV, so "
       "their baseline is higher than hg-outline's; the last column subtracts the reader-only child.\n\n"
       "| process | max RSS MB | wall ms | above reader-only MB | note |\n|---|---|---|---|---|\n";
  long reader_kb = -1;
  for (const auto& m : r.memory)
    if (m.what.rfind("reading the file only", 0) == 0) reader_kb = m.max_rss_kb;
  for (const auto& m : r.memory) {
    const bool child = m.what.rfind("hg-outline", 0) != 0;
    o << "| " << m.what << " | " << (m.max_rss_kb < 0 ? std::string("failed") : fmt("%.0f", m.max_rss_kb / 1024.0))
      << " | " << ms(m.wall_ms) << " | "
      << (child && reader_kb > 0 && m.max_rss_kb > 0 ? fmt("%.0f", (m.max_rss_kb - reader_kb) / 1024.0)
                                                     : std::string("–"))
      << " | " << m.note << " |\n";
  }
}

// The issue-3 targets with their verdicts.
void targets_table(std::ostream& o, const Report& r) {
  o << "\n## Targets (issue 3)\n\n| target | cloud | measured | limit | verdict |\n|---|---|---|---|---|\n";
  for (const auto& c : r.clouds) {
    const std::string set = set_of(c);
    const double d = med(c, key::dshi), cg = med(c, key::cgal_dt);
    if (set == "high") {
      o << "| DSHI ≤ 0.3 × CGAL DT + loops | " << c.preset << " | " << ms(d) << " ms = " << fmt("%.2f", d / cg)
        << " × | " << ms(0.3 * cg) << " ms | " << verdict(d, 0.3 * cg) << " |\n";
      const double pc = med(c, key::pcl);
      o << "| DSHI ≤ PCL ConcaveHull / 30 | " << c.preset << " | " << ms(d) << " ms | " << ms(pc / 30) << " ms | "
        << verdict(d, pc / 30) << " |\n";
      const double hs = med(c, key::dshi_hilbert_shuf);
      o << "| hilbert on shuffled ≤ 1.3 × scan order | " << c.preset << " | " << ms(hs)
        << " ms = " << fmt("%.2f", hs / d) << " × | " << ms(1.3 * d) << " ms | " << verdict(hs, 1.3 * d) << " |\n";
    } else {
      o << "| DSHI ≤ 0.6 × CGAL DT + loops | " << c.preset << " | " << ms(d) << " ms = " << fmt("%.2f", d / cg)
        << " × | " << ms(0.6 * cg) << " ms | " << verdict(d, 0.6 * cg) << " |\n";
      const OurStats *ord = stats(c, key::ordinary), *dshi = stats(c, key::dshi);
      if (ord && dshi) {
        const PaperCost& p = (set == "low" ? kTable2 : kTable7)[c.piece - 1];
        const double ours = 1000.0 * dshi->tri.search_cost / ord->tri.search_cost, paper = 1000 * p.dshi / p.ordinary;
        o << "| DSHI/ordinary ≤ paper's ‰ | " << c.preset << " | " << fmt("%.3f ‰", ours) << " | "
          << fmt("%.3f ‰", paper) << " | " << verdict(ours, paper) << " |\n";
        const double locate_only = 1000.0 * dshi->tri.search_cost_locate / ord->tri.search_cost;
        o << "| DSHI/ordinary ≤ paper's ‰, point location only | " << c.preset << " | " << fmt("%.3f ‰", locate_only)
          << " | " << fmt("%.3f ‰", paper) << " | " << verdict(locate_only, paper) << " |\n";
      }
    }
  }
  for (const auto& m : r.memory)
    if (m.what.rfind("hg-outline (", 0) == 0)
      o << "| peak memory, 1 thread ≤ 140 MB (issue 13; issue 3: 150 MB) | " << r.memory_cloud << " | "
        << fmt("%.0f MB", m.max_rss_kb / 1024.0) << " | 140 MB | " << verdict(m.max_rss_kb / 1024.0, 140) << " |\n";
}

}  // namespace

void write_markdown(const Report& r, const std::string& path) {
  std::ofstream o(path);
  if (!o) throw std::runtime_error("cannot write " + path);
  header_section(o, r);
  side_by_side_table(o, r);
  threads_targets_table(o, r);
  o << "\n";
  paper_tables(o, r);
  high_density_table(o, r);
  work_table(o, r);
  same_outline_table(o, r);
  memory_table(o, r);
  targets_table(o, r);
  if (!r.include_text.empty()) o << "\n" << r.include_text;
}

// ---- plot ----
namespace {

struct Axis {
  double lo, hi;  // log10 range
  int p0, p1;     // pixel range
  double map(double v) const { return p0 + (std::log10(v) - lo) / (hi - lo) * (p1 - p0); }
};

void panel(cv::Mat& img, cv::Rect box, const std::string& title, const std::string& ylabel,
           const std::vector<std::pair<std::string, std::vector<cv::Point2d>>>& series) {
  const std::vector<cv::Scalar> colours = {{200, 60, 20}, {30, 140, 30}, {20, 120, 230}, {150, 40, 160}, {0, 0, 200},
                                           {120, 120, 0}, {90, 90, 90},  {0, 180, 220},  {180, 0, 90},   {60, 60, 160}};
  double xmin = 1e300, xmax = 0, ymin = 1e300, ymax = 0;
  for (const auto& s : series)
    for (const auto& p : s.second)
      if (p.x > 0 && p.y > 0) {
        xmin = std::min(xmin, p.x);
        xmax = std::max(xmax, p.x);
        ymin = std::min(ymin, p.y);
        ymax = std::max(ymax, p.y);
      }
  if (xmax <= 0) return;
  const int left = box.x + 80, right = box.x + box.width - 20, top = box.y + 40, bottom = box.y + box.height - 60;
  Axis ax{std::floor(std::log10(xmin)), std::ceil(std::log10(xmax)), left, right};
  Axis ay{std::floor(std::log10(ymin)), std::ceil(std::log10(ymax)), bottom, top};
  if (ax.hi == ax.lo) ax.hi += 1;
  if (ay.hi == ay.lo) ay.hi += 1;
  const auto font = cv::FONT_HERSHEY_SIMPLEX;
  cv::putText(img, title, {left, box.y + 25}, font, 0.6, {0, 0, 0}, 1, cv::LINE_AA);
  cv::rectangle(img, {left, top}, {right, bottom}, {0, 0, 0}, 1);
  for (double e = ax.lo; e <= ax.hi + 1e-9; e += 1) {
    const int x = static_cast<int>(ax.map(std::pow(10, e)));
    cv::line(img, {x, top}, {x, bottom}, {225, 225, 225}, 1);
    cv::putText(img, "1e" + std::to_string(static_cast<int>(e)), {x - 15, bottom + 20}, font, 0.45, {0, 0, 0}, 1,
                cv::LINE_AA);
  }
  for (double e = ay.lo; e <= ay.hi + 1e-9; e += 1) {
    const int y = static_cast<int>(ay.map(std::pow(10, e)));
    cv::line(img, {left, y}, {right, y}, {225, 225, 225}, 1);
    cv::putText(img, "1e" + std::to_string(static_cast<int>(e)), {left - 45, y + 5}, font, 0.45, {0, 0, 0}, 1,
                cv::LINE_AA);
  }
  cv::putText(img, "points", {(left + right) / 2 - 20, bottom + 45}, font, 0.5, {0, 0, 0}, 1, cv::LINE_AA);
  cv::putText(img, ylabel, {left + 5, top + 18}, font, 0.5, {0, 0, 0}, 1, cv::LINE_AA);
  int legend_y = top + 40;
  for (std::size_t k = 0; k < series.size(); ++k) {
    auto pts = series[k].second;
    if (pts.empty()) continue;
    std::sort(pts.begin(), pts.end(), [](auto a, auto b) { return a.x < b.x; });
    const cv::Scalar col = colours[k % colours.size()];
    cv::Point prev(-1, -1);
    for (const auto& p : pts) {
      if (!(p.x > 0 && p.y > 0)) continue;
      const cv::Point q(static_cast<int>(ax.map(p.x)), static_cast<int>(ay.map(p.y)));
      cv::circle(img, q, 3, col, cv::FILLED, cv::LINE_AA);
      if (prev.x >= 0) cv::line(img, prev, q, col, 1, cv::LINE_AA);
      prev = q;
    }
    cv::line(img, {left + 15, legend_y - 4}, {left + 40, legend_y - 4}, col, 2, cv::LINE_AA);
    cv::putText(img, series[k].first, {left + 45, legend_y}, font, 0.45, col, 1, cv::LINE_AA);
    legend_y += 18;
  }
}

}  // namespace

void write_plot(const Report& r, const std::string& path) {
  cv::Mat img(720, 1600, CV_8UC3, cv::Scalar(255, 255, 255));
  std::vector<std::pair<std::string, std::vector<cv::Point2d>>> times, visits;
  for (const std::string& k :
       {key::ours_1t, key::ours_nt, key::dshi, key::dshi_hilbert_shuf, key::dshi_brio_shuf, key::dshi_band, key::ds,
        key::ordinary, key::cgal_dt, key::delaunator, key::cgal_alpha, key::pcl}) {
    std::vector<cv::Point2d> t;
    for (const auto& c : r.clouds)
      if (const Method* m = c.find(k); m && !m->time.empty())
        t.emplace_back(static_cast<double>(c.points), m->time.median());
    if (!t.empty()) times.emplace_back(k, t);
  }
  for (const std::string& k :
       {key::dshi, key::dshi_hilbert_shuf, key::dshi_brio_shuf, key::dshi_band, key::ds, key::ordinary}) {
    std::vector<cv::Point2d> v;
    for (const auto& c : r.clouds)
      if (const OurStats* s = stats(c, k))
        v.emplace_back(static_cast<double>(c.points), static_cast<double>(s->tri.search_cost) / s->points_used);
    if (!v.empty()) visits.emplace_back(k, v);
  }
  panel(img, {0, 0, 800, 720}, "Outline time (median ms, one thread) vs points", "ms", times);
  panel(img, {800, 0, 800, 720}, "Search cost per inserted point (triangles visited)", "visits/point", visits);
  cv::putText(img, "hg-bench " + r.date, {10, 712}, cv::FONT_HERSHEY_SIMPLEX, 0.4, {100, 100, 100}, 1, cv::LINE_AA);
  if (!cv::imwrite(path, img)) throw std::runtime_error("cannot write " + path);
}

}  // namespace hg::bench
