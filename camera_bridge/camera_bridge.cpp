#include "camera_bridge/camera_bridge.hpp"

#include <limits>
#include <algorithm>
#include <cmath>

#include <opencv2/imgcodecs.hpp>

#include "camera_bridge/source_registry.hpp"
#include "camera_bridge/sources.hpp"
#include "hullgrind/depth_frame_t.hpp"
#include "hullgrind/heartbeat_t.hpp"
#include "hullgrind/job_request_t.hpp"
#include "hullgrind/robot_status_t.hpp"
#include "runtime/channels.hpp"

namespace hg::camera_bridge {

using hullgrind::heartbeat_t;
using hullgrind::plate_cloud_t;
using runtime::Level;
using runtime::logf;
using Clock = std::chrono::steady_clock;

// The bridge's parameters: capture, plane finding, part segmentation, monitoring and retry; then --source
// and each registered source's own section (source_registry.hpp).
static std::vector<runtime::Param> bridge_params() {
  std::vector<runtime::Param> params = {
      runtime::text_param("source", "synthetic", "the camera source (--help lists them, docs/cameras.md)",
                          source_names()),
      {"rate", "2", "continuous: frames processed per second at most (<= 0: every frame)", false,
       runtime::ParamType::Number},
      runtime::text_param("trigger", "continuous",
                          "continuous | job (one capture per job id of a job_request_t ACTION_START on HG_JOB_REQUEST)",
                          {"continuous", "job"}),
      runtime::text_param("parts", "largest", "largest | all: publish the largest part or every part (labelled)",
                          {"largest", "all"}),
      runtime::text_param("plane", "ransac", "ransac | calibrated (then --plane-normal and --plane-offset)",
                          {"ransac", "calibrated"}),
      {"plane-normal", "0,0,-1", "calibrated table normal in the camera frame, towards the camera", false,
       runtime::ParamType::Numbers},
      {"plane-offset", "-1.5", "calibrated plane: normal . p = offset (metres, negative)", false,
       runtime::ParamType::Number},
      {"ransac-iterations", "150", "RANSAC hypotheses", false, runtime::ParamType::Integer, 1},
      {"ransac-threshold", "0.004", "table inlier distance, metres", false, runtime::ParamType::Number, 0,
       std::numeric_limits<double>::infinity(), true},
      {"min-height", "0.003", "part pixels: at least this high above the table, metres", false,
       runtime::ParamType::Number},
      {"max-height", "0.040", "part pixels: at most this high above the table, metres", false,
       runtime::ParamType::Number},
      {"open-size", "2", "opening kernel against specks, pixels (0: none; no-depth pixels spared)", false,
       runtime::ParamType::Integer, 0},
      {"close-size", "3", "closing kernel against pin holes, pixels (0: none)", false, runtime::ParamType::Integer, 0},
      {"min-area", "0.002", "smallest part, m^2", false, runtime::ParamType::Number, 0},
      {"top-tolerance", "0", "cloud points: within this of the top plane, metres (0: 4 sigma, >= 1 mm)", false,
       runtime::ParamType::Number, 0},
      {"dropout-width", "0.010",
       "a gap inside a part with no return at table height and at most this wide (metres) is dropout: filled, not a hole",
       false, runtime::ParamType::Number, 0},
      {"keep-dropout", "", "leave dropout inside the parts as gaps in the cloud instead of filling it", true},
      {"depth-rate", "1", "HG_DEPTH messages per second at most (0: none)", false, runtime::ParamType::Number, 0},
      {"depth-decimation", "4", "HG_DEPTH keeps every n-th pixel of every n-th row", false, runtime::ParamType::Integer,
       1},
      {"retry-min", "0.5", "seconds before the first re-open of a failed device", false, runtime::ParamType::Number, 0,
       std::numeric_limits<double>::infinity(), true},
      {"retry-max", "8", "back-off limit, seconds", false, runtime::ParamType::Number, 0,
       std::numeric_limits<double>::infinity(), true},
      {"frame-id", "camera", "header.frame_id of the published messages"},
  };
  for (runtime::Param& p : source_params()) params.push_back(std::move(p));
  // The flat names of the source parameters before they had a section: refused naming the new key.
  for (const auto& [old, now] :
       std::vector<std::pair<std::string, std::string>>{{"scene", "--synthetic.scene"},
                                                        {"profile", "--synthetic.profile"},
                                                        {"seed", "--synthetic.seed"},
                                                        {"noise-scale", "--synthetic.noise-scale"},
                                                        {"write-truth", "--synthetic.write-truth"},
                                                        {"files", "--files.path"},
                                                        {"intrinsics", "--files.intrinsics"},
                                                        {"loop", "--files.loop or --openni2.loop"},
                                                        {"uri", "--openni2.uri"},
                                                        {"playback-speed", "--openni2.playback-speed"},
                                                        {"genicam-device", "--genicam.device"},
                                                        {"genicam-format", "--genicam.format"}})
    params.push_back(runtime::moved_param(old, now));
  return params;
}

runtime::ProcessInfo process_info() {
  std::string details =
      "Captures depth frames, finds the table plane (RANSAC, or a calibrated plane refined by least squares),\n"
      "takes the pixels standing min-height..max-height above it as parts (cleaned by morphology, connected\n"
      "components, min-area), fits the plate's top plane and publishes the part pixels projected onto it as\n"
      "plate_cloud_t on HG_PLATE_CLOUD in scan-line (row-major image) order, with part labels. A frame with no\n"
      "part is published with status NO_PART, an unusable one (no table plane) with BAD_FRAME, each with the\n"
      "reason. Corrupt frames (wrong size or type, all zero) are counted as dropped in the heartbeat and\n"
      "skipped. A decimated PNG depth image goes to HG_DEPTH (depth_frame_t) at most --depth-rate per second.\n"
      "A device that is missing or lost sets the heartbeat to ERROR with the reason and is retried with\n"
      "back-off (--retry-min doubling up to --retry-max) until it comes back.\n"
      "Eye-in-hand: every cloud carries the robot's flange pose at capture (plate_cloud_t flange_*), the latest\n"
      "HG_ROBOT_STATUS if the robot was IDLE and heard within 1 s, else flange_valid false (docs/calibration.md).\n"
      "Plate-plane axes: normal towards the camera, u = camera x projected into the plane, v = normal x u.\n";
  details += sources_help();
  return {"hg-camera-bridge", "Depth camera -> plate points (HG_PLATE_CLOUD) and monitoring depth (HG_DEPTH).", details,
          bridge_params()};
}

BridgeOptions options_from(const runtime::Node& node) {
  BridgeOptions o;
  const std::string trigger = node.params().text("trigger");
  if (trigger != "continuous" && trigger != "job")
    throw runtime::ConfigError("--trigger must be continuous or job, not '" + trigger + "'");
  o.job_trigger = trigger == "job";
  o.rate = node.params().number("rate");
  const std::string parts = node.params().text("parts");
  if (parts != "largest" && parts != "all")
    throw runtime::ConfigError("--parts must be largest or all, not '" + parts + "'");
  SegmentParams& s = o.segment;
  s.all_parts = parts == "all";
  const std::string plane = node.params().text("plane");
  if (plane != "ransac" && plane != "calibrated")
    throw runtime::ConfigError("--plane must be ransac or calibrated, not '" + plane + "'");
  s.calibrated_plane = plane == "calibrated";
  const auto nrm = node.params().numbers("plane-normal");
  if (nrm.size() != 3) throw runtime::ConfigError("--plane-normal needs three numbers nx,ny,nz");
  s.plane_normal = Eigen::Vector3d(nrm[0], nrm[1], nrm[2]);
  if (!(s.plane_normal.norm() > 0)) throw runtime::ConfigError("--plane-normal must not be zero");
  s.plane_normal.normalize();
  s.plane_offset = node.params().number("plane-offset");
  s.ransac_iterations = static_cast<int>(node.params().integer("ransac-iterations"));
  s.ransac_threshold = node.params().number("ransac-threshold");
  s.min_height = node.params().number("min-height");
  s.max_height = node.params().number("max-height");
  s.open_size = static_cast<int>(node.params().integer("open-size"));
  s.close_size = static_cast<int>(node.params().integer("close-size"));
  s.min_area = node.params().number("min-area");
  s.top_tolerance = node.params().number("top-tolerance");
  s.dropout_width = node.params().number("dropout-width");
  s.fill_dropout = !node.params().flag("keep-dropout");
  o.depth_rate = node.params().number("depth-rate");
  o.depth_decimation = static_cast<int>(node.params().integer("depth-decimation"));
  if (o.depth_decimation < 1 || o.depth_decimation > 64)
    throw runtime::ConfigError("--depth-decimation must be in 1..64");
  o.retry_min = node.params().number("retry-min");
  o.retry_max = node.params().number("retry-max");
  if (!(o.retry_min > 0) || !(o.retry_max >= o.retry_min))
    throw runtime::ConfigError("need 0 < --retry-min <= --retry-max");
  o.frame_id = node.params().text("frame-id");
  try {
    // Let segment()'s own checks speak for the segmentation parameters before anything runs.
    segment(cv::Mat(), camera::Intrinsics{}, s);
  } catch (const std::invalid_argument& e) {
    throw runtime::ConfigError(e.what());
  }
  return o;
}

std::unique_ptr<camera::DepthSource> source_from(const runtime::Node& node) {
  const bool job = node.params().text("trigger") == "job";
  // In job mode a source delivers when asked (rendered, triggered); otherwise at the processing rate.
  return make_source(node.params(), job, job ? 0.0 : node.params().number("rate"));
}

void fill_plate_cloud(const Segmentation& s, plate_cloud_t& m) {
  m.status = s.status == SegmentStatus::Ok       ? plate_cloud_t::STATUS_OK
             : s.status == SegmentStatus::NoPart ? plate_cloud_t::STATUS_NO_PART
                                                 : plate_cloud_t::STATUS_BAD_FRAME;
  m.status_text = s.text;
  const bool ok = s.status == SegmentStatus::Ok;
  for (int i = 0; i < 3; ++i) {
    m.plane_origin[i] = ok ? s.origin[i] : 0.0;
    m.plane_normal[i] = ok ? s.normal[i] : 0.0;
    m.plane_u_axis[i] = ok ? s.u_axis[i] : 0.0;
    m.plane_v_axis[i] = ok ? s.v_axis[i] : 0.0;
  }
  m.thickness = ok ? s.thickness : 0.0;
  m.n = ok ? static_cast<std::int32_t>(s.size()) : 0;
  m.u = ok ? s.u : std::vector<float>{};
  m.v = ok ? s.v : std::vector<float>{};
  m.part = ok ? s.part : std::vector<std::int16_t>{};
  m.num_parts = static_cast<std::int16_t>(ok ? s.num_parts : 0);
  m.dropout_filled = ok ? s.dropout_filled : 0;
  m.dropout_filled_area = ok ? s.dropout_filled_area : 0.0;
  m.edge_assessed = ok;  // an organized frame was behind the points
  m.edge_dropout_fraction = ok ? s.edge_dropout_fraction() : 0.0;
  m.largest_edge_gap = ok ? s.largest_edge_gap : 0.0;
}

void fill_flange(const std::optional<FlangeReading>& r, std::int64_t now_utime, plate_cloud_t& m) {
  m.flange_valid = r && r->mode == hullgrind::robot_status_t::MODE_IDLE &&
                   std::abs(double(now_utime - r->recv_utime)) * 1e-6 <= kFlangeMaxAge;
  for (int i = 0; i < 3; ++i) m.flange_position[i] = m.flange_valid ? r->position[i] : 0.0;
  for (int i = 0; i < 4; ++i) m.flange_orientation[i] = m.flange_valid ? r->orientation[i] : (i == 0 ? 1.0 : 0.0);
}

Bridge::Bridge(runtime::Node& node, std::unique_ptr<camera::DepthSource> source, BridgeOptions options)
    : node_(node), source_(std::move(source)), opt_(std::move(options)) {
  node_.subscribe<hullgrind::robot_status_t>(channels::kRobotStatus,
                                             [this](const hullgrind::robot_status_t& m, const runtime::Delivery& d) {
                                               FlangeReading r;
                                               std::copy(m.tcp_position, m.tcp_position + 3, r.position);
                                               std::copy(m.tcp_orientation, m.tcp_orientation + 4, r.orientation);
                                               r.mode = m.mode;
                                               r.recv_utime = d.recv_utime;
                                               std::lock_guard lock(mutex_);
                                               flange_ = r;
                                             });
  if (opt_.job_trigger) {
    node_.subscribe<hullgrind::job_request_t>(channels::kJobRequest,
                                              [this](const hullgrind::job_request_t& m, const runtime::Delivery&) {
                                                if (m.action == hullgrind::job_request_t::ACTION_START)
                                                  on_job(m.job_id);
                                              });
  }
}

Bridge::~Bridge() {
  stop();
  try {
    if (source_ && source_->is_open()) source_->close();
  } catch (...) {
  }
}

void Bridge::start() {
  if (!thread_.joinable()) thread_ = std::thread([this] { run(); });
}

void Bridge::stop() {
  stop_ = true;
  wake_.notify_all();
  if (thread_.joinable()) thread_.join();
}

void Bridge::on_job(const std::string& job_id) {
  {
    std::lock_guard lock(mutex_);
    if (captured_.find(job_id)) {
      logf(Level::Info, "job '%s': repeated START, captured once already", job_id.c_str());
      return;
    }
    captured_.set(job_id, "", 0, 0, "capture requested");
    jobs_.push_back(job_id);
  }
  logf(Level::Info, "job '%s': capture requested", job_id.c_str());
  wake_.notify_all();
}

bool Bridge::sleep_for(double seconds) {
  std::unique_lock lock(mutex_);
  wake_.wait_for(lock, std::chrono::duration<double>(seconds), [this] { return stop_ || node_.stopping(); });
  return !(stop_ || node_.stopping());
}

void Bridge::run() {
  double backoff = opt_.retry_min;
  auto fail = [&](const std::string& why) {
    node_.set_state(heartbeat_t::STATE_ERROR, why + "; retrying in " + std::to_string(backoff).substr(0, 4) + " s");
    try {
      source_->close();
    } catch (...) {
    }
    sleep_for(backoff);
    backoff = std::min(backoff * 2, opt_.retry_max);
  };
  while (!stop_ && !node_.stopping()) {
    try {
      if (!source_->is_open()) {
        source_->open();
        logf(Level::Info, "opened %s", source_->describe().c_str());
        node_.set_state(heartbeat_t::STATE_OK);
        backoff = opt_.retry_min;
      }
      if (opt_.job_trigger) {
        std::unique_lock lock(mutex_);
        if (!wake_.wait_for(lock, std::chrono::milliseconds(200),
                            [this] { return stop_ || node_.stopping() || !jobs_.empty(); }) ||
            jobs_.empty())
          continue;
      }
      std::optional<camera::DepthFrame> frame = source_->grab(opt_.grab_timeout);
      count_skipped();
      if (!frame) continue;
      if (!opt_.job_trigger && opt_.rate > 0 && last_processed_ != Clock::time_point{} &&
          Clock::now() - last_processed_ < std::chrono::duration<double>(0.95 / opt_.rate))
        continue;  // a device faster than --rate: take the next one in time
      process(*frame);
    } catch (const camera::SourceError& e) {
      // Say which source, unless the backend's message already starts with it.
      const std::string what = e.what(), who = source_->describe();
      fail(what.rfind(who, 0) == 0 ? what : who + ": " + what);
    } catch (const std::exception& e) {  // a backend bug must not take the process down either
      fail(source_->describe() + ": unexpected error: " + e.what());
    }
  }
}

void Bridge::count_skipped() {
  const std::int64_t skipped = source_->frames_skipped();
  if (skipped <= skipped_seen_) return;
  node_.count_dropped(skipped - skipped_seen_);
  skipped_seen_ = skipped;
  std::uint64_t suppressed = 0;
  if (corrupt_log_.allow(suppressed))
    logf(Level::Warn, "%s dropped incomplete or malformed frames (%lld so far)", source_->describe().c_str(),
         (long long)skipped);
}

void Bridge::process(camera::DepthFrame& frame) {
  const auto t0 = Clock::now();
  if (const std::string why = frame_defect(frame.depth, frame.intrinsics); !why.empty()) {
    ++corrupt_;
    node_.count_dropped();
    std::uint64_t suppressed = 0;
    if (corrupt_log_.allow(suppressed))
      logf(Level::Warn, "skipped corrupt frame %lld: %s (%lld so far%s)", (long long)frame.seq, why.c_str(),
           (long long)corrupt_.load(), suppressed ? (", " + std::to_string(suppressed) + " not logged").c_str() : "");
    if (++corrupt_in_a_row_ == opt_.degraded_after)
      node_.set_state(heartbeat_t::STATE_DEGRADED,
                      std::to_string(corrupt_in_a_row_) + " corrupt frames in a row: " + why);
    return;
  }
  if (corrupt_in_a_row_ >= opt_.degraded_after) node_.set_state(heartbeat_t::STATE_OK);
  corrupt_in_a_row_ = 0;
  last_processed_ = t0;

  const Segmentation s = segment(frame.depth, frame.intrinsics, opt_.segment, frame.intensity);
  plate_cloud_t msg{};
  msg.header.utime = frame.utime;
  msg.header.frame_id = opt_.frame_id;
  msg.source_frame_seq = frame.seq;
  fill_plate_cloud(s, msg);
  std::string job;
  {
    std::lock_guard lock(mutex_);
    fill_flange(flange_, runtime::now_utime(), msg);
    if (opt_.job_trigger && !jobs_.empty()) {
      job = jobs_.front();
      jobs_.pop_front();
    }
  }
  node_.publish(channels::kPlateCloud, msg);
  node_.set_latency(std::chrono::duration<double>(Clock::now() - t0).count());
  ++processed_;
  if (!job.empty())
    logf(Level::Info, "job '%s': frame %lld -> %s, %d points, %d part(s)%s%s", job.c_str(), (long long)frame.seq,
         s.status == SegmentStatus::Ok       ? "OK"
         : s.status == SegmentStatus::NoPart ? "NO_PART"
                                             : "BAD_FRAME",
         msg.n, int(msg.num_parts), s.text.empty() ? "" : ": ", s.text.c_str());
  else if (s.status != SegmentStatus::Ok)
    logf(Level::Debug, "frame %lld: %s", (long long)frame.seq, s.text.c_str());
  publish_depth(frame);
}

void Bridge::publish_depth(const camera::DepthFrame& frame) {
  if (!(opt_.depth_rate > 0)) return;
  const auto now = Clock::now();
  if (last_depth_ != Clock::time_point{} && now - last_depth_ < std::chrono::duration<double>(1.0 / opt_.depth_rate))
    return;
  last_depth_ = now;
  // Every k-th pixel of every k-th row, no interpolation (a mean of table and plate depths is no depth):
  // new pixel j is old pixel k j, so fx' = fx / k and cx' = cx / k.
  const int k = opt_.depth_decimation;
  const camera::Intrinsics& in = frame.intrinsics;
  cv::Mat small((frame.depth.rows + k - 1) / k, (frame.depth.cols + k - 1) / k, CV_16UC1);
  for (int r = 0; r < small.rows; ++r) {
    const std::uint16_t* src = frame.depth.ptr<std::uint16_t>(r * k);
    std::uint16_t* dst = small.ptr<std::uint16_t>(r);
    for (int c = 0; c < small.cols; ++c) dst[c] = src[c * k];
  }
  std::vector<std::uint8_t> png;
  if (!cv::imencode(".png", small, png, {cv::IMWRITE_PNG_COMPRESSION, 1})) return;
  hullgrind::depth_frame_t m{};
  m.header.utime = frame.utime;
  m.header.frame_id = opt_.frame_id;
  m.width = small.cols;
  m.height = small.rows;
  m.fx = in.fx / k;
  m.fy = in.fy / k;
  m.cx = in.cx / k;
  m.cy = in.cy / k;
  m.depth_unit = in.depth_unit;
  m.encoding = hullgrind::depth_frame_t::ENCODING_PNG16;
  m.data_size = static_cast<std::int32_t>(png.size());
  m.data.assign(png.begin(), png.end());
  node_.publish(channels::kDepth, m);
}

std::unique_ptr<Bridge> attach(runtime::Node& node) {
  BridgeOptions options = options_from(node);
  std::unique_ptr<camera::DepthSource> source = source_from(node);
  logf(Level::Info, "source: %s; trigger: %s", source->describe().c_str(), options.job_trigger ? "job" : "continuous");
  auto bridge = std::make_unique<Bridge>(node, std::move(source), options);
  bridge->start();
  return bridge;  // its destructor stops the capture thread after the loop
}

}  // namespace hg::camera_bridge
