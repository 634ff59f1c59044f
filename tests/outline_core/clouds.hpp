// Point clouds for the outline core tests.
#pragma once

#include <algorithm>
#include <cmath>
#include <random>
#include <vector>

#include "outline_core/outline.hpp"

namespace hg::outline::testing {

inline std::vector<Vec2> random_cloud(std::size_t n, std::uint64_t seed, double scale = 1, Vec2 offset = {}) {
  std::mt19937_64 rng(seed);
  std::uniform_real_distribution<double> u(0, 1);
  std::vector<Vec2> p(n);
  for (auto& q : p) q = {offset.x + scale * u(rng), offset.y + scale * u(rng)};
  return p;
}

// Scan order (rows of increasing y), spacing `step`, optional jitter (fraction of step).
inline std::vector<Vec2> grid_cloud(int w, int h, double step = 1, Vec2 offset = {}, double jitter = 0,
                                    std::uint64_t seed = 1) {
  std::mt19937_64 rng(seed);
  std::uniform_real_distribution<double> u(-jitter, jitter);
  std::vector<Vec2> p;
  for (int y = 0; y < h; ++y)
    for (int x = 0; x < w; ++x) {
      const double jx = jitter > 0 ? u(rng) : 0, jy = jitter > 0 ? u(rng) : 0;
      p.push_back({offset.x + step * (x + jx), offset.y + step * (y + jy)});
    }
  return p;
}

// Many points on a few lines (including the hull), plus a few others.
inline std::vector<Vec2> collinear_heavy(std::uint64_t seed) {
  std::mt19937_64 rng(seed);
  std::vector<Vec2> p;
  for (int i = 0; i <= 200; ++i) {
    p.push_back({static_cast<double>(i), 0});        // bottom hull edge
    p.push_back({static_cast<double>(i), 2.0 * i});  // diagonal
    p.push_back({100.0, static_cast<double>(i)});    // vertical line through the middle
    p.push_back({i * 0.1, i * 0.3 + 7});             // rounded: only nearly collinear
  }
  p.push_back({50, 300});
  p.push_back({-20, 150});
  std::shuffle(p.begin(), p.end(), rng);
  return p;
}

// Integer points on the circle x^2 + y^2 = 1105^2 (1105 = 5 * 13 * 17 has many), and its centre.
inline std::vector<Vec2> cocircular_cloud() {
  std::vector<Vec2> p{{0, 0}};
  const long r = 1105;
  for (long x = -r; x <= r; ++x) {
    const long y2 = r * r - x * x;
    const long y = std::lround(std::sqrt(static_cast<double>(y2)));
    if (y * y == y2) {
      p.push_back({static_cast<double>(x), static_cast<double>(y)});
      if (y) p.push_back({static_cast<double>(x), static_cast<double>(-y)});
    }
  }
  return p;
}

// Distinct points repeated 1..6 times, shuffled.
inline std::vector<Vec2> duplicate_heavy(std::uint64_t seed) {
  std::mt19937_64 rng(seed);
  std::vector<Vec2> base = grid_cloud(12, 12);
  auto extra = random_cloud(200, seed + 1, 11);
  base.insert(base.end(), extra.begin(), extra.end());
  std::vector<Vec2> p;
  std::uniform_int_distribution<int> reps(1, 6);
  for (const Vec2& b : base)
    for (int k = reps(rng); k > 0; --k) p.push_back(b);
  std::shuffle(p.begin(), p.end(), rng);
  return p;
}

}  // namespace hg::outline::testing
