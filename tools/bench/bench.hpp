// hg-bench's measurements and the report written from them (markdown tables + PNG plot).
#pragma once

#include <cstdint>
#include <map>
#include <optional>
#include <string>
#include <vector>

#include "peers.hpp"

namespace hg::bench {

// Wall-clock times of repeated runs of one method on one cloud, milliseconds.
struct Timing {
  std::vector<double> ms;
  double median() const;
  double min() const;
  double max() const;
  bool empty() const { return ms.empty(); }
};

// Counters of one triangulation (deterministic: the same on every run).
struct OurStats {
  outline::TriangulationStats tri;  // as outline::Result holds them
  std::size_t points_used = 0, outer_loops = 0, holes = 0, boundary_edges = 0;
  double area = 0;
};

struct Method {
  std::string key;  // e.g. "dshi", "dshi hilbert (shuffled)"
  Timing time;
  OurStats stats;    // ours only
  PeerOutline peer;  // peers only
  bool is_peer = false;
};

struct CloudResult {
  std::string preset, table;  // "low-1", "Table 1"
  int piece = 0;
  std::size_t paper_points = 0, points = 0;
  double pitch = 0, alpha_radius = 0, nn_spacing = 0;
  std::vector<Method> methods;
  const Method* find(const std::string& key) const {
    for (const auto& m : methods)
      if (m.key == key) return &m;
    return nullptr;
  }
};

struct MemoryResult {
  std::string what, command;
  long max_rss_kb = -1;
  double wall_ms = 0;
  std::string note;
};

struct Report {
  std::string command, date, machine, compiler, cgal_version, delaunator_version, pcl_version, cloud_options;
  std::string load_start, load_end;
  int runs = 0, slow_runs = 0, slow_runs_high = 0, ordinary_runs = 0, band_rows = 0, threads = 2;
  std::vector<CloudResult> clouds;
  std::vector<MemoryResult> memory;
  std::string memory_cloud;
  std::string include_text;  // hand-written section appended (profile), from --include
};

void write_markdown(const Report& report, const std::string& path);
void write_plot(const Report& report, const std::string& path);

// Names of the methods (keys of Method).
namespace key {
inline const std::string ordinary = "ordinary";
inline const std::string ds = "ds";
inline const std::string dshi = "dshi";                       // scan order, as given
inline const std::string dshi_hilbert_scan = "dshi hilbert";  // Hilbert order of the scan-order cloud
inline const std::string dshi_asis_shuf = "dshi as-is (shuffled)";
inline const std::string dshi_hilbert_shuf = "dshi hilbert (shuffled)";
inline const std::string dshi_brio_shuf = "dshi brio (shuffled)";
inline const std::string dshi_band = "dshi banded";  // experiment: bands of rows, column order
// hg-outline's defaults (BRIO order) on the scan-order cloud, one thread and Report::threads threads.
inline const std::string ours_1t = "dshi brio, 1 thread";
inline const std::string ours_nt = "dshi brio, N threads";
inline const std::string cgal_dt = "CGAL DT + loops";
inline const std::string cgal_alpha = "CGAL Alpha_shape_2";
inline const std::string delaunator = "delaunator + loops";
inline const std::string pcl = "PCL ConcaveHull";
}  // namespace key

}  // namespace hg::bench
