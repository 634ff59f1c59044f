#include "camera_bridge/segment.hpp"

#include <algorithm>
#include <cstdio>
#include <limits>
#include <cmath>
#include <random>
#include <stdexcept>

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

std::string frame_defect(const cv::Mat& depth, const Intrinsics& in) {
  if (in.width <= 0 || in.height <= 0 || !(in.fx > 0) || !(in.fy > 0) || !(in.depth_unit > 0) ||
      !std::isfinite(in.cx) || !std::isfinite(in.cy))
    return "bad intrinsics (" + std::to_string(in.width) + "x" + std::to_string(in.height) + ", fx " +
           std::to_string(in.fx) + ", fy " + std::to_string(in.fy) + ", depth unit " + std::to_string(in.depth_unit) + ")";
  if (depth.empty()) return "empty depth image";
  if (depth.type() != CV_16UC1) return "depth image is not 16-bit single-channel (OpenCV type " + std::to_string(depth.type()) + ")";
  if (depth.cols != in.width || depth.rows != in.height)
    return "depth image is " + std::to_string(depth.cols) + "x" + std::to_string(depth.rows) + " but the intrinsics say " +
           std::to_string(in.width) + "x" + std::to_string(in.height);
  if (cv::countNonZero(depth) == 0) return "no valid pixel (all zero)";
  return {};
}

