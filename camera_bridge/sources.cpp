#include "camera_bridge/sources.hpp"

#include <algorithm>
#include <cmath>
#include <filesystem>
#include <thread>

#include <opencv2/core/persistence.hpp>
#include <opencv2/imgcodecs.hpp>

#include "camera_types/pacing.hpp"
#include "runtime/log.hpp"
#include "runtime/node.hpp"

#if HG_HAVE_OUTLINE_IO
#include "outline_io/cloud.hpp"
#endif

namespace hg::camera_bridge {

namespace fs = std::filesystem;

namespace {

std::string lower_ext(const fs::path& p) {
  std::string e = p.extension().string();
  for (char& c : e) c = static_cast<char>(std::tolower(static_cast<unsigned char>(c)));
  return e;
}

}  // namespace

// ---- intrinsics files ----

camera::Intrinsics read_intrinsics(const std::string& path) {
  std::error_code ec;
  if (!fs::is_regular_file(path, ec))
    throw camera::SourceError("cannot open intrinsics file '" + path + "': no such file");
  cv::FileStorage fsr;
  try {
    if (!fsr.open(path, cv::FileStorage::READ)) throw camera::SourceError("cannot open intrinsics file '" + path + "'");
  } catch (const cv::Exception& e) {
    throw camera::SourceError("intrinsics file '" + path + "' is not valid YAML/JSON/XML: " + e.what());
  }
  camera::Intrinsics in;
  auto num = [&](const char* key, bool required, double fallback) {
    const cv::FileNode n = fsr[key];
    if (n.empty()) {
      if (required) throw camera::SourceError("intrinsics file '" + path + "': key '" + key + "' missing");
      return fallback;
    }
    if (!n.isReal() && !n.isInt())
      throw camera::SourceError("intrinsics file '" + path + "': key '" + key + "' is not a number");
    return static_cast<double>(n);
  };
  const double w = num("width", true, 0), h = num("height", true, 0);
  in.fx = num("fx", true, 0);
  in.fy = num("fy", true, 0);
  in.cx = num("cx", true, 0);
  in.cy = num("cy", true, 0);
  in.depth_unit = num("depth_unit", false, 0.001);
  if (!(w >= 1 && w <= 65535 && h >= 1 && h <= 65535 && w == std::floor(w) && h == std::floor(h)))
    throw camera::SourceError("intrinsics file '" + path + "': width/height must be whole numbers in 1..65535");
  if (!(in.fx > 0 && in.fy > 0 && in.depth_unit > 0 && std::isfinite(in.cx) && std::isfinite(in.cy)))
    throw camera::SourceError("intrinsics file '" + path + "': fx, fy and depth_unit must be positive");
  in.width = static_cast<int>(w);
  in.height = static_cast<int>(h);
  return in;
}

void write_intrinsics(const camera::Intrinsics& in, const std::string& path) {
  cv::FileStorage fsw(path, cv::FileStorage::WRITE);
  if (!fsw.isOpened()) throw std::runtime_error("cannot write intrinsics file '" + path + "'");
  fsw << "width" << in.width << "height" << in.height << "fx" << in.fx << "fy" << in.fy << "cx" << in.cx << "cy"
      << in.cy << "depth_unit" << in.depth_unit;
}

// ---- clouds ----

cv::Mat cloud_to_depth(const std::vector<double>& xyz, const camera::Intrinsics& in) {
  cv::Mat depth = cv::Mat::zeros(in.height, in.width, CV_16UC1);
  for (std::size_t i = 0; i + 2 < xyz.size(); i += 3) {
    const double x = xyz[i], y = xyz[i + 1], z = xyz[i + 2];
    if (!(z > 0) || !std::isfinite(x) || !std::isfinite(y)) continue;
    const double u = std::round(in.fx * x / z + in.cx), v = std::round(in.fy * y / z + in.cy);
    if (!(u >= 0 && u < in.width && v >= 0 && v < in.height)) continue;
    const double counts = std::round(z / in.depth_unit);
    if (!(counts >= 1 && counts <= 65535)) continue;
    auto& d = depth.at<std::uint16_t>(static_cast<int>(v), static_cast<int>(u));
    if (d == 0 || counts < d) d = static_cast<std::uint16_t>(counts);  // nearest point wins
  }
  return depth;
}

bool can_read_clouds() { return HG_HAVE_OUTLINE_IO != 0; }

// ---- files ----

FilesSource::FilesSource(std::string path, std::string intrinsics_path, double rate, bool loop)
    : path_(std::move(path)),
      intrinsics_path_(std::move(intrinsics_path)),
      loop_(loop),
      period_(camera::period_of(rate)) {}

std::string FilesSource::describe() const { return "files '" + path_ + "'"; }

void FilesSource::open() {
  if (intrinsics_path_.empty()) {
    // Default: intrinsics.yaml beside the images.
    const fs::path p(path_);
    intrinsics_path_ = ((fs::is_directory(p) ? p : p.parent_path()) / "intrinsics.yaml").string();
  }
  intrinsics_ = read_intrinsics(intrinsics_path_);
  files_.clear();
  std::error_code ec;
  if (fs::is_directory(path_, ec)) {
    for (const auto& e : fs::directory_iterator(path_, ec))
      if (e.is_regular_file() && lower_ext(e.path()) == ".png") files_.push_back(e.path().string());
    std::sort(files_.begin(), files_.end());
    if (files_.empty()) throw camera::SourceError("no .png files in '" + path_ + "'");
  } else if (fs::is_regular_file(path_, ec)) {
    const std::string ext = lower_ext(path_);
    if (ext == ".pcd" || ext == ".ply") {
      if (!can_read_clouds())
        throw camera::SourceError("'" + path_ + "': this build has no .pcd/.ply reader (outline I/O library missing)");
    } else if (ext != ".png") {
      throw camera::SourceError("'" + path_ + "': expected a directory of .png files, a .png, .pcd or .ply file");
    }
    files_.push_back(path_);
  } else {
    throw camera::SourceError("no such file or directory '" + path_ + "'");
  }
  next_file_ = 0;
  open_ = true;
}

std::optional<camera::DepthFrame> FilesSource::grab(std::chrono::milliseconds timeout) {
  if (!open_) throw camera::SourceError("files source is not open");
  if (next_file_ >= files_.size()) {
    if (!loop_) {
      std::this_thread::sleep_for(std::min(timeout, std::chrono::milliseconds(100)));
      return std::nullopt;
    }
    next_file_ = 0;
  }
  if (!camera::wait_slot(next_, period_, timeout)) return std::nullopt;
  const std::string& file = files_[next_file_++];
  camera::DepthFrame f;
  f.seq = seq_++;
  f.utime = runtime::now_utime();
  f.intrinsics = intrinsics_;
  const std::string ext = lower_ext(file);
  if (ext == ".png") {
    // Whatever is wrong (missing, not a PNG, 8-bit, colour) leaves depth empty or of the wrong type, and
    // the bridge's frame check names the problem; the file name is logged here.
    try {
      f.depth = cv::imread(file, cv::IMREAD_UNCHANGED);
    } catch (const cv::Exception& e) {
      f.depth.release();
    }
    if (f.depth.empty() || f.depth.type() != CV_16UC1)
      runtime::logf(runtime::Level::Warn, "files source: '%s' is not a 16-bit single-channel PNG", file.c_str());
  } else {
#if HG_HAVE_OUTLINE_IO
    try {
      f.depth = cloud_to_depth(outline_io::read_cloud_file(file).xyz, intrinsics_);
    } catch (const std::exception& e) {
      runtime::logf(runtime::Level::Warn, "files source: %s", e.what());
      f.depth.release();
    }
#endif
  }
  return f;
}

}  // namespace hg::camera_bridge
