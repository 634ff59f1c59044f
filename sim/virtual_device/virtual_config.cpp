#include "sim/virtual_device/virtual_config.hpp"

#include <cctype>
#include <charconv>
#include <memory>
#include <cmath>
#include <cstdlib>
#include <stdexcept>
#include <string_view>

#if HG_HAVE_SCENE
#include "sim/scene/scene.hpp"
#endif

namespace hg::sim::virtual_device {
namespace {

[[noreturn]] void fail(const std::string& uri, std::size_t offset, const std::string& what) {
  throw std::invalid_argument("virtual device URI '" + uri + "', byte " + std::to_string(offset) + ": " + what);
}

template <class T>
T parse_number(const std::string& uri, std::size_t offset, std::string_view text, const char* key) {
  T value{};
  auto [end, ec] = std::from_chars(text.data(), text.data() + text.size(), value);
  if (ec != std::errc() || end != text.data() + text.size() || text.empty())
    fail(uri, offset, std::string("'") + key + "' wants a number, got '" + std::string(text) + "'");
  return value;
}

std::string format_double(double v) {
  char buf[64];
  auto [end, ec] = std::to_chars(buf, buf + sizeof buf, v);
  return std::string(buf, end);
}

}  // namespace

VirtualDeviceConfig parse_virtual_uri(const std::string& uri) {
  const std::string_view scheme(kUriScheme);
  if (uri.compare(0, scheme.size(), scheme) != 0) fail(uri, 0, "does not start with hg-virtual://");
  VirtualDeviceConfig c;
  const std::size_t query = uri.find('?', scheme.size());
  c.scene = uri.substr(scheme.size(), query == std::string::npos ? std::string::npos : query - scheme.size());
  if (c.scene.empty()) fail(uri, scheme.size(), "no scene name after hg-virtual://");
  for (char ch : c.scene)
    if (!(std::isalnum(static_cast<unsigned char>(ch)) || ch == '-' || ch == '_'))
      fail(uri, scheme.size(), "scene name may hold letters, digits, '-' and '_' only");
  if (query == std::string::npos) return c;

  std::size_t pos = query + 1;
  while (pos <= uri.size()) {
    std::size_t amp = uri.find('&', pos);
    if (amp == std::string::npos) amp = uri.size();
    const std::string_view item(uri.data() + pos, amp - pos);
    const std::size_t eq = item.find('=');
    if (eq == std::string_view::npos) fail(uri, pos, "expected key=value, got '" + std::string(item) + "'");
    const std::string key(item.substr(0, eq));
    const std::string_view value = item.substr(eq + 1);
    const std::size_t value_at = pos + eq + 1;
    if (key == "profile") {
      if (value.empty()) fail(uri, value_at, "empty profile");
      c.profile = std::string(value);
    } else if (key == "fps") {
      c.fps = parse_number<double>(uri, value_at, value, "fps");
      if (!(c.fps > 0 && c.fps <= 120)) fail(uri, value_at, "fps must be in (0, 120]");
    } else if (key == "seed") {
      c.seed = parse_number<std::uint64_t>(uri, value_at, value, "seed");
    } else if (key == "disconnect_after") {
      c.disconnect_after = parse_number<std::uint64_t>(uri, value_at, value, "disconnect_after");
    } else if (key == "reconnect_after") {
      const double s = parse_number<double>(uri, value_at, value, "reconnect_after");
      if (!(s >= 0 && s <= 3600)) fail(uri, value_at, "reconnect_after must be in [0, 3600] seconds");
      c.reconnect_after = s;
    } else if (key == "cropping") {
      if (value != "0" && value != "1") fail(uri, value_at, "cropping must be 0 or 1");
      c.cropping_property = value == "1";
    } else {
      fail(uri, pos,
           "unknown option '" + key + "' (known: profile, fps, seed, disconnect_after, reconnect_after, cropping)");
    }
    pos = amp + 1;
  }
  return c;
}

std::string to_uri(const VirtualDeviceConfig& c) {
  std::string uri = std::string(kUriScheme) + c.scene + "?profile=" + c.profile + "&fps=" + format_double(c.fps);
  if (c.seed) uri += "&seed=" + std::to_string(*c.seed);
  if (c.disconnect_after) uri += "&disconnect_after=" + std::to_string(*c.disconnect_after);
  if (c.reconnect_after) uri += "&reconnect_after=" + format_double(*c.reconnect_after);
  if (!c.cropping_property) uri += "&cropping=0";
  return uri;
}

std::string announced_uri_from_environment() {
  if (const char* uri = std::getenv("HG_VIRTUAL_URI"); uri && *uri) {
    parse_virtual_uri(uri);  // validate
    return uri;
  }
  // Build a URI from the single variables so that they are validated by the same parser.
  VirtualDeviceConfig c;
  std::string uri = std::string(kUriScheme);
  const char* scene = std::getenv("HG_VIRTUAL_SCENE");
  uri += (scene && *scene) ? scene : c.scene.c_str();
  const char* profile = std::getenv("HG_VIRTUAL_PROFILE");
  uri += "?profile=" + std::string((profile && *profile) ? profile : c.profile.c_str());
  const char* fps = std::getenv("HG_VIRTUAL_FPS");
  uri += "&fps=" + ((fps && *fps) ? std::string(fps) : format_double(c.fps));
  const std::pair<const char*, const char*> optional_keys[] = {{"HG_VIRTUAL_SEED", "seed"},
                                                               {"HG_VIRTUAL_DISCONNECT_AFTER", "disconnect_after"},
                                                               {"HG_VIRTUAL_RECONNECT_AFTER", "reconnect_after"}};
  for (auto [env, key] : optional_keys)
    if (const char* v = std::getenv(env); v && *v) uri += std::string("&") + key + "=" + v;
  parse_virtual_uri(uri);
  return uri;
}

// ---- frames ----

#if HG_HAVE_SCENE
struct FrameRenderer::Impl {
  SceneSpec spec;
  CameraProfile profile;
};

FrameRenderer::FrameRenderer(const VirtualDeviceConfig& config) {
  auto impl = std::make_shared<Impl>();
  impl->spec = scene_preset(config.scene);
  if (config.seed) impl->spec.seed = *config.seed;
  impl->profile = camera_profile(config.profile);
  intrinsics_ = impl->profile.intrinsics();
  impl_ = std::move(impl);
}

bool FrameRenderer::has_intensity() const { return impl_->spec.effects.intensity; }

FrameRenderer::Frame FrameRenderer::render_frame(std::uint64_t frame_index) const {
  hg::sim::RenderedFrame r = hg::sim::render(impl_->spec, impl_->profile, frame_index);
  return {std::move(r.depth), std::move(r.intensity)};
}
#else
// Stand-in until the scene renderer (hg_camera_scene) is built: a flat table 1.2 m below the camera with
// one 12 mm plate, the same for every frame.
struct FrameRenderer::Impl {};

FrameRenderer::FrameRenderer(const VirtualDeviceConfig& config) {
  if (config.profile == "pm806") intrinsics_ = {1280, 960, 1120.0, 1120.0, 640.0, 480.0, 0.001};
  else if (config.profile == "lsr-l")
    intrinsics_ = {2048, 1536, 1750.0, 1750.0, 1024.0, 768.0, 0.0001};
  else if (config.profile == "m130")  // 0.32 mm between pixels at 1.3 m, as the renderer's profile
    intrinsics_ = {2448, 2048, 1.3 / 0.32e-3, 1.3 / 0.32e-3, 1224.0, 1024.0, 0.0001};
  else
    throw std::invalid_argument("unknown camera profile '" + config.profile + "' (known: pm806, lsr-l, m130)");
  impl_ = std::make_shared<Impl>();
}

bool FrameRenderer::has_intensity() const { return false; }

FrameRenderer::Frame FrameRenderer::render_frame(std::uint64_t) const {
  const auto& in = intrinsics_;
  cv::Mat depth(in.height, in.width, CV_16UC1, cv::Scalar(std::lround(1.2 / in.depth_unit)));
  depth(cv::Rect(in.width / 4, in.height / 4, in.width / 2, in.height / 3))
      .setTo(cv::Scalar(std::lround(1.188 / in.depth_unit)));
  return {depth, cv::Mat()};
}
#endif

}  // namespace hg::sim::virtual_device
