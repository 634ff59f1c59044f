// The outline on several threads: the cloud split into vertical strips, one per thread, each
// triangulated with a margin band of its neighbours' points (docs/outline-core-threads.md).
// Internal to the outline core: compute_outline calls it.
#pragma once

#include <array>
#include <cstddef>
#include <cstdint>
#include <span>
#include <vector>

#include "outline.hpp"

namespace hg::outline {

// How many strips compute_outline uses for `points` points under `options`: 1 for Options::threads == 1,
// for outer_only, local alpha mode, modes other than DSHI, and below min_points_per_thread per strip.
int strips_for(const Options& options, std::size_t points);

// What one stage of the threaded outline cost the thread that ran it: getrusage(RUSAGE_THREAD) user and
// system CPU time (not stretched by other processes' load as wall time is; system time is mostly the page
// faults of fresh memory), those minor faults, the voluntary context switches (the thread blocked: at a
// meeting, or on a kernel lock) and the wall time (which includes waiting at a meeting).
struct StageCost {
  double user_ms = 0, sys_ms = 0, wall_ms = 0;
  long faults = 0, blocked = 0;
  double cpu_ms() const { return user_ms + sys_ms; }
};
// A strip's stages in the order they run (docs/outline-core-threads.md, "How it works"): its zone's index
// list, the insertion order and translated copy, the meeting when every strip holds its points, the
// insertion, the nearest-neighbour histogram, the second meeting, the survey of its triangles, then (after
// the merge starts) the check cells, the untrusted triangles' checks and the free edges.
struct StripProfile {
  StageCost zone, order, wait_points, insert, nn, wait_nn, survey, cells, check, edges;
};
// The whole split: the calling thread's serial parts around the strips' stages.
struct SplitProfile {
  StageCost split;  // box and boundaries, before the strips start
  StageCost merge;  // medians, hull, recovery of missed triangles, the radius (serial)
  StageCost chain;  // chaining the merged free edges into loops (serial)
  std::vector<StripProfile> strips;
};

// What the strips found before the radius is known, merged (for tests: the split's own figures).
struct StripSurvey {
  std::size_t distinct = 0;        // distinct finite points, each counted by the strip owning it
  std::size_t hull = 0;            // points on the convex hull's boundary
  std::size_t triangles = 0;       // finite Delaunay triangles: 2 distinct - 2 - hull
  std::size_t trusted = 0;         // owned triangles proven Delaunay for the whole cloud
  double margin = 0;               // the margin band's width M
  std::vector<double> boundaries;  // the strips' x boundaries (inner ones)
  // Owned trusted triangles as input indices, counter-clockwise (filled with Options::keep_triangles).
  std::vector<std::array<std::uint32_t, 3>> owned;
  SplitProfile profile;  // what each stage cost (for the benchmarks)
};

// The threaded pipeline into `res`; false when a check finds the split unsafe for this cloud (a strip
// with too few points, the margin narrower than 4 R, a median not determined by the trusted triangles,
// a circumcentre side not decidable exactly): the caller then runs the one-thread path. `survey`, when
// given, receives the split's figures.
bool run_threaded(std::span<const Vec2> points, const Options& options, int strips, Result& res,
                  StripSurvey* survey = nullptr);
// The same; `owned`, when given, is the vector `points` views: it is emptied (its memory returned) once
// every strip holds its zone's points, and filled again with the same points (non-finite ones as NaN)
// if the run then returns false.
bool run_threaded(std::span<const Vec2> points, std::vector<Vec2>* owned, const Options& options, int strips,
                  Result& res, StripSurvey* survey = nullptr);

}  // namespace hg::outline