Segmentation segment(const cv::Mat& depth, const Intrinsics& in, const SegmentParams& P) {
  check(P);
  Segmentation out;
  if (std::string why = frame_defect(depth, in); !why.empty()) {
    out.text = why;
    return out;
  }
  const int W = depth.cols, H = depth.rows;
  const double unit = in.depth_unit;
  std::vector<double> ray_a(W), ray_b(H);  // pixel ray direction ((c - cx) / fx, (r - cy) / fy, 1)
  for (int c = 0; c < W; ++c) ray_a[c] = (c - in.cx) / in.fx;
  for (int r = 0; r < H; ++r) ray_b[r] = (r - in.cy) / in.fy;

  // ---- table plane ----
  std::vector<Eigen::Vector3d> samples;
  samples.reserve(static_cast<std::size_t>(W / P.sample_stride + 1) * (H / P.sample_stride + 1));
  for (int r = P.sample_stride / 2; r < H; r += P.sample_stride) {
    const std::uint16_t* dr = depth.ptr<std::uint16_t>(r);
    for (int c = P.sample_stride / 2; c < W; c += P.sample_stride)
      if (dr[c]) samples.emplace_back(ray_a[c] * dr[c] * unit, ray_b[r] * dr[c] * unit, dr[c] * unit);
  }
  if (samples.size() < 50) {
    out.text = "too few valid depth pixels (" + std::to_string(samples.size()) + " of the sampled grid) to find the table";
    return out;
  }
  Eigen::Vector3d n = P.plane_normal.normalized();
  double offset = P.plane_offset;
  if (!P.calibrated_plane) {
    // RANSAC, deterministic: hypotheses scored on a fixed subset of about 2000 samples.
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
      for (std::size_t i = 0; i < samples.size(); i += eval_step) score += std::abs(h.dot(samples[i]) - o) < P.ransac_threshold;
      if (score > best) {
        best = score;
        n = h;
        offset = o;
      }
    }
    if (best == 0) {
      out.text = "no table plane found (RANSAC found no plane facing the camera)";
      return out;
    }
  }
  // Least-squares refinement on the inliers (twice: the second pass uses the better plane's inliers).
  std::size_t inliers = 0;
  for (int pass = 0; pass < 2; ++pass) {
    PlaneSums sums;
    sums.ref = samples[samples.size() / 2];
    for (const auto& p : samples)
      if (std::abs(n.dot(p) - offset) < P.ransac_threshold) sums.add(p);
    inliers = static_cast<std::size_t>(sums.n);
    if (inliers < 3) break;
    const Eigen::Vector3d c = sums.centroid();
    n = smallest_eigenvector(sums.scatter());
    orient(n, c);
    offset = n.dot(c);
    out.table_rms = std::sqrt(std::max(0.0, n.dot(sums.scatter() * n) / sums.n));
  }
  const double table_fraction = static_cast<double>(inliers) / samples.size();
  if (table_fraction < P.min_table_fraction) {
    out.text = fmt("no table plane: only %.1f %% of the valid pixels lie on the best plane (need %.1f %%)",
                   100 * table_fraction, 100 * P.min_table_fraction);
    return out;
  }
  out.table_normal = n;
  out.table_offset = offset;

  // ---- part mask: height above the table within the thickness band ----
  // Float and branch-free so the compiler vectorises it: the height is n . (z ray) - offset, with z in
  // depth counts folded into the per-column factor (float keeps ~0.1 um at 2 m, far below the noise).
  // Scratch images kept per thread: allocating ~6 MB afresh each frame costs page faults every time.
  thread_local cv::Mat mask, nodata, cc;
  mask.create(H, W, CV_8UC1);
  nodata.create(H, W, CV_8UC1);
  std::vector<float> na(W);
  for (int c = 0; c < W; ++c) na[c] = static_cast<float>(n.x() * ray_a[c] * unit);
  const float lo = static_cast<float>(P.min_height + offset), hi = static_cast<float>(P.max_height + offset);
  for (int r = 0; r < H; ++r) {
    const std::uint16_t* dr = depth.ptr<std::uint16_t>(r);
    std::uint8_t* mr = mask.ptr<std::uint8_t>(r);
    std::uint8_t* zr = nodata.ptr<std::uint8_t>(r);
    const float nb = static_cast<float>((n.y() * ray_b[r] + n.z()) * unit);
    for (int c = 0; c < W; ++c) {
      const float d = static_cast<float>(dr[c]);
      const float h = d * (na[c] + nb);  // n . p, compared with offset + band
      mr[c] = static_cast<std::uint8_t>(-static_cast<int>((d > 0.0f) & (h >= lo) & (h <= hi)));
      zr[c] = static_cast<std::uint8_t>(-static_cast<int>(d == 0.0f));
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
  // Plain labelling plus our own area and row-range pass: connectedComponentsWithStats computes its
  // statistics several times slower than this.
  const int ncc = cv::connectedComponents(mask, cc, 8, CV_32S);
  std::vector<int> area(ncc, 0), first_row(ncc, H), last_row(ncc, -1);
  for (int r = 0; r < H; ++r) {
    const int* cr = cc.ptr<int>(r);
    for (int c = 0; c < W; ++c)
      if (const int l = cr[c]) {
        ++area[l];
        first_row[l] = std::min(first_row[l], r);
        last_row[l] = r;
      }
  }
  // A pixel's footprint on the table, near the optical axis.
  const double z_table = offset / n.z();
  const double pixel_area = (z_table / in.fx) * (z_table / in.fy);
  std::vector<int> keep;  // component ids, largest first
  int largest_px = 0;
  for (int k = 1; k < ncc; ++k) {
    largest_px = std::max(largest_px, area[k]);
    if (area[k] * pixel_area >= P.min_area) keep.push_back(k);
  }
  std::sort(keep.begin(), keep.end(), [&](int a, int b) { return area[a] != area[b] ? area[a] > area[b] : a < b; });
  if (keep.empty()) {
    out.status = SegmentStatus::NoPart;
    out.text = ncc <= 1 ? std::string("nothing on the table")
                        : fmt("nothing on the table larger than %.4f m^2 (largest blob %.4f m^2)", P.min_area,
                              largest_px * pixel_area);
    return out;
  }
  if (!P.all_parts) keep.resize(1);
  if (keep.size() > 254) keep.resize(254);
  // Labels 1..K in scan order of each kept component's first pixel; the part pixels with a depth are
  // gathered (camera-frame points, scan order) in the same pass, so later passes touch only them.
  std::vector<std::uint8_t> relabel(ncc, 0);
  for (int k : keep) relabel[k] = 255;  // kept, number not given yet
  out.labels.create(H, W, CV_8UC1);
  std::vector<float> px, py, pz;
  std::vector<std::uint8_t> plab;
  std::vector<std::int32_t> pidx;
  std::size_t expect = 0;
  for (int k : keep) expect += area[k];
  px.reserve(expect), py.reserve(expect), pz.reserve(expect), plab.reserve(expect), pidx.reserve(expect);
  // Only the rows of the kept components can hold a label.
  int by0 = H, by1 = 0;
  for (int k : keep) by0 = std::min(by0, first_row[k]), by1 = std::max(by1, last_row[k] + 1);
  const int bx0 = 0, bx1 = W;
  out.labels.setTo(0);
  int next = 0;
  for (int r = by0; r < by1; ++r) {
    const int* cr = cc.ptr<int>(r);
    const std::uint16_t* dr = depth.ptr<std::uint16_t>(r);
    std::uint8_t* lr = out.labels.ptr<std::uint8_t>(r);
    for (int c = bx0; c < bx1; ++c) {
      std::uint8_t& l = relabel[cr[c]];
      if (l == 255) l = static_cast<std::uint8_t>(++next);
      lr[c] = l;
      if (l && dr[c]) {
        const double z = dr[c] * unit;
        px.push_back(static_cast<float>(ray_a[c] * z));
        py.push_back(static_cast<float>(ray_b[r] * z));
        pz.push_back(static_cast<float>(z));
        plab.push_back(static_cast<std::uint8_t>(l - 1));
        pidx.push_back(r * W + c);
      }
    }
  }
  const int K = next;
  out.num_parts = K;
  const int largest = relabel[keep[0]] - 1;
  const std::size_t npts = px.size();

  // ---- plate top plane: one normal for all parts (they lie flat on the same table), one offset each ----
  // Fitted on the part pixels, then refitted twice without the pixels far from it (mixed edge pixels,
  // side walls), whose residuals are one-sided and would tilt the plane. Points as float (0.1 um at 2 m,
  // far below the noise); sums in double about a reference point near the table.
  std::vector<PlaneSums> part_sums(K);
  const Eigen::Vector3d ref(0, 0, z_table);
  Eigen::Vector3d pn = n;  // plate normal, start from the table's
  std::vector<double> poff(K, 0);
  double tol = std::numeric_limits<double>::infinity();
  std::vector<double> residual_sample;
  auto point = [&](std::size_t i) { return Eigen::Vector3d(px[i], py[i], pz[i]); };
  for (int pass = 0; pass < 3; ++pass) {
    for (auto& ps : part_sums) ps = PlaneSums{ref};
    for (std::size_t i = 0; i < npts; ++i) {
      const Eigen::Vector3d p = point(i);
      if (pass > 0 && !(std::abs(pn.dot(p) - poff[plab[i]]) <= tol)) continue;
      part_sums[plab[i]].add(p);
    }
    Eigen::Matrix3d scatter = Eigen::Matrix3d::Zero();
    for (const auto& ps : part_sums)
      if (ps.n >= 1) scatter += ps.scatter();
    const auto& big = part_sums[largest];
    if (!(big.n >= 3)) {
      out.status = SegmentStatus::BadFrame;
      out.text = "the part has too few valid depth pixels to fit its plane";
      return out;
    }
    pn = smallest_eigenvector(scatter);
    orient(pn, big.centroid());
    for (int k = 0; k < K; ++k) poff[k] = part_sums[k].n >= 1 ? pn.dot(part_sums[k].centroid()) : 0;
    // Robust residual scale (median absolute residual of every 3rd point) for the next pass's cut.
    residual_sample.clear();
    for (std::size_t i = 0; i < npts; i += 3) residual_sample.push_back(std::abs(pn.dot(point(i)) - poff[plab[i]]));
    auto mid = residual_sample.begin() + residual_sample.size() / 2;
    std::nth_element(residual_sample.begin(), mid, residual_sample.end());
    const double sigma = residual_sample.empty() ? 0.0 : 1.4826 * *mid;
    tol = P.top_tolerance > 0 ? P.top_tolerance : std::max(4 * sigma, 0.001);
  }
  out.normal = pn;
  out.origin = part_sums[largest].centroid();  // on the largest part's top plane (its centroid lies on it)
  out.thickness = n.dot(out.origin) - offset;
  Eigen::Vector3d ux = Eigen::Vector3d::UnitX() - pn.x() * pn;
  if (ux.norm() < 1e-6) ux = Eigen::Vector3d::UnitY() - pn.y() * pn;  // plane perpendicular to camera x
  out.u_axis = ux.normalized();
  out.v_axis = pn.cross(out.u_axis);

  // ---- points, scan-line order (the gathered order) ----
  out.u.reserve(npts);
  out.v.reserve(npts);
  out.part.reserve(npts);
  out.pixel.reserve(npts);
  for (std::size_t i = 0; i < npts; ++i) {
    const Eigen::Vector3d p = point(i);
    if (!(std::abs(pn.dot(p) - poff[plab[i]]) <= tol)) continue;
    const Eigen::Vector3d q = p - out.origin;  // orthogonal projection onto the plane = in-plane coordinates
    out.u.push_back(static_cast<float>(q.dot(out.u_axis)));
    out.v.push_back(static_cast<float>(q.dot(out.v_axis)));
    out.part.push_back(static_cast<std::int16_t>(plab[i]));
    out.pixel.push_back(pidx[i]);
  }
  if (out.u.empty()) {
    out.status = SegmentStatus::BadFrame;
    out.text = "the part mask holds no pixel on the fitted top plane";
    return out;
  }
  out.status = SegmentStatus::Ok;
  return out;
}

}  // namespace hg::camera_bridge
