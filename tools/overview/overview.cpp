#include "tools/overview/overview.hpp"

#include "jobs/job_ledger.hpp"

#include <algorithm>
#include <cmath>
#include <cstring>
#include <limits>

#include <opencv2/imgcodecs.hpp>
#include <opencv2/imgproc.hpp>

#include "outline_io/outline_message.hpp"
#include "outline_io/outline_writers.hpp"
#include "outline_io/palette.hpp"
#include "path_planner/io.hpp"

namespace hg::overview {
namespace {

using Json = nlohmann::ordered_json;
using namespace outline_io::palette;

cv::Scalar bgr(std::uint32_t rgb) { return cv::Scalar(rgb & 0xff, (rgb >> 8) & 0xff, (rgb >> 16) & 0xff); }

std::string state_name(int s) { return jobs::job_state_name(std::int8_t(s)); }

// "hole 2: 285.7 mm TOO_SMALL; outer loop 0: 3.1 mm UNREACHED": the stretches a job's end left unground.
std::string unground_text(const hullgrind::job_status_t& s) {
  static const char* causes[] = {"UNREACHED", "TOO_SMALL", "CORNER", "EXCLUDED", "NOT_RUN"};
  std::string out;
  for (const auto& u : s.unground) {
    char buf[96];
    std::snprintf(buf, sizeof buf, "%s %d: %.1f mm %s", u.hole ? "hole" : "outer loop", int(u.loop_index),
                  u.length * 1e3, u.cause >= 0 && u.cause < 5 ? causes[u.cause] : "?");
    out += (out.empty() ? "" : "; ") + std::string(buf);
  }
  return out;
}

double ms(std::int64_t a, std::int64_t b) { return double(b - a) * 1e-3; }

}  // namespace

Json outline_json(const JobTrace& job) {
  return outline_io::outline_message_json(job.outline->msg, job.cloud ? &job.cloud->msg : nullptr);
}

Json summary_json(const JobTrace& job) {
  Json j;
  j["job_id"] = job.job_id;
  j["final_state"] = job.final_status ? state_name(job.final_status->msg.state) : "none";
  if (job.final_status) {
    j["final_source"] = job.final_status->msg.source;
    j["final_message"] = job.final_status->msg.message;
    if (job.final_status->msg.answer) j["final_answer"] = true;  // the end is an answer (e.g. the job history's)
    Json unground = Json::array();
    for (const auto& u : job.final_status->msg.unground)
      unground.push_back({{"loop", u.loop_index},
                          {"hole", u.hole},
                          {"start", u.start},
                          {"length", u.length},
                          {"cause", int(u.cause)},
                          {"reason", u.reason}});
    j["unground"] = std::move(unground);
  }
  Json stages = Json::object();
  if (job.cloud) stages["capture_to_cloud_ms"] = ms(job.cloud->msg.header.utime, job.cloud->log_utime);
  if (job.cloud && job.outline) stages["cloud_to_outline_ms"] = ms(job.cloud->log_utime, job.outline->log_utime);
  if (job.outline) stages["outline_compute_ms"] = job.outline->msg.compute_time * 1e3;
  if (job.outline && job.path && job.request)
    stages["plan_ms"] = ms(std::max(job.outline->log_utime, job.request->log_utime), job.path->log_utime);
  // plan_ms is a latency through the bus (the request's and the path's delivery); this is the planner's own part.
  if (job.path) stages["plan_compute_ms"] = job.path->msg.compute_time * 1e3;
  if (job.path && job.final_status) stages["robot_run_ms"] = ms(job.path->log_utime, job.final_status->log_utime);
  if (job.request && job.final_status)
    stages["request_to_end_ms"] = ms(job.request->log_utime, job.final_status->log_utime);
  j["stages"] = std::move(stages);
  if (job.cloud) j["cloud_points"] = job.cloud->msg.n;
  if (job.outline) {
    int holes = 0;
    for (const auto& l : job.outline->msg.loops) holes += l.hole;
    j["outline_loops"] = job.outline->msg.num_loops;
    j["outline_holes"] = holes;
  }
  if (job.path) j["path_waypoints"] = job.path->msg.n;
  Json states = Json::array();
  for (const auto& s : job.statuses)
    states.push_back({{"t_ms", job.request ? ms(job.request->log_utime, s.log_utime) : 0.0},
                      {"source", s.msg.source},
                      {"state", state_name(s.msg.state)},
                      {"progress", s.msg.progress},
                      {"message", s.msg.message}});
  j["statuses"] = std::move(states);
  return j;
}

double PlatePath::grind_height_median() const {
  std::vector<double> h;
  for (std::size_t i = 0; i < height.size(); ++i)
    if (kind[i] == hullgrind::grind_path_t::KIND_GRIND) h.push_back(std::abs(height[i]));
  if (h.empty()) return 0;
  std::nth_element(h.begin(), h.begin() + long(h.size() / 2), h.end());
  return h[h.size() / 2];
}

PlatePath path_on_plate(const JobTrace& job, const Eigen::Isometry3d& camera_to_base) {
  PlatePath out;
  if (!job.path || !job.outline) return out;
  const auto& o = job.outline->msg;
  const Eigen::Vector3d origin(o.plane_origin), u(o.plane_u_axis), v(o.plane_v_axis), n(o.plane_normal);
  const Eigen::Isometry3d base_to_camera = camera_to_base.inverse();
  for (int i = 0; i < job.path->msg.n; ++i) {
    const Eigen::Vector3d p = base_to_camera * Eigen::Vector3d(job.path->msg.position[std::size_t(i)].data()) - origin;
    out.uv.emplace_back(p.dot(u), p.dot(v));
    out.height.push_back(p.dot(n));
    out.kind.push_back(job.path->msg.kind[std::size_t(i)]);
  }
  return out;
}

double scale_bar_mm(double span) {
  const double limit = span * 1e3 / 4;
  double best = 1;
  for (double decade = 1e-3; decade <= 1e6; decade *= 10)
    for (double m : {1.0, 2.0, 5.0})
      if (m * decade <= limit) best = m * decade;
  return best;
}

namespace {

// Picture transform: plate (u, v) in metres -> pixel, y up, fitted to the content.
struct Canvas {
  Eigen::Vector2d lo, hi;
  double scale = 1;
  int width = 1400, height = 0;
  static constexpr int margin = 40, legend = 252;  // the scale bar and up to 9 caption lines
  explicit Canvas(const std::vector<Eigen::Vector2d>& pts) {
    lo = Eigen::Vector2d::Constant(std::numeric_limits<double>::max());
    hi = -lo;
    for (const auto& p : pts) lo = lo.cwiseMin(p), hi = hi.cwiseMax(p);
    if (lo.x() > hi.x()) lo = {0, 0}, hi = {1, 1};
    scale = (width - 2 * margin) / std::max(hi.x() - lo.x(), 1e-9);
    height = int((hi.y() - lo.y()) * scale) + 2 * margin + legend;
    if (height > 2400) {  // very tall parts: fit the height instead
      scale = (2400 - 2 * margin - legend) / std::max(hi.y() - lo.y(), 1e-9);
      height = 2400;
    }
  }
  cv::Point px(const Eigen::Vector2d& p) const {
    return cv::Point(int(std::lround(margin + (p.x() - lo.x()) * scale)),
                     int(std::lround(height - legend - margin - (p.y() - lo.y()) * scale)));
  }
};

void draw_scale_bar(cv::Mat& img, const Canvas& c) {
  const double mm = scale_bar_mm((img.cols - 2 * Canvas::margin) / c.scale);
  const int len = int(std::lround(mm * 1e-3 * c.scale));
  const cv::Point a(img.cols - Canvas::margin - len, c.height - Canvas::legend + 8), b(a.x + len, a.y);
  cv::line(img, a, b, bgr(kText), 3);
  for (const cv::Point& e : {a, b}) cv::line(img, e - cv::Point(0, 6), e + cv::Point(0, 6), bgr(kText), 2);
  char text[32];
  std::snprintf(text, sizeof text, "%g mm", mm);
  cv::putText(img, text, cv::Point(a.x, a.y + 24), cv::FONT_HERSHEY_SIMPLEX, 0.55, bgr(kText), 1, cv::LINE_AA);
}

// Edge the tool does not reach, over everything else: the base-frame points back onto the plate as the
// path. Returns the length drawn, mm.
double draw_unreached(cv::Mat& img, const Canvas& c, const JobTrace& job, const Eigen::Isometry3d& camera_to_base,
                      const hg::path_planner::PlannerConfig& planner) {
  if (!job.outline) return 0;
  const auto& o = job.outline->msg;
  const Eigen::Vector3d origin(o.plane_origin), u(o.plane_u_axis), v(o.plane_v_axis);
  const Eigen::Isometry3d base_to_camera = camera_to_base.inverse();
  double mm = 0;
  for (const auto& stretch : unreached_stretches(job, planner)) {
    std::vector<cv::Point> pts;
    for (const Eigen::Vector3d& b : stretch) {
      const Eigen::Vector3d p = base_to_camera * b;
      pts.push_back(c.px({(p - origin).dot(u), (p - origin).dot(v)}));
    }
    for (std::size_t i = 1; i < stretch.size(); ++i) mm += (stretch[i] - stretch[i - 1]).norm() * 1e3;
    if (pts.size() == 1) cv::circle(img, pts[0], 3, bgr(kUnreached), -1, cv::LINE_AA);
    cv::polylines(img, pts, false, bgr(kUnreached), 4, cv::LINE_AA);
  }
  return mm;
}

std::vector<std::string> caption(const JobTrace& job, const PlatePath& path, std::size_t cloud_points, int outers,
                                 int holes, const std::string& base_frame, bool coverage, double unreached_mm) {
  const Json s = summary_json(job);
  std::vector<std::string> lines;
  std::string outcome =
      "job " + job.job_id + ": " + s["final_state"].get<std::string>() +
      (job.final_status && !job.final_status->msg.message.empty() ? " (" + job.final_status->msg.message + ")" : "");
  if (outcome.size() > 125) outcome = outcome.substr(0, 122) + "...";
  lines.push_back(outcome);
  if (job.final_status && !job.final_status->msg.unground.empty()) {
    std::string gaps = "NOT GROUND: " + unground_text(job.final_status->msg);
    if (gaps.size() > 125) gaps = gaps.substr(0, 122) + "...";
    lines.push_back(gaps);
  }
  char buf[256];
  std::snprintf(buf, sizeof buf,
                "cloud %zu points; outline %d outer + %d holes (white, light blue), R = %.2f mm; path %zu waypoints",
                cloud_points, outers, holes, job.outline ? job.outline->msg.alpha_radius * 1e3 : 0.0, path.uv.size());
  lines.push_back(buf);
  const std::string camera =
      job.outline && !job.outline->msg.header.frame_id.empty() ? job.outline->msg.header.frame_id : "camera";
  lines.push_back("view: the plate plane (u right, v up) of frame '" + camera + "'; path from frame '" + base_frame +
                  "' through the camera-to-base calibration");
  if (path.grind_height_median() > kOffPlaneWarning) {
    std::snprintf(buf, sizeof buf, "WARNING: the grind path is %.1f mm off the plate: not the planner's calibration",
                  path.grind_height_median() * 1e3);
    lines.push_back(buf);
  }
  lines.push_back(
      "path (the tool's centre): grind (orange), lead-in (green), lead-out (teal), approach (slate), retract "
      "(purple), travel (grey); circle: start");
  if (coverage) {
    if (unreached_mm > 0)
      std::snprintf(buf, sizeof buf, "edge out of the tool's reach (red, the planner's coverage check): about %.1f mm",
                    unreached_mm);
    else
      std::snprintf(buf, sizeof buf, "edge out of the tool's reach (red, the planner's coverage check): none");
    lines.push_back(buf);
  }
  // The stages wrap at the caption's width (125 characters, as the lines above are cut): all of them are read.
  std::string t = "stages:";
  for (auto& [k, v] : s["stages"].items()) {
    std::snprintf(buf, sizeof buf, " %s %.1f", k.c_str(), v.get<double>());
    if (t.size() + std::strlen(buf) > 125) lines.push_back(t), t = "       ";
    t += buf;
  }
  lines.push_back(t);
  return lines;
}

}  // namespace

std::vector<std::vector<Eigen::Vector3d>> unreached_stretches(const JobTrace& job,
                                                              const hg::path_planner::PlannerConfig& planner) {
  namespace pp = hg::path_planner;
  std::vector<std::vector<Eigen::Vector3d>> out;
  if (!job.path || !job.outline) return out;
  const auto& g = job.path->msg;
  std::vector<pp::Waypoint> path;
  for (std::size_t i = 0; i < g.position.size() && i < g.kind.size(); ++i)
    path.push_back({Eigen::Vector3d(g.position[i].data()), Eigen::Quaterniond::Identity(), 0, g.kind[i], -1});
  const pp::PathCoverage pc =
      pp::path_coverage(pp::from_lcm(job.outline->msg), path, g.tool_radius, g.flipped, planner);
  for (const pp::LoopCoverage& l : pc.loops)
    for (const pp::UnreachedStretch& s : l.unreached) {
      std::vector<Eigen::Vector3d> pts;
      for (const Eigen::Vector2d& p : s.points) pts.push_back(pc.plate_to_base * Eigen::Vector3d(p.x(), p.y(), 0));
      out.push_back(std::move(pts));
    }
  return out;
}

std::vector<unsigned char> overview_png(const JobTrace& job, const Eigen::Isometry3d& camera_to_base,
                                        const hg::path_planner::PlannerConfig* planner) {
  std::vector<Eigen::Vector2d> cloud;
  if (job.cloud)
    for (int i = 0; i < job.cloud->msg.n; ++i)
      cloud.emplace_back(job.cloud->msg.u[std::size_t(i)], job.cloud->msg.v[std::size_t(i)]);
  const PlatePath path = path_on_plate(job, camera_to_base);
  std::vector<Eigen::Vector2d> all = cloud;
  all.insert(all.end(), path.uv.begin(), path.uv.end());
  if (job.outline)
    for (const auto& l : job.outline->msg.loops)
      for (int i = 0; i < l.n; ++i) all.emplace_back(l.u[std::size_t(i)], l.v[std::size_t(i)]);
  const Canvas c(all);
  cv::Mat img(c.height, c.width, CV_8UC3, bgr(kBackground));
  for (const auto& p : cloud) {
    cv::Point q = c.px(p);
    if (q.x >= 0 && q.y >= 0 && q.x < c.width && q.y < c.height)
      img.at<cv::Vec3b>(q) = cv::Vec3b(kCloud & 0xff, (kCloud >> 8) & 0xff, kCloud >> 16);
  }
  int holes = 0, outers = 0;
  if (job.outline)
    for (const auto& l : job.outline->msg.loops) {
      std::vector<cv::Point> pts;
      for (int i = 0; i < l.n; ++i) pts.push_back(c.px({l.u[std::size_t(i)], l.v[std::size_t(i)]}));
      cv::polylines(img, pts, true, bgr(l.hole ? kHole : kOuter), 2, cv::LINE_AA);
      (l.hole ? holes : outers)++;
    }
  for (std::size_t i = 1; i < path.uv.size(); ++i) {
    const int k = path.kind[i];
    cv::line(img, c.px(path.uv[i - 1]), c.px(path.uv[i]), bgr(kind_colour(k)),
             k == hullgrind::grind_path_t::KIND_GRIND ? 2 : 1, cv::LINE_AA);
  }
  if (!path.uv.empty()) cv::circle(img, c.px(path.uv.front()), 7, bgr(kText), 2, cv::LINE_AA);
  const double unreached_mm = planner ? draw_unreached(img, c, job, camera_to_base, *planner) : 0;
  draw_scale_bar(img, c);
  const auto lines = caption(job, path, cloud.size(), outers, holes, planner ? planner->base_frame : "robot_base",
                             planner != nullptr, unreached_mm);
  for (std::size_t i = 0; i < lines.size(); ++i)
    cv::putText(img, lines[i], cv::Point(Canvas::margin, c.height - Canvas::legend + 50 + int(i) * 22),
                cv::FONT_HERSHEY_SIMPLEX, 0.5, bgr(kText), 1, cv::LINE_AA);
  std::vector<unsigned char> png;
  cv::imencode(".png", img, png);
  return png;
}

}  // namespace hg::overview
