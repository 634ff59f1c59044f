#include "camera_bridge/gaps.hpp"

#include <algorithm>
#include <cmath>
#include <cstdint>

#include <opencv2/imgproc.hpp>

namespace hg::camera_bridge {

namespace {

// What one gap (connected set of pixels without a point) holds.
struct Gap {
  int pixels = 0;
  int through = 0;  // returns at table height or below: the laser went through the steel
  int no_return = 0;
  int lit = 0;           // of the no-return pixels, those with light coming back (intensity image)
  bool border = false;   // touches the image border: outside every part
  int part = -1;         // the part whose points enclose it; -2: more than one (outside every part)
  float half_width = 0;  // largest distance to a point pixel, pixels
  bool dropout = false;
};

inline Eigen::Vector3d ray(const camera::Intrinsics& in, int c, int r) {
  return {(c - in.cx) / in.fx, (r - in.cy) / in.fy, 1.0};
}

// Intensity as float (empty when there is none of the right size and type).
cv::Mat intensity_of(const cv::Mat& intensity, const cv::Mat& depth) {
  cv::Mat f;
  if (intensity.empty() || intensity.size() != depth.size()) return f;
  if (intensity.type() != CV_8UC1 && intensity.type() != CV_16UC1) return f;
  intensity.convertTo(f, CV_32F);
  return f;
}

// Half the median intensity of the points: a no-return pixel at least this bright received light from a
// surface (saturated or specular steel), which a hole over nothing does not.
float lit_level(const cv::Mat& intensity, const Segmentation& s) {
  if (intensity.empty() || s.pixel.empty()) return 0;
  std::vector<float> v;
  for (std::size_t i = 0; i < s.pixel.size(); i += 7) v.push_back(intensity.ptr<float>()[s.pixel[i]]);
  std::nth_element(v.begin(), v.begin() + v.size() / 2, v.end());
  return 0.5f * v[v.size() / 2];
}

// The points' part image: 0 none, k + 1 a point of part k.
cv::Mat point_image(const Segmentation& s, const cv::Size& size) {
  cv::Mat img = cv::Mat::zeros(size, CV_8UC1);
  for (std::size_t i = 0; i < s.pixel.size(); ++i) img.data[s.pixel[i]] = static_cast<std::uint8_t>(s.part[i] + 1);
  return img;
}

// Height above the table of pixel (c, r) with a depth of `counts`.
inline double height(const camera::Intrinsics& in, const PlatePlanes& pl, int c, int r, int counts) {
  return pl.table_normal.dot(ray(in, c, r) * (counts * in.depth_unit)) - pl.table_offset;
}

// The gaps (4-connected, as the complement of 8-connected points) with what their pixels hold.
std::vector<Gap> read_gaps(const cv::Mat& depth, const cv::Mat& light, float lit, const camera::Intrinsics& in,
                           const PlatePlanes& pl, const cv::Mat& pts, cv::Mat& cc) {
  const int W = depth.cols, H = depth.rows;
  const cv::Mat empty = pts == 0;
  const int n = cv::connectedComponents(empty, cc, 4, CV_32S);
  std::vector<Gap> gaps(n);
  double thinnest = 1e9;  // half the thinnest part: below it a return is at table height, not on a top face
  for (double o : pl.top_offset) thinnest = std::min(thinnest, 0.5 * (o - pl.table_offset));
  cv::Mat dist;
  cv::distanceTransform(empty, dist, cv::DIST_L2, 3);
  for (int r = 0; r < H; ++r) {
    const int* cr = cc.ptr<int>(r);
    const std::uint16_t* dr = depth.ptr<std::uint16_t>(r);
    for (int c = 0; c < W; ++c) {
      if (!cr[c]) continue;
      Gap& g = gaps[cr[c]];
      ++g.pixels;
      g.border |= r == 0 || c == 0 || r == H - 1 || c == W - 1;
      g.half_width = std::max(g.half_width, dist.ptr<float>(r)[c]);
      if (!dr[c]) {
        ++g.no_return;
        g.lit += !light.empty() && light.ptr<float>(r)[c] >= lit;
      } else if (height(in, pl, c, r, dr[c]) < thinnest) {
        ++g.through;
      }
      const int nb[4][2] = {{c - 1, r}, {c + 1, r}, {c, r - 1}, {c, r + 1}};
      for (const auto& q : nb) {
        if (q[0] < 0 || q[1] < 0 || q[0] >= W || q[1] >= H) continue;
        const int k = pts.ptr<std::uint8_t>(q[1])[q[0]] - 1;
        if (k >= 0) g.part = g.part == -1 || g.part == k ? k : -2;
      }
    }
  }
  return gaps;
}

// Dropout or cut-out (gaps.hpp): through-returns on a tenth of the gap make it a cut-out; without them a
// gap wider than dropout_width is one too, unless light came back from most of its no-return pixels.
void decide(std::vector<Gap>& gaps, double pixel_size, const SegmentParams& P, bool have_light, Segmentation& out) {
  for (std::size_t k = 1; k < gaps.size(); ++k) {
    Gap& g = gaps[k];
    if (g.border || g.part < 0) continue;  // the table around the parts
    const bool through = g.through >= 3 && g.through * 10 >= g.pixels;
    const double width = (2.0 * g.half_width - 1.0) * pixel_size;
    const bool steel_seen = have_light && 2 * g.lit >= g.no_return;
    g.dropout = !through && (width <= P.dropout_width || steel_seen);
    if (!g.dropout) ++out.cutouts;
  }
}

// The pixels of `to_fill` (0 none, k + 1: part k) as points on their part's top plane, merged into the
// points in scan order; `patch` (CV_32S) numbers the patch each belongs to, `area` gets each patch's area.
void fill(const cv::Mat& to_fill, const cv::Mat& patch, const camera::Intrinsics& in, const PlatePlanes& pl,
          std::vector<double>& area, Segmentation& out) {
  Segmentation merged;
  const std::size_t n = out.size();
  std::size_t i = 0;
  auto take = [&](std::size_t j) {
    merged.u.push_back(out.u[j]), merged.v.push_back(out.v[j]), merged.part.push_back(out.part[j]);
    merged.pixel.push_back(out.pixel[j]), merged.filled.push_back(0);
  };
  const int W = to_fill.cols;
  for (int r = 0; r < to_fill.rows; ++r) {
    const std::uint8_t* fr = to_fill.ptr<std::uint8_t>(r);
    for (int c = 0; c < W; ++c) {
      if (!fr[c]) continue;
      const int px = r * W + c;
      for (; i < n && out.pixel[i] < px; ++i) take(i);
      const int k = fr[c] - 1;
      const Eigen::Vector3d d = ray(in, c, r);
      const double nd = pl.top_normal.dot(d), t = pl.top_offset[k] / nd;
      const Eigen::Vector3d q = t * d - out.origin;
      merged.u.push_back(static_cast<float>(q.dot(out.u_axis)));
      merged.v.push_back(static_cast<float>(q.dot(out.v_axis)));
      merged.part.push_back(static_cast<std::int16_t>(k));
      merged.pixel.push_back(px);
      merged.filled.push_back(1);
      area[patch.ptr<int>(r)[c]] += t * t / (in.fx * in.fy * std::abs(nd));  // the pixel's footprint
    }
  }
  for (; i < n; ++i) take(i);
  out.u = std::move(merged.u), out.v = std::move(merged.v), out.part = std::move(merged.part);
  out.pixel = std::move(merged.pixel), out.filled = std::move(merged.filled);
}

// Fills the dropout gaps and the glints (pixels of `to_fill` already set) and counts the patches of two
// pixels or more (single missing pixels leave no hole in an outline): each dropout gap, each 8-connected
// patch of glint.
void count_and_fill(const std::vector<Gap>& gaps, const cv::Mat& cc, const cv::Mat& glint, const camera::Intrinsics& in,
                    const PlatePlanes& pl, cv::Mat& to_fill, Segmentation& out) {
  cv::Mat glints, stats, centroids;
  const int n_glints = cv::connectedComponentsWithStats(glint, glints, stats, centroids, 8, CV_32S);
  cv::Mat patch = glints.clone();  // glint patches 1..n_glints - 1, then the gaps after them
  for (int r = 0; r < cc.rows; ++r) {
    const int* cr = cc.ptr<int>(r);
    for (int c = 0; c < cc.cols; ++c)
      if (cr[c] && gaps[cr[c]].dropout) {
        to_fill.ptr<std::uint8_t>(r)[c] = static_cast<std::uint8_t>(gaps[cr[c]].part + 1);
        patch.ptr<int>(r)[c] = n_glints - 1 + cr[c];
      }
  }
  std::vector<double> area(n_glints + gaps.size(), 0);
  fill(to_fill, patch, in, pl, area, out);
  for (int k = 1; k < n_glints; ++k)
    if (stats.at<int>(k, cv::CC_STAT_AREA) >= 2) ++out.dropout_filled, out.dropout_filled_area += area[k];
  for (std::size_t k = 1; k < gaps.size(); ++k)
    if (gaps[k].dropout && gaps[k].pixels >= 2) ++out.dropout_filled, out.dropout_filled_area += area[n_glints - 1 + k];
}

// Cumulative length along a closed contour (plate-plane points), from a polyline through every 4th point
// (the pixel staircase measured point to point would overstate a slanted edge by up to 8 %; a noisy edge's
// raggedness still adds 1-2 % at 0.8 mm pixels). s[i] is the
// length up to point i, s[n] the whole contour.
std::vector<double> arc_length(const std::vector<Eigen::Vector2d>& p) {
  const std::size_t n = p.size(), step = std::min<std::size_t>(4, std::max<std::size_t>(1, n / 4));
  std::vector<double> s(n + 1, 0);
  for (std::size_t a = 0; a < n; a += step) {
    const std::size_t b = std::min(a + step, n);
    const double len = (p[b % n] - p[a]).norm();
    for (std::size_t j = a + 1; j <= b; ++j) s[j] = s[a] + len * double(j - a) / double(b - a);
  }
  return s;
}

// One outer contour: its length, the length in dropout or shadow, the longest such stretch.
// Whether the no-return band beside contour pixel q ends within `reach` pixels in a return from the table
// (below half the part's thickness): the shadow a triangulation baseline casts beside a lit top face. The
// top's returns end at the edge there; steel at top height beside them would be lit too (it is never in its
// own plate's shadow), so the band cannot hide steel beyond reach.
bool shadow_bounded(const cv::Point& q, const cv::Mat& region, const cv::Mat& depth, const camera::Intrinsics& in,
                    const PlatePlanes& pl, int part, int reach) {
  // Outward: away from the region's pixels around q (a 5 x 5 window), so that the search runs across the
  // edge, not along it into the table beyond the band's ends.
  Eigen::Vector2d out = Eigen::Vector2d::Zero();
  for (int dy = -2; dy <= 2; ++dy)
    for (int dx = -2; dx <= 2; ++dx) {
      const int c = q.x + dx, r = q.y + dy;
      if (c >= 0 && r >= 0 && c < depth.cols && r < depth.rows && region.ptr<std::uint8_t>(r)[c])
        out -= Eigen::Vector2d(dx, dy);
    }
  if (out.squaredNorm() == 0) return false;
  out.normalize();
  const double half = 0.5 * (pl.top_offset[part] - pl.table_offset);
  for (int k = 1; k <= reach; ++k) {
    const int c = int(std::lround(q.x + k * out.x())), r = int(std::lround(q.y + k * out.y()));
    if (c < 0 || r < 0 || c >= depth.cols || r >= depth.rows) return false;
    const int counts = depth.ptr<std::uint16_t>(r)[c];
    if (counts && !region.ptr<std::uint8_t>(r)[c]) return height(in, pl, c, r, counts) < half;
  }
  return false;
}

void assess_contour(const std::vector<cv::Point>& contour, const cv::Mat& region, const cv::Mat& depth,
                    const camera::Intrinsics& in, const PlatePlanes& pl, int part, double shadow_tan,
                    Segmentation& out) {
  const std::size_t n = contour.size();
  if (n < 3) return;
  // The widest shadow a baseline of angle atan(shadow_tan) casts beside this part, in pixels.
  const double thickness = pl.top_offset[part] - pl.table_offset;
  const int reach = int(std::ceil(shadow_tan * thickness * in.fx / std::abs(pl.top_offset[part])));
  std::size_t shadowed = 0;
  std::vector<Eigen::Vector2d> p(n);
  std::vector<char> dark(n);
  for (std::size_t i = 0; i < n; ++i) {
    const cv::Point& q = contour[i];
    const Eigen::Vector3d d = ray(in, q.x, q.y);
    const Eigen::Vector3d x = pl.top_offset[part] / pl.top_normal.dot(d) * d - out.origin;
    p[i] = {x.dot(out.u_axis), x.dot(out.v_axis)};
    bool seen = false;
    for (int dy = -1; dy <= 1 && !seen; ++dy)
      for (int dx = -1; dx <= 1 && !seen; ++dx) {
        const int c = q.x + dx, r = q.y + dy;
        if (c < 0 || r < 0 || c >= depth.cols || r >= depth.rows || region.ptr<std::uint8_t>(r)[c]) continue;
        seen = depth.ptr<std::uint16_t>(r)[c] != 0;
      }
    if (!seen && shadow_bounded(q, region, depth, in, pl, part, reach)) seen = true, ++shadowed;
    dark[i] = !seen;
  }
  const std::vector<double> s = arc_length(p);
  const double total = s[n], per_point = total / double(n);
  out.edge_length += total;
  out.edge_shadow_length += per_point * double(shadowed);
  // Runs of dark points, around the closed contour (starting after a seen point).
  std::size_t start = 0;
  while (start < n && dark[start]) ++start;
  if (start == n) {
    out.edge_dropout_length += total;
    out.largest_edge_gap = std::max(out.largest_edge_gap, total);
    return;
  }
  // A run's length: first to last dark point along the contour, at least one point's share.
  double run = -1;
  for (std::size_t j = 1; j <= n; ++j) {
    const std::size_t i = (start + j) % n, prev = (start + j - 1) % n;
    if (dark[i]) {
      run = run < 0 ? 0 : run + (i > prev ? s[i] - s[prev] : s[n] - s[prev]);
    } else if (run >= 0) {
      run = std::max(run, per_point);
      out.edge_dropout_length += run;
      out.largest_edge_gap = std::max(out.largest_edge_gap, run);
      run = -1;
    }
  }
}

// The outer contour of each part's points (filled dropout included, kept mixed pixels not), the largest
// piece of each part.
void assess_edge(const cv::Mat& depth, const camera::Intrinsics& in, const PlatePlanes& pl, const Segmentation& s0,
                 double shadow_tan, Segmentation& out) {
  const cv::Mat pts = point_image(s0, depth.size());
  for (int k = 0; k < out.num_parts; ++k) {
    // Without the kept mixed pixels: each saw the table beside the steel, so the contour of the rest has the
    // drop from plate to table in the frame just outside it wherever they lie.
    cv::Mat region = pts == k + 1;
    if (!out.mixed.empty()) region.setTo(0, out.mixed);
    std::vector<std::vector<cv::Point>> contours;
    cv::findContours(region.clone(), contours, cv::RETR_EXTERNAL, cv::CHAIN_APPROX_NONE);
    if (contours.empty()) continue;
    const auto largest = std::max_element(contours.begin(), contours.end(), [](const auto& a, const auto& b) {
      return std::abs(cv::contourArea(a)) < std::abs(cv::contourArea(b));
    });
    assess_contour(*largest, region, depth, in, pl, k, shadow_tan, out);
  }
}

}  // namespace

cv::Mat saturated_no_return(const cv::Mat& depth, const cv::Mat& intensity) {
  cv::Mat out = cv::Mat::zeros(depth.size(), CV_8UC1);
  if (intensity.empty() || intensity.size() != depth.size()) return out;
  if (intensity.type() != CV_8UC1 && intensity.type() != CV_16UC1) return out;
  const double full = intensity.type() == CV_8UC1 ? 255 : 65535;
  return (intensity >= full) & (depth == 0);
}

void fill_gaps_and_assess_edge(const cv::Mat& depth, const cv::Mat& intensity, const camera::Intrinsics& in,
                               const PlatePlanes& pl, const SegmentParams& P, Segmentation& out) {
  if (P.fill_dropout) {
    const cv::Mat light = intensity_of(intensity, depth);
    const float lit = lit_level(light, out);
    cv::Mat pts = point_image(out, depth.size()), to_fill = cv::Mat::zeros(depth.size(), CV_8UC1), cc;
    // Saturated pixels of a part's mask: steel (gaps.hpp), points of that part before the gaps are read.
    const cv::Mat glint = saturated_no_return(depth, intensity) & (out.labels > 0) & (pts == 0);
    out.labels.copyTo(to_fill, glint);
    out.labels.copyTo(pts, glint);
    std::vector<Gap> gaps = read_gaps(depth, light, lit, in, pl, pts, cc);
    // A pixel's size on the plate near the optical axis.
    const double pixel_size = std::abs(pl.top_offset.front() / pl.top_normal.z()) / in.fx;
    decide(gaps, pixel_size, P, !light.empty(), out);
    count_and_fill(gaps, cc, glint, in, pl, to_fill, out);
  } else {
    out.filled.assign(out.size(), 0);
  }
  assess_edge(depth, in, pl, out, P.shadow_tan, out);
}

}  // namespace hg::camera_bridge
