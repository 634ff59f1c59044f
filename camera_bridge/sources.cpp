#include "camera_bridge/sources.hpp"

#include <algorithm>
#include <cmath>
#include <filesystem>
#include <thread>

#include <opencv2/core/persistence.hpp>
#include <opencv2/imgcodecs.hpp>

#include "camera_bridge/source_registry.hpp"
#include "camera_types/pacing.hpp"
#include "runtime/log.hpp"
#include "runtime/node.hpp"
#include "sim/scene/scene.hpp"

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

// ---- the built-in sources' registrations ----

namespace {

std::string joined(const std::vector<std::string>& v) {
  std::string s;
  for (const auto& x : v) s += (s.empty() ? "" : "|") + x;
  return s;
}

std::unique_ptr<camera::DepthSource> make_synthetic(const SourceContext& c) {
  sim::SceneSpec spec = sim::scene_preset(c.text("scene"));
  sim::CameraProfile prof = sim::camera_profile(c.text("profile"));
  const double k = c.number("noise-scale");
  prof.noise_a *= k;
  prof.noise_b *= k;
  prof.dropout = std::min(1.0, prof.dropout * k);
  prof.flying_pixel_prob = std::min(1.0, prof.flying_pixel_prob * k);
  if (c.given("seed")) spec.seed = static_cast<std::uint64_t>(c.integer("seed"));
  if (const std::string truth = c.text("write-truth"); !truth.empty()) {
    sim::write_truth(spec, prof, sim::render(spec, prof, 0), 0, truth);
    runtime::logf(runtime::Level::Info, "wrote the ground truth of scene '%s' to %s", spec.name.c_str(), truth.c_str());
  }
  // In job mode frames are rendered when asked for; otherwise at the processing rate.
  return std::make_unique<sim::SyntheticSource>(std::move(spec), prof, c.rate);
}

std::unique_ptr<camera::DepthSource> make_files(const SourceContext& c) {
  const std::string path = c.text("path");
  if (path.empty()) throw c.error("path", "--source files needs --files.path DIR|FILE");
  return std::make_unique<FilesSource>(path, c.text("intrinsics"), c.rate, c.flag("loop"));
}

}  // namespace

SourceEntry synthetic_source() {
  return {"synthetic",
          "the scene renderer (sim/scene): a preset scene seen by a camera profile, with its sensor effects",
          {{"scene", "three-parts", "scene preset (" + joined(sim::scene_preset_names()) + ")"},
           {"profile", "pm806", "camera profile (" + joined(sim::camera_profile_names()) + ")"},
           {"seed", "", "noise seed (default: the scene's)", false, runtime::ParamType::Integer},
           {"noise-scale", "1", "multiplies the profile's depth noise, dropout and mixed-pixel rate (0: clean)", false,
            runtime::ParamType::Number, 0},
           {"write-truth", "", "write the scene's ground truth JSON to this file at start"}},
          make_synthetic,
          ""};
}

SourceEntry files_source() {
  return {"files",
          std::string("a directory of 16-bit depth PNGs + an intrinsics YAML") +
              (can_read_clouds() ? ", or one .pcd/.ply cloud" : " (.pcd/.ply not in this build)"),
          {{"path", "", "directory of 16-bit depth PNGs, or one .png/.pcd/.ply file"},
           {"intrinsics", "",
            "intrinsics YAML (width height fx fy cx cy depth_unit); default intrinsics.yaml beside the files"},
           {"loop", "", "start again after the last frame", true}},
          make_files,
          ""};
}

}  // namespace hg::camera_bridge
