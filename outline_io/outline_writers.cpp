#include "outline_io/outline_writers.hpp"

#include "outline_io/outline_file.hpp"
#include "outline_io/palette.hpp"

#include <fcntl.h>
#include <sys/stat.h>
#include <unistd.h>

#include <algorithm>
#include <cerrno>
#include <charconv>
#include <cmath>
#include <cstdio>
#include <cstring>
#include <opencv2/core.hpp>
#include <opencv2/imgproc.hpp>
#include <png.h>

namespace hg::outline_io {

namespace {

nlohmann::ordered_json arr3(const std::array<double, 3>& a) { return {a[0], a[1], a[2]}; }

bool drawable(const Vec2& p) { return std::isfinite(p.x) && std::isfinite(p.y); }

// Page transform: world (x, y) -> picture (px, py), fitted to about 1200 px, y up.
struct View {
  double minx = 0, miny = 0, scale = 1;
  int width = 1200, height = 1200;
  static constexpr double margin = 40, target = 1120;
  explicit View(std::span<const Vec2> pts) {
    const auto first = std::find_if(pts.begin(), pts.end(), drawable);  // skipped (NaN) points are not drawn
    if (first == pts.end()) return;
    double maxx = first->x, maxy = first->y;
    minx = first->x, miny = first->y;
    for (auto& p : pts) {
      if (!drawable(p)) continue;
      minx = std::min(minx, p.x), maxx = std::max(maxx, p.x);
      miny = std::min(miny, p.y), maxy = std::max(maxy, p.y);
    }
    double ext = std::max(maxx - minx, maxy - miny);
    scale = ext > 0 ? target / ext : 1;
    width = static_cast<int>(std::ceil((maxx - minx) * scale + 2 * margin));
    height = static_cast<int>(std::ceil((maxy - miny) * scale + 2 * margin)) + 30;  // legend strip
  }
  double px(const Vec2& p) const { return margin + (p.x - minx) * scale; }
  double py(const Vec2& p) const { return height - margin - (p.y - miny) * scale; }
};

void append_num(std::string& s, double v) {
  char buf[32];
  auto r = std::to_chars(buf, buf + sizeof buf, v, std::chars_format::fixed, 1);
  s.append(buf, r.ptr);
}

// The product's colours (palette.hpp): as SVG text and as OpenCV's BGR.
std::string css(std::uint32_t rgb) {
  char buf[8];
  std::snprintf(buf, sizeof buf, "#%06x", unsigned(rgb));
  return buf;
}
cv::Scalar bgr(std::uint32_t rgb) { return cv::Scalar(rgb & 0xff, (rgb >> 8) & 0xff, (rgb >> 16) & 0xff); }
// Triangles: a line darker than the cloud, so the loops stay on top.
constexpr std::uint32_t kTriangles = 0x2b3a4a;

}  // namespace

namespace {

// The outline file's part of hg-outline's JSON: frame, spacing, plane, the loops' holes and points.
OutlineFile outline_file_of(const Result& r, const PlanarPoints& planar, const RunInfo& info) {
  OutlineFile f;
  f.frame = info.frame;
  f.spacing = r.spacing;
  if (planar.projected) f.plane = planar.plane;
  for (const Loop& l : r.loops) f.loops.push_back({l.hole, l.points});
  return f;
}

nlohmann::ordered_json run_json(const Result& r, const PlanarPoints& planar, const RunInfo& info) {
  nlohmann::ordered_json j;
  j["input"] = {{"file", info.input}, {"format", info.format}, {"has_z", info.has_z}, {"projected", planar.projected}};
  j["points_read"] = r.points_read;
  j["points_skipped"] = r.points_skipped;
  j["points_used"] = r.points_used;
  j["duplicates_merged"] = r.duplicates_merged;
  j["alpha_radius"] = r.alpha_radius;
  j["alpha_automatic"] = r.alpha_automatic;
  j["alpha_mode"] = to_string(r.alpha_mode);
  j["spacing"] = r.spacing;  // also when 0 (the outline file leaves it out then)
  j["nn_spacing_median"] = r.nn_spacing_median;
  j["holes_dropped"] = r.holes_dropped;
  j["mode"] = to_string(r.mode);
  j["order"] = to_string(r.order);
  j["threads"] = r.threads_used;  // strips computed in parallel (1: the one-thread path ran)
  j["triangles"] = r.stats.triangles;
  j["search_cost"] = r.stats.search_cost;
  j["search_cost_locate"] = r.stats.search_cost_locate;
  j["search_cost_cavity"] = r.stats.search_cost_cavity;
  j["incircle_tests"] = r.stats.incircle_tests;
  j["orient_tests"] = r.stats.orient_tests;
  j["time_ms"] = {
      {"read", info.read_ms},     {"project", info.project_ms}, {"triangulate", r.time.triangulate_ms},
      {"alpha", r.time.alpha_ms}, {"loops", r.time.loops_ms},   {"total", info.project_ms + r.time.total_ms}};
  return j;
}

}  // namespace

nlohmann::ordered_json outline_json(const Result& r, const PlanarPoints& planar, const RunInfo& info) {
  nlohmann::ordered_json j = outline_file_json(outline_file_of(r, planar, info));
  j.update(run_json(r, planar, info));
  if (planar.projected) {
    j["plane"]["rms_distance"] = planar.rms_distance;
    j["plane"]["max_distance"] = planar.max_distance;
  }
  for (std::size_t k = 0; k < r.loops.size(); ++k) {
    const Loop& l = r.loops[k];
    nlohmann::ordered_json& jl = j["loops"][k];
    jl["area"] = l.area;
    jl["perimeter"] = l.perimeter;
    if (planar.projected) {
      auto p3 = nlohmann::ordered_json::array();
      for (auto& p : l.points) p3.push_back(arr3(plane_to_3d(planar.plane, p)));
      jl["points_3d"] = std::move(p3);
    }
    jl["point_index"] = l.point_index;
  }
  return j;
}

std::string triangles_text(const Result& r) {
  std::string s;
  s.reserve(r.delaunay_triangles.size() * 24);
  char buf[16];
  for (auto& t : r.delaunay_triangles) {
    for (int k = 0; k < 3; ++k) {
      auto res = std::to_chars(buf, buf + sizeof buf, t[k]);
      s.append(buf, res.ptr);
      s += k < 2 ? ' ' : '\n';
    }
  }
  return s;
}

std::string render_svg(std::span<const Vec2> points, const Result& r, bool draw_triangles) {
  View view(points);
  std::string s;
  s += "<?xml version=\"1.0\" encoding=\"UTF-8\"?>\n";
  s += "<svg xmlns=\"http://www.w3.org/2000/svg\" width=\"" + std::to_string(view.width) + "\" height=\"" +
       std::to_string(view.height) + "\" viewBox=\"0 0 " + std::to_string(view.width) + " " +
       std::to_string(view.height) + "\">\n<rect width=\"100%\" height=\"100%\" fill=\"" + css(palette::kBackground) +
       "\"/>\n";
  if (draw_triangles && !r.delaunay_triangles.empty()) {
    s += "<path fill=\"none\" stroke=\"" + css(kTriangles) + "\" stroke-width=\"0.5\" d=\"";
    for (auto& t : r.delaunay_triangles) {
      for (int k = 0; k < 3; ++k) {
        if (t[k] >= points.size()) continue;
        s += k == 0 ? 'M' : 'L';
        append_num(s, view.px(points[t[k]]));
        s += ' ';
        append_num(s, view.py(points[t[k]]));
      }
      s += 'Z';
    }
    s += "\"/>\n";
  }
  // A picture for a person: beyond 250k dots only every k-th point is drawn (said in the legend).
  const std::size_t step = std::max<std::size_t>(1, (points.size() + 249999) / 250000);
  s += "<path fill=\"none\" stroke=\"" + css(palette::kCloud) + "\" stroke-width=\"2\" stroke-linecap=\"round\" d=\"";
  for (std::size_t i = 0; i < points.size(); i += step) {
    if (!drawable(points[i])) continue;
    s += 'M';
    append_num(s, view.px(points[i]));
    s += ' ';
    append_num(s, view.py(points[i]));
    s += "h0";
  }
  s += "\"/>\n";
  for (const Loop& l : r.loops) {
    s += "<polygon fill=\"none\" stroke=\"";
    s += css(l.hole ? palette::kHole : palette::kOuter);
    s += "\" stroke-width=\"2\" points=\"";
    for (auto& p : l.points) {
      append_num(s, view.px(p));
      s += ',';
      append_num(s, view.py(p));
      s += ' ';
    }
    s += "\"/>\n";
  }
  std::size_t holes = std::count_if(r.loops.begin(), r.loops.end(), [](const Loop& l) { return l.hole; });
  s += "<text x=\"10\" y=\"" + std::to_string(view.height - 10) +
       "\" font-family=\"sans-serif\" font-size=\"14\" fill=\"" + css(palette::kText) + "\">";
  s += std::to_string(points.size()) + " points" +
       (step > 1 ? " (every " + std::to_string(step) + "th drawn)" : std::string()) + ", ";
  s += "<tspan fill=\"" + css(palette::kOuter) + "\">" + std::to_string(r.loops.size() - holes) + " outer</tspan>, ";
  s += "<tspan fill=\"" + css(palette::kHole) + "\">" + std::to_string(holes) + " holes</tspan>, R = ";
  char radius[32];  // in the input's units, as the PNG legend: metres need more than one decimal
  std::snprintf(radius, sizeof radius, "%.4g", r.alpha_radius);
  s += radius;
  s += "</text>\n</svg>\n";
  return s;
}

std::vector<unsigned char> render_png(std::span<const Vec2> points, const Result& r, bool draw_triangles) {
  View view(points);
  cv::Mat img(view.height, view.width, CV_8UC3, bgr(palette::kBackground));
  constexpr int shift = 4;  // sub-pixel coordinates for OpenCV's drawing
  auto pt = [&](const Vec2& p) {
    return cv::Point(static_cast<int>(std::lround(view.px(p) * (1 << shift))),
                     static_cast<int>(std::lround(view.py(p) * (1 << shift))));
  };
  if (draw_triangles) {
    for (auto& t : r.delaunay_triangles) {
      if (t[0] >= points.size() || t[1] >= points.size() || t[2] >= points.size()) continue;
      cv::Point q[3] = {pt(points[t[0]]), pt(points[t[1]]), pt(points[t[2]])};
      const cv::Point* pp = q;
      int n = 3;
      cv::polylines(img, &pp, &n, 1, true, bgr(kTriangles), 1, cv::LINE_8, shift);
    }
  }
  const bool big_dots = points.size() < 20000;
  for (auto& p : points) {
    if (!drawable(p)) continue;
    if (big_dots) {
      cv::circle(img, pt(p), 2 << shift, bgr(palette::kCloud), cv::FILLED, cv::LINE_AA, shift);
    } else {
      int x = static_cast<int>(view.px(p)), y = static_cast<int>(view.py(p));
      const cv::Scalar c = bgr(palette::kCloud);
      if (x >= 0 && y >= 0 && x < img.cols && y < img.rows) img.at<cv::Vec3b>(y, x) = cv::Vec3b(c[0], c[1], c[2]);
    }
  }
  const cv::Scalar outer = bgr(palette::kOuter), hole = bgr(palette::kHole);
  for (const Loop& l : r.loops) {
    std::vector<cv::Point> poly;
    poly.reserve(l.points.size());
    for (auto& p : l.points) poly.push_back(pt(p));
    cv::polylines(img, poly, true, l.hole ? hole : outer, 2, cv::LINE_AA, shift);
  }
  std::size_t holes = std::count_if(r.loops.begin(), r.loops.end(), [](const Loop& l) { return l.hole; });
  char legend[160];
  std::snprintf(legend, sizeof legend, "%zu points, %zu outer (white), %zu holes (light blue), R = %.4g", points.size(),
                r.loops.size() - holes, holes, r.alpha_radius);
  cv::putText(img, legend, cv::Point(10, view.height - 10), cv::FONT_HERSHEY_SIMPLEX, 0.5, bgr(palette::kText), 1,
              cv::LINE_AA);
  // libpng directly, not OpenCV's imgcodecs: linking imgcodecs maps ~140 shared libraries (GDAL, ...) into
  // hg-outline, ~40 MB of its peak memory, for this one call.
  png_image image{};
  image.version = PNG_IMAGE_VERSION;
  image.width = png_uint_32(img.cols);
  image.height = png_uint_32(img.rows);
  image.format = PNG_FORMAT_BGR;
  png_alloc_size_t size = 0;
  const auto stride = png_int_32(img.step[0]);
  if (!png_image_write_to_memory(&image, nullptr, &size, 0, img.data, stride, nullptr))
    throw WriteError(std::string("PNG encoding failed: ") + image.message);
  std::vector<unsigned char> png(size);
  if (!png_image_write_to_memory(&image, png.data(), &size, 0, img.data, stride, nullptr))
    throw WriteError(std::string("PNG encoding failed: ") + image.message);
  png.resize(size);
  return png;
}

StagedFiles::~StagedFiles() {
  for (auto& e : entries_)
    if (!e.temp_path.empty()) ::unlink(e.temp_path.c_str());
}

void StagedFiles::stage(const std::string& path, const void* data, std::size_t size) {
  std::string tmpl = path + ".tmp-XXXXXX";
  int fd = ::mkstemp(tmpl.data());
  if (fd < 0) throw WriteError(path + ": cannot create a file in its folder: " + std::strerror(errno));
  entries_.push_back({path, tmpl});
  const char* p = static_cast<const char*>(data);
  std::size_t left = size;
  while (left > 0) {
    ssize_t w = ::write(fd, p, left);
    if (w < 0 && errno == EINTR) continue;
    if (w <= 0) {
      int err = errno;
      ::close(fd);
      throw WriteError(path + ": write failed: " + std::strerror(err));
    }
    p += w;
    left -= static_cast<std::size_t>(w);
  }
  // mkstemp makes 0600; give the permissions an ordinary new file would get.
  const mode_t mask = ::umask(0);
  ::umask(mask);
  ::fchmod(fd, 0666 & ~mask);
  if (::close(fd) != 0) throw WriteError(path + ": write failed: " + std::strerror(errno));
}

void StagedFiles::commit() {
  for (auto& e : entries_) {
    if (std::rename(e.temp_path.c_str(), e.final_path.c_str()) != 0)
      throw WriteError(e.final_path + ": cannot rename the finished file into place: " + std::strerror(errno));
    e.temp_path.clear();
  }
}

}  // namespace hg::outline_io
