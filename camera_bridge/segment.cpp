#include "camera_bridge/segment.hpp"

#include "camera_bridge/gaps.hpp"

#include <algorithm>
#include <cstdio>
#include <limits>
#include <cmath>
#include <random>
#include <stdexcept>
#include <utility>

#include <Eigen/Eigenvalues>
#include <opencv2/imgproc.hpp>

namespace hg::camera_bridge {

namespace {

std::string fmt(const char* f, double a, double b = 0, double c = 0, double d = 0) {
  char buf[256];
  std::snprintf(buf, sizeof buf, f, a, b, c, d);
  return buf;
}

void check(const SegmentParams& p) {
  auto bad = [](const std::string& s) { throw std::invalid_argument("segmentation: " + s); };
  if (p.ransac_iterations < 1) bad("ransac_iterations must be >= 1");
  if (!(p.ransac_threshold > 0)) bad("ransac_threshold must be > 0");
  if (p.sample_stride < 1) bad("sample_stride must be >= 1");
  if (!(p.min_table_fraction >= 0 && p.min_table_fraction <= 1)) bad("min_table_fraction must be in [0, 1]");
  if (!(p.min_height > 0) || !(p.max_height > p.min_height)) bad("need 0 < min_height < max_height");
  if (p.open_size < 0 || p.open_size > 31) bad("open_size must be in 0..31");
  if (p.close_size < 0 || p.close_size > 31) bad("close_size must be in 0..31");
  if (!(p.min_area >= 0)) bad("min_area must be >= 0");
  if (!(p.top_tolerance >= 0)) bad("top_tolerance must be >= 0");
  if (!(p.mixed_fraction >= 0)) bad("mixed_fraction must be >= 0");
  if (!(p.shadow_tan >= 0 && p.shadow_tan <= 1)) bad("shadow_tan must be in [0, 1]");
  if (!(p.footprint_pixels >= 0) || std::isinf(p.footprint_pixels)) bad("footprint_pixels must be a number >= 0");
  if (!(p.dropout_width >= 0) || std::isinf(p.dropout_width)) bad("dropout_width must be a number >= 0");
  if (p.calibrated_plane && !(std::abs(p.plane_normal.norm() - 1.0) < 1e-3))
    bad("calibrated plane normal must be a unit vector");
}

// Least-squares plane through points (centroid and the eigenvector of the smallest eigenvalue of the
// scatter), accumulated about `ref` so the sums do not cancel at camera distances.
struct PlaneSums {
  Eigen::Vector3d ref = Eigen::Vector3d::Zero(), s = Eigen::Vector3d::Zero();
  Eigen::Matrix3d ss = Eigen::Matrix3d::Zero();
  double n = 0;
  void add(const Eigen::Vector3d& p) {
    const Eigen::Vector3d q = p - ref;
    s += q;
    ss.noalias() += q * q.transpose();
    n += 1;
  }
  Eigen::Vector3d centroid() const { return ref + s / n; }
  Eigen::Matrix3d scatter() const { return ss - s * s.transpose() / n; }
};

Eigen::Vector3d smallest_eigenvector(const Eigen::Matrix3d& m) {
  Eigen::SelfAdjointEigenSolver<Eigen::Matrix3d> es(m);
  return es.eigenvectors().col(0);  // eigenvalues ascending
}

// Normal towards the camera (the camera is at the origin): n . (0 - p) > 0 for points p of the plane.
void orient(Eigen::Vector3d& n, const Eigen::Vector3d& point_on_plane) {
  if (n.dot(point_on_plane) > 0) n = -n;
}

}  // namespace

std::string frame_defect(const cv::Mat& depth, const camera::Intrinsics& in) {
  if (in.width <= 0 || in.height <= 0 || !(in.fx > 0) || !(in.fy > 0) || !(in.depth_unit > 0) ||
      !std::isfinite(in.cx) || !std::isfinite(in.cy))
    return "bad intrinsics (" + std::to_string(in.width) + "x" + std::to_string(in.height) + ", fx " +
           std::to_string(in.fx) + ", fy " + std::to_string(in.fy) + ", depth unit " + std::to_string(in.depth_unit) +
           ")";
  if (depth.empty()) return "empty depth image";
  if (depth.type() != CV_16UC1)
    return "depth image is not 16-bit single-channel (OpenCV type " + std::to_string(depth.type()) + ")";
  if (depth.cols != in.width || depth.rows != in.height)
    return "depth image is " + std::to_string(depth.cols) + "x" + std::to_string(depth.rows) +
           " but the intrinsics say " + std::to_string(in.width) + "x" + std::to_string(in.height);
  if (cv::countNonZero(depth) == 0) return "no valid pixel (all zero)";
  return {};
}

namespace {

// Pixel ray directions ((c - cx) / fx, (r - cy) / fy, 1): a per column, b per row.
struct Rays {
  std::vector<double> a, b;
  double unit = 0;  // metres per depth count
};

Rays pixel_rays(const camera::Intrinsics& in, int W, int H) {
  Rays ray{std::vector<double>(W), std::vector<double>(H), in.depth_unit};
  for (int c = 0; c < W; ++c) ray.a[c] = (c - in.cx) / in.fx;
  for (int r = 0; r < H; ++r) ray.b[r] = (r - in.cy) / in.fy;
  return ray;
}

// n . p = offset, n towards the camera.
struct Plane {
  Eigen::Vector3d n;
  double offset;
};

// Camera-frame points of the pixels with depth on a grid of `stride`.
std::vector<Eigen::Vector3d> sample_points(const cv::Mat& depth, const Rays& ray, int stride) {
  const int W = depth.cols, H = depth.rows;
  std::vector<Eigen::Vector3d> samples;
  samples.reserve(static_cast<std::size_t>(W / stride + 1) * (H / stride + 1));
  for (int r = stride / 2; r < H; r += stride) {
    const std::uint16_t* dr = depth.ptr<std::uint16_t>(r);
    for (int c = stride / 2; c < W; c += stride)
      if (dr[c]) samples.emplace_back(ray.a[c] * dr[c] * ray.unit, ray.b[r] * dr[c] * ray.unit, dr[c] * ray.unit);
  }
  return samples;
}

// RANSAC, deterministic: hypotheses scored on a fixed subset of about 2000 samples. False when no
// hypothesis faces the camera (plane left as it was).
bool ransac_plane(const std::vector<Eigen::Vector3d>& samples, const SegmentParams& P, Plane& plane) {
  std::mt19937_64 rng(P.ransac_seed);
  std::uniform_int_distribution<std::size_t> pick(0, samples.size() - 1);
  const std::size_t eval_step = std::max<std::size_t>(1, samples.size() / 2000);
  std::size_t best = 0;
  for (int it = 0; it < P.ransac_iterations; ++it) {
    const Eigen::Vector3d& a = samples[pick(rng)];
    const Eigen::Vector3d& b = samples[pick(rng)];
    const Eigen::Vector3d& c = samples[pick(rng)];
    Eigen::Vector3d h = (b - a).cross(c - a);
    const double len = h.norm();
    if (!(len > 1e-9)) continue;
    h /= len;
    if (std::abs(h.z()) < 0.5) continue;  // a table seen more than 60 degrees off axis is not our cell
    const double o = h.dot(a);
    std::size_t score = 0;
    for (std::size_t i = 0; i < samples.size(); i += eval_step)
      score += std::abs(h.dot(samples[i]) - o) < P.ransac_threshold;
    if (score > best) {
      best = score;
      plane = {h, o};
    }
  }
  return best > 0;
}

// Least-squares refinement on the inliers (twice: the second pass uses the better plane's inliers).
// Returns the inlier count of the last pass; `rms` is the inliers' RMS distance from the refitted plane.
std::size_t refine_plane(const std::vector<Eigen::Vector3d>& samples, double threshold, Plane& plane, double& rms) {
  std::size_t inliers = 0;
  for (int pass = 0; pass < 2; ++pass) {
    PlaneSums sums;
    sums.ref = samples[samples.size() / 2];
    for (const auto& p : samples)
      if (std::abs(plane.n.dot(p) - plane.offset) < threshold) sums.add(p);
    inliers = static_cast<std::size_t>(sums.n);
    if (inliers < 3) break;
    const Eigen::Vector3d c = sums.centroid();
    plane.n = smallest_eigenvector(sums.scatter());
    orient(plane.n, c);
    plane.offset = plane.n.dot(c);
    rms = std::sqrt(std::max(0.0, plane.n.dot(sums.scatter() * plane.n) / sums.n));
  }
  return inliers;
}

// The table plane (calibrated, or found by RANSAC), refined on its inliers. Empty when found, else why not.
std::string fit_table(const cv::Mat& depth, const Rays& ray, const SegmentParams& P, Plane& table, double& rms) {
  const std::vector<Eigen::Vector3d> samples = sample_points(depth, ray, P.sample_stride);
  if (samples.size() < 50)
    return "too few valid depth pixels (" + std::to_string(samples.size()) + " of the sampled grid) to find the table";
  table = {P.plane_normal.normalized(), P.plane_offset};
  if (!P.calibrated_plane && !ransac_plane(samples, P, table))
    return "no table plane found (RANSAC found no plane facing the camera)";
  const std::size_t inliers = refine_plane(samples, P.ransac_threshold, table, rms);
  const double table_fraction = static_cast<double>(inliers) / samples.size();
  if (table_fraction < P.min_table_fraction)
    return fmt("no table plane: only %.1f %% of the valid pixels lie on the best plane (need %.1f %%)",
               100 * table_fraction, 100 * P.min_table_fraction);
  return {};
}

// Part mask: height above the table within the thickness band; `nodata` marks the pixels without depth.
// Float and branch-free so the compiler vectorises it: the height is n . (z ray) - offset, with z in
// depth counts folded into the per-column factor (float keeps ~0.1 um at 2 m, far below the noise).
void height_band_mask(const cv::Mat& depth, const Rays& ray, const Plane& table, const SegmentParams& P, cv::Mat& mask,
                      cv::Mat& nodata) {
  const int W = depth.cols, H = depth.rows;
  const Eigen::Vector3d& n = table.n;
  mask.create(H, W, CV_8UC1);
  nodata.create(H, W, CV_8UC1);
  std::vector<float> na(W);
  for (int c = 0; c < W; ++c) na[c] = static_cast<float>(n.x() * ray.a[c] * ray.unit);
  const float lo = static_cast<float>(P.min_height + table.offset),
              hi = static_cast<float>(P.max_height + table.offset);
  for (int r = 0; r < H; ++r) {
    const std::uint16_t* dr = depth.ptr<std::uint16_t>(r);
    std::uint8_t* mr = mask.ptr<std::uint8_t>(r);
    std::uint8_t* zr = nodata.ptr<std::uint8_t>(r);
    const float nb = static_cast<float>((n.y() * ray.b[r] + n.z()) * ray.unit);
    for (int c = 0; c < W; ++c) {
      const float d = static_cast<float>(dr[c]);
      const float h = d * (na[c] + nb);  // n . p, compared with offset + band
      mr[c] = static_cast<std::uint8_t>(-static_cast<int>((d > 0.0f) & (h >= lo) & (h <= hi)));
      zr[c] = static_cast<std::uint8_t>(-static_cast<int>(d == 0.0f));
    }
  }
}

// Opening (k x k squares that fit the mask) against specks of table noise above min_height, and
// closing against pin holes (dropout, noise below min_height). Erosion counts pixels without depth as
// part and the opened mask keeps only real mask pixels: otherwise a dropout beside the edge, or a mixed
// pixel there that falls below min_height, takes the good edge pixels around it with it, and the
// outline runs a pixel or two into the material for a stretch (the deepest errors of the whole
// pipeline's path came from that). The default 2 x 2 removes single pixels and one-pixel lines, which
// is what the specks are; a larger kernel eats more of the edge wherever such pixels cluster.
// Explicit anchors: erosion by the square at (0, 0), dilation by its reflection, so even sizes stay put.
void open_and_close(cv::Mat& mask, const cv::Mat& nodata, const SegmentParams& P) {
  auto square = [](int k) { return cv::Mat::ones(k, k, CV_8UC1); };
  if (P.open_size > 1) {
    const int k = P.open_size;
    thread_local cv::Mat opened;
    cv::bitwise_or(mask, nodata, opened);
    cv::erode(opened, opened, square(k), {0, 0});
    cv::dilate(opened, opened, square(k), {k - 1, k - 1});
    cv::bitwise_and(opened, mask, mask);
  }
  if (P.close_size > 1) {
    const int k = P.close_size;
    cv::dilate(mask, mask, square(k), {0, 0});
    cv::erode(mask, mask, square(k), {k - 1, k - 1});
  }
}

// Connected components of the mask with their pixel counts and row ranges (index 0: background).
struct Components {
  int count = 0;
  std::vector<int> area, first_row, last_row;
};

// Plain labelling plus our own area and row-range pass: connectedComponentsWithStats computes its
// statistics several times slower than this.
Components label_components(const cv::Mat& mask, cv::Mat& cc) {
  const int W = mask.cols, H = mask.rows;
  Components comp;
  comp.count = cv::connectedComponents(mask, cc, 8, CV_32S);
  comp.area.assign(comp.count, 0);
  comp.first_row.assign(comp.count, H);
  comp.last_row.assign(comp.count, -1);
  for (int r = 0; r < H; ++r) {
    const int* cr = cc.ptr<int>(r);
    for (int c = 0; c < W; ++c)
      if (const int l = cr[c]) {
        ++comp.area[l];
        comp.first_row[l] = std::min(comp.first_row[l], r);
        comp.last_row[l] = r;
      }
  }
  return comp;
}

// Ids of the components of at least min_area, largest first (at most 254, or the largest only).
std::vector<int> kept_components(const Components& comp, double pixel_area, const SegmentParams& P) {
  std::vector<int> keep;
  for (int k = 1; k < comp.count; ++k)
    if (comp.area[k] * pixel_area >= P.min_area) keep.push_back(k);
  const auto& area = comp.area;
  std::sort(keep.begin(), keep.end(), [&](int a, int b) { return area[a] != area[b] ? area[a] > area[b] : a < b; });
  if (!keep.empty() && !P.all_parts) keep.resize(1);
  if (keep.size() > 254) keep.resize(254);
  return keep;
}

std::string no_part_text(const Components& comp, double pixel_area, const SegmentParams& P) {
  if (comp.count <= 1) return "nothing on the table";
  const int largest_px = *std::max_element(comp.area.begin() + 1, comp.area.end());
  return fmt("nothing on the table larger than %.4f m^2 (largest blob %.4f m^2)", P.min_area, largest_px * pixel_area);
}

// The part pixels with a depth, as float camera-frame points in scan order, with their part and pixel.
struct PartPixels {
  std::vector<float> x, y, z;
  std::vector<std::uint8_t> part;
  std::vector<std::int32_t> pixel;
  std::size_t size() const { return x.size(); }
  Eigen::Vector3d point(std::size_t i) const { return Eigen::Vector3d(x[i], y[i], z[i]); }
};

// Labels 1..K in scan order of each kept component's first pixel into `labels`; the part pixels with a
// depth are gathered in the same pass, so later passes touch only them. Returns K; relabel[component]
// is its label.
int gather_parts(const cv::Mat& depth, const Rays& ray, const cv::Mat& cc, const Components& comp,
                 const std::vector<int>& keep, cv::Mat& labels, PartPixels& pts, std::vector<std::uint8_t>& relabel) {
  const int W = depth.cols, H = depth.rows;
  relabel.assign(comp.count, 0);
  for (int k : keep) relabel[k] = 255;  // kept, number not given yet
  labels.create(H, W, CV_8UC1);
  std::size_t expect = 0;
  for (int k : keep) expect += comp.area[k];
  pts.x.reserve(expect), pts.y.reserve(expect), pts.z.reserve(expect), pts.part.reserve(expect),
      pts.pixel.reserve(expect);
  // Only the rows of the kept components can hold a label.
  int by0 = H, by1 = 0;
  for (int k : keep) by0 = std::min(by0, comp.first_row[k]), by1 = std::max(by1, comp.last_row[k] + 1);
  labels.setTo(0);
  int next = 0;
  for (int r = by0; r < by1; ++r) {
    const int* cr = cc.ptr<int>(r);
    const std::uint16_t* dr = depth.ptr<std::uint16_t>(r);
    std::uint8_t* lr = labels.ptr<std::uint8_t>(r);
    for (int c = 0; c < W; ++c) {
      std::uint8_t& l = relabel[cr[c]];
      if (l == 255) l = static_cast<std::uint8_t>(++next);
      lr[c] = l;
      if (l && dr[c]) {
        const double z = dr[c] * ray.unit;
        pts.x.push_back(static_cast<float>(ray.a[c] * z));
        pts.y.push_back(static_cast<float>(ray.b[r] * z));
        pts.z.push_back(static_cast<float>(z));
        pts.part.push_back(static_cast<std::uint8_t>(l - 1));
        pts.pixel.push_back(r * W + c);
      }
    }
  }
  return next;
}

// Plate top planes: one normal for all parts (they lie flat on the same table), one offset each, and
// the cut `tol` on the distance from them.
struct TopPlanes {
  Eigen::Vector3d normal;
  std::vector<double> offset;
  double tol = std::numeric_limits<double>::infinity();
  Eigen::Vector3d origin;  // the largest part's centroid on its plane
  // Per part, the top face's height off its plane as a quadratic in the in-plane coordinates (x, y along
  // e1, e2 about centre[k]): bow[k] . (1, x, y, x^2, xy, y^2). Zero for a flat plate; a bowed one
  // (docs/scene.md, warp) has its edge off the plane by its bow there.
  std::vector<Eigen::Matrix<double, 6, 1>> bow;
  std::vector<Eigen::Vector3d> centre;
  Eigen::Vector3d e1, e2;
  bool holds(const PartPixels& pts, std::size_t i) const {
    return std::abs(normal.dot(pts.point(i)) - offset[pts.part[i]]) <= tol;
  }
  Eigen::Matrix<double, 6, 1> monomials(int k, const Eigen::Vector3d& p) const {
    const double x = e1.dot(p - centre[k]), y = e2.dot(p - centre[k]);
    return (Eigen::Matrix<double, 6, 1>() << 1, x, y, x * x, x * y, y * y).finished();
  }
  // The top face's offset along the normal at (above or below) point p of part k.
  double offset_at(int k, const Eigen::Vector3d& p) const {
    return offset[k] + (bow.empty() ? 0.0 : bow[k].dot(monomials(k, p)));
  }
};

// Each part's bow (TopPlanes::bow): least squares on every 8th of its top pixels (thousands: the bow comes
// out to a few micrometres through the depth's noise and quantization); none for a part with fewer than 60.
// The coordinates' origin is the part's first pixel (any point of the part keeps the sums well conditioned).
void fit_top_bows(const PartPixels& pts, int K, TopPlanes& top) {
  top.e1 = top.normal.unitOrthogonal(), top.e2 = top.normal.cross(top.e1);
  top.centre.assign(K, Eigen::Vector3d::Zero());
  std::vector<bool> seen(K, false);
  for (std::size_t i = 0; i < pts.size(); ++i)
    if (!seen[pts.part[i]]) seen[pts.part[i]] = true, top.centre[pts.part[i]] = pts.point(i);
  std::vector<Eigen::Matrix<double, 6, 6>> ata(K, Eigen::Matrix<double, 6, 6>::Zero());
  std::vector<Eigen::Matrix<double, 6, 1>> atb(K, Eigen::Matrix<double, 6, 1>::Zero());
  std::vector<int> used(K, 0);
  for (std::size_t i = 0; i < pts.size(); i += 8) {
    if (!top.holds(pts, i)) continue;
    const int k = pts.part[i];
    const Eigen::Vector3d p = pts.point(i);
    const Eigen::Matrix<double, 6, 1> m = top.monomials(k, p);
    ata[k].noalias() += m * m.transpose(), atb[k] += m * (top.normal.dot(p) - top.offset[k]), ++used[k];
  }
  top.bow.assign(K, Eigen::Matrix<double, 6, 1>::Zero());
  for (int k = 0; k < K; ++k)
    if (used[k] >= 60) top.bow[k] = ata[k].ldlt().solve(atb[k]);
}

// Fitted on the part pixels, then refitted twice without the pixels far from it (mixed edge pixels,
// side walls), whose residuals are one-sided and would tilt the plane. Sums in double about a reference
// point near the table. False when the largest part has too few pixels to fit a plane.
bool fit_top_planes(const PartPixels& pts, int K, int largest, const Eigen::Vector3d& table_normal, double z_table,
                    double top_tolerance, TopPlanes& top) {
  std::vector<PlaneSums> part_sums(K);
  const Eigen::Vector3d ref(0, 0, z_table);
  top.normal = table_normal;  // start from the table's
  top.offset.assign(K, 0);
  std::vector<double> residual_sample;
  for (int pass = 0; pass < 3; ++pass) {
    for (auto& ps : part_sums) ps = PlaneSums{ref};
    for (std::size_t i = 0; i < pts.size(); ++i)
      if (pass == 0 || top.holds(pts, i)) part_sums[pts.part[i]].add(pts.point(i));
    Eigen::Matrix3d scatter = Eigen::Matrix3d::Zero();
    for (const auto& ps : part_sums)
      if (ps.n >= 1) scatter += ps.scatter();
    const auto& big = part_sums[largest];
    if (!(big.n >= 3)) return false;
    top.normal = smallest_eigenvector(scatter);
    orient(top.normal, big.centroid());
    for (int k = 0; k < K; ++k) top.offset[k] = part_sums[k].n >= 1 ? top.normal.dot(part_sums[k].centroid()) : 0;
    // Robust residual scale (median absolute residual of every 3rd point) for the next pass's cut.
    residual_sample.clear();
    for (std::size_t i = 0; i < pts.size(); i += 3)
      residual_sample.push_back(std::abs(top.normal.dot(pts.point(i)) - top.offset[pts.part[i]]));
    auto mid = residual_sample.begin() + residual_sample.size() / 2;
    std::nth_element(residual_sample.begin(), mid, residual_sample.end());
    const double sigma = residual_sample.empty() ? 0.0 : 1.4826 * *mid;
    top.tol = top_tolerance > 0 ? top_tolerance : std::max(4 * sigma, 0.001);
  }
  top.origin = part_sums[largest].centroid();
  return true;
}

// What a part pixel's point is: on the top plane (within the tolerance), a mixed pixel at the edge kept as
// steel (placed where its ray meets the top plane, or straight down when it may see a side wall), or neither.
enum PointKind : std::uint8_t { kDrop = 0, kTop = 1, kMixedSight = 2, kMixedDown = 3, kSawTable = 4 };

// Depth fraction of a pixel between table and top along its own ray: 0 on the table, 1 on the top plane.
// A pixel whose footprint straddles the edge reports the return-weighted mean depth of both (docs/cameras.md,
// "Mixed pixels at the edge"), so the fraction is the steel's share of its footprint's return.
// `o`: the top face's offset along the top normal beside the pixel (local_top_offset()).
double depth_fraction(const PartPixels& pts, std::size_t i, const TopPlanes& top, double o, const Plane& table) {
  const Eigen::Vector3d p = pts.point(i), d = p / p.z();
  const double z_top = o / top.normal.dot(d), z_table = table.offset / table.n.dot(d);
  return (z_table - p.z()) / (z_table - z_top);
}

// The pixel where the camera's vertical (the top plane's normal) meets the image: vertical lines, such as a
// plate's side wall seen edge-on, run through it, and a wall is seen only where the edge faces it.
Eigen::Vector2d nadir_pixel(const camera::Intrinsics& in, const Eigen::Vector3d& normal) {
  const double nz = std::abs(normal.z()) > 1e-9 ? normal.z() : 1e-9;
  return {in.cx + in.fx * normal.x() / nz, in.cy + in.fy * normal.y() / nz};
}

// The depth fraction of a pixel whose centre lies exactly on the top face's edge: the least a pixel with its
// centre on the steel shows. Its footprint (SegmentParams::footprint_pixels wide, returns taken equal) is
// half steel; the other half sees the table, or, where the edge faces the nadir (cos_wall > 0, the cosine
// between the edge's outward normal and the direction to the nadir), first the side wall: seen from the
// camera it reaches W = t tan(theta) cos_wall beyond the edge, its depth falling linearly from top to table,
// so that half of the footprint (L = half its width) shows the fraction 1 - L / 2W (W >= L) or W / 2L.
double steel_centre_fraction(const PartPixels& pts, std::size_t i, const TopPlanes& top, double o, const Plane& table,
                             const camera::Intrinsics& in, double cos_wall, const SegmentParams& P) {
  if (!(cos_wall > 0)) return P.mixed_fraction;
  const double t = o - table.offset;
  const Eigen::Vector3d p = pts.point(i), T = p * (o / top.normal.dot(p));  // its ray on the top plane
  const double tan_theta = (T - o * top.normal).norm() / std::abs(o);
  const double wall = t * tan_theta * cos_wall, half = 0.5 * P.footprint_pixels * T.z() / in.fx;
  const double seen = wall >= half ? 1 - half / (2 * wall) : wall / (2 * half);
  return P.mixed_fraction + (1 - P.mixed_fraction) * seen;
}

// Classifies the part pixels (PointKind). A pixel off the top plane is a mixed pixel kept as steel when it
// borders a top pixel of its part (or a saturated one) and its depth fraction is at least
// SegmentParams::mixed_fraction: for a footprint symmetric about the pixel's centre and cut by a straight edge, the
// centre lies on the steel when the steel covers half the footprint or more. Where the edge faces the nadir pixel the
// camera also sees the plate's side wall, whose pixels lie between table and top as well: there the point goes straight
// down (a wall pixel then lands on the edge, never beyond it); elsewhere along its ray (its centre on the top).
// `local`: for each point kept as a mixed pixel, the top face's offset there (TopPlanes::offset_at()).
std::vector<std::uint8_t> classify(const cv::Mat& depth, const PartPixels& pts, const TopPlanes& top,
                                   const Plane& table, const camera::Intrinsics& in, const SegmentParams& P,
                                   cv::Mat top_img, std::vector<double>& local) {
  const std::size_t n = pts.size();
  const int W = in.width, H = in.height;
  std::vector<std::uint8_t> kind(n, kDrop);
  local.assign(n, 0.0);
  // top_img: part + 1 of the part's saturated pixels (a glint is top face too, gaps.hpp: where a ground
  // strip's glint reaches the edge the edge pixels border no top pixel with a depth), and of the top pixels.
  for (std::size_t i = 0; i < n; ++i)
    if (top.holds(pts, i)) kind[i] = kTop, top_img.data[pts.pixel[i]] = static_cast<std::uint8_t>(pts.part[i] + 1);
  if (!(P.mixed_fraction <= 1)) return kind;
  const Eigen::Vector2d nadir = nadir_pixel(in, top.normal);
  for (std::size_t i = 0; i < n; ++i) {
    const int c = pts.pixel[i] % W, r = pts.pixel[i] / W;
    Eigen::Vector2d inward = Eigen::Vector2d::Zero();  // towards the top pixels around it
    bool edge = false;  // a neighbour returned, but not from this part's top: a depth jump beside it
    for (int dr = -1; dr <= 1; ++dr)
      for (int dc = -1; dc <= 1; ++dc) {
        const int cc = c + dc, rr = r + dr;
        const bool on_top =
            cc >= 0 && rr >= 0 && cc < W && rr < H && top_img.ptr<std::uint8_t>(rr)[cc] == pts.part[i] + 1;
        if (on_top) inward += Eigen::Vector2d(dc, dr);
        edge |= !on_top && cc >= 0 && rr >= 0 && cc < W && rr < H && depth.ptr<std::uint16_t>(rr)[cc];
      }
    if (!edge || inward.squaredNorm() == 0) continue;  // inside the top face, or not beside it at all
    const bool on_plane = kind[i] == kTop;
    kind[i] = kDrop;
    const Eigen::Vector2d to_nadir = (nadir - Eigen::Vector2d(c, r)).normalized();
    const double cos_wall = -inward.normalized().dot(to_nadir);  // > 0: the edge faces the nadir
    const double o = top.offset_at(pts.part[i], pts.point(i));
    const double f = depth_fraction(pts, i, top, o, table);
    if (!(f >= steel_centre_fraction(pts, i, top, o, table, in, cos_wall, P))) continue;
    if (!on_plane && !(f <= 1.0 + top.tol / std::max(1e-3, o - table.offset))) continue;
    kind[i] = (cos_wall > 0 ? kMixedDown : kMixedSight) | (on_plane ? 0 : kSawTable);
    local[i] = o;
  }
  return kind;
}

// The plate frame (origin on the largest part's top plane, u along the camera's x where possible) and
// the in-plane coordinates of the points kept (classify()), in scan-line (gathered) order.
void project_onto_top(const cv::Mat& depth, const PartPixels& pts, const TopPlanes& top, const Plane& table,
                      const camera::Intrinsics& in, const SegmentParams& P, const cv::Mat& glint, Segmentation& out) {
  const Eigen::Vector3d& pn = top.normal;
  out.normal = pn;
  out.origin = top.origin;
  out.thickness = table.n.dot(out.origin) - table.offset;
  Eigen::Vector3d ux = Eigen::Vector3d::UnitX() - pn.x() * pn;
  if (ux.norm() < 1e-6) ux = Eigen::Vector3d::UnitY() - pn.y() * pn;  // plane perpendicular to camera x
  out.u_axis = ux.normalized();
  out.v_axis = pn.cross(out.u_axis);
  cv::Mat glint_labels = cv::Mat::zeros(in.height, in.width, CV_8UC1);
  out.labels.copyTo(glint_labels, glint);
  std::vector<double> local;
  const std::vector<std::uint8_t> kind = classify(depth, pts, top, table, in, P, std::move(glint_labels), local);
  const std::size_t npts = pts.size();
  out.u.reserve(npts);
  out.v.reserve(npts);
  out.part.reserve(npts);
  out.pixel.reserve(npts);
  out.mixed = cv::Mat::zeros(in.height, in.width, CV_8UC1);
  for (std::size_t i = 0; i < npts; ++i) {
    if (kind[i] == kDrop) continue;
    Eigen::Vector3d p = pts.point(i);
    if ((kind[i] & 3) == kMixedSight) p *= local[i] / pn.dot(p);  // where its ray meets the top beside it
    if (kind[i] & kSawTable) out.mixed.data[pts.pixel[i]] = 255;
    const Eigen::Vector3d q = p - out.origin;  // orthogonal projection = in-plane coordinates
    out.u.push_back(static_cast<float>(q.dot(out.u_axis)));
    out.v.push_back(static_cast<float>(q.dot(out.v_axis)));
    out.part.push_back(static_cast<std::int16_t>(pts.part[i]));
    out.pixel.push_back(pts.pixel[i]);
  }
}

}  // namespace

Segmentation segment(const cv::Mat& depth, const camera::Intrinsics& in, const SegmentParams& P,
                     const cv::Mat& intensity) {
  check(P);
  Segmentation out;
  auto fail = [&](SegmentStatus status, std::string why) {
    out.status = status;
    out.text = std::move(why);
    return out;
  };
  if (std::string why = frame_defect(depth, in); !why.empty()) return fail(SegmentStatus::BadFrame, why);
  const Rays ray = pixel_rays(in, depth.cols, depth.rows);
  Plane table;
  if (std::string why = fit_table(depth, ray, P, table, out.table_rms); !why.empty())
    return fail(SegmentStatus::BadFrame, why);
  out.table_normal = table.n;
  out.table_offset = table.offset;

  // Scratch images kept per thread: allocating ~6 MB afresh each frame costs page faults every time.
  thread_local cv::Mat mask, nodata, cc;
  height_band_mask(depth, ray, table, P, mask, nodata);
  const cv::Mat glint = saturated_no_return(depth, intensity);
  mask |= glint;  // a glint is steel at no known height (gaps.hpp)
  open_and_close(mask, nodata, P);
  const Components comp = label_components(mask, cc);
  // A pixel's footprint on the table, near the optical axis.
  const double z_table = table.offset / table.n.z();
  const double pixel_area = (z_table / in.fx) * (z_table / in.fy);
  const std::vector<int> keep = kept_components(comp, pixel_area, P);
  if (keep.empty()) return fail(SegmentStatus::NoPart, no_part_text(comp, pixel_area, P));

  PartPixels pts;
  std::vector<std::uint8_t> relabel;
  out.num_parts = gather_parts(depth, ray, cc, comp, keep, out.labels, pts, relabel);
  TopPlanes top;
  if (!fit_top_planes(pts, out.num_parts, relabel[keep[0]] - 1, table.n, z_table, P.top_tolerance, top))
    return fail(SegmentStatus::BadFrame, "the part has too few valid depth pixels to fit its plane");
  fit_top_bows(pts, out.num_parts, top);
  project_onto_top(depth, pts, top, table, in, P, glint, out);
  if (out.u.empty()) return fail(SegmentStatus::BadFrame, "the part mask holds no pixel on the fitted top plane");
  fill_gaps_and_assess_edge(depth, intensity, in, {table.n, table.offset, top.normal, top.offset}, P, out);
  out.status = SegmentStatus::Ok;
  return out;
}

}  // namespace hg::camera_bridge
