// The smoothing context: the ring's moments and the scales every stage uses, computed once.
#include "path_planner/smooth/stages.hpp"

#include <algorithm>
#include <cmath>

namespace hg::path_planner::smooth {

std::optional<SmoothContext> make_context(const Ring& ring, double pitch, const SmoothOptions& o) {
  const int n = int(ring.size());
  if (n < 8 || !(pitch >= 0)) return std::nullopt;
  SmoothContext c(ring);
  const Unrolled& u = c.u;
  c.pitch = pitch;
  c.total = u.S(n) - u.S(0);
  // Length unit of the scales: the pitch, or the vertex spacing when noise spreads the vertices further.
  std::vector<double> e(n);
  for (int i = 0; i < n; ++i) e[i] = u.S(i + 1) - u.S(i);
  std::nth_element(e.begin(), e.begin() + n / 2, e.end());
  c.spacing = e[n / 2];
  // Unknown pitch: a densely sampled boundary (a noisy one, whose lattice is lost) is still fitted, with the
  // vertex spacing as the unit and without edge compensation; a drawn polygon (long edges) is left alone.
  if (pitch == 0 && !(c.spacing > 0 && c.spacing <= c.total / 200)) return std::nullopt;
  c.unit = std::max(pitch, c.spacing);
  // Noise level of a window mean: the outline's (all loops pooled), or this loop's own.
  c.win = window_of(o);
  c.sigma = o.noise;
  if (!(c.sigma > 0)) {
    std::vector<double> dev;
    append_window_noise(u, c.win, dev);
    c.sigma = sigma_of(dev);
  }
  // The corner detector's lines are at least 60 window-mean noise levels long: noise then tilts them by
  // about 1/60 rad, so that a tight arc (a 20 mm slot end under pm806 noise, where one corner scale of
  // 8 pixels turns by ~30 deg) cannot pass for a corner by the noise inflating its turn at one scale.
  c.scale = std::max(o.corner_scale_pitches * c.unit, 60.0 * c.sigma);
  c.bias_scale = o.edge_compensation && pitch > 0 ? 1.0 : 0.0;
  // A window mean beyond this is a misfit, not noise or staircase (4 sigma: docs/decisions/smooth-4-sigma.md).
  c.tolerance = 0.1 * (pitch > 0 ? pitch : c.spacing) + 4.0 * c.sigma;
  c.min_piece = 2 * c.win;
  c.corner_angle = o.corner_angle;
  return c;
}

}  // namespace hg::path_planner::smooth
