#include "sim/partgen/writers.hpp"

#include <unistd.h>

#include <cerrno>
#include <charconv>
#include <cmath>
#include <cstdio>
#include <cstring>
#include <stdexcept>

namespace hg::partgen {

namespace {
// Writes bytes to path via a temporary sibling and rename(2).
class AtomicFile {
 public:
  explicit AtomicFile(std::string path) : path_(std::move(path)), tmp_(path_ + ".tmp" + std::to_string(getpid())) {
    f_ = std::fopen(tmp_.c_str(), "wb");
    if (!f_) fail("cannot create");
  }
  ~AtomicFile() {
    if (f_) {
      std::fclose(f_);
      std::remove(tmp_.c_str());
    }
  }
  void write(const void* data, size_t n) {
    if (n && std::fwrite(data, 1, n, f_) != n) fail("cannot write");
  }
  void write(const std::string& s) { write(s.data(), s.size()); }
  void commit() {
    const bool ok = std::fclose(f_) == 0;
    f_ = nullptr;
    if (!ok) {
      std::remove(tmp_.c_str());
      fail("cannot write");
    }
    if (std::rename(tmp_.c_str(), path_.c_str()) != 0) {
      const int e = errno;
      std::remove(tmp_.c_str());
      errno = e;
      fail("cannot rename temporary file onto");
    }
  }

 private:
  [[noreturn]] void fail(const char* what) {
    throw std::runtime_error(std::string(what) + " '" + path_ + "': " + std::strerror(errno));
  }
  std::string path_, tmp_;
  std::FILE* f_ = nullptr;
};

char* put_fixed(char* p, char* end, double v) { return std::to_chars(p, end, v, std::chars_format::fixed, 7).ptr; }

nlohmann::json ring_json(const Ring& r) {
  nlohmann::json a = nlohmann::json::array();
  for (const Vec2& p : r) a.push_back({p.x(), p.y()});
  return a;
}
}  // namespace

void write_xyz(const Cloud& cloud, const std::string& path) {
  AtomicFile f(path);
  std::string buf;
  buf.resize(1 << 20);
  size_t used = 0;
  for (size_t i = 0; i < cloud.size(); ++i) {
    if (buf.size() - used < 128) {
      f.write(buf.data(), used);
      used = 0;
    }
    char* p = buf.data() + used;
    char* end = buf.data() + buf.size();
    p = put_fixed(p, end, cloud.xyz[3 * i]);
    *p++ = ' ';
    p = put_fixed(p, end, cloud.xyz[3 * i + 1]);
    *p++ = ' ';
    p = put_fixed(p, end, cloud.xyz[3 * i + 2]);
    *p++ = '\n';
    used = static_cast<size_t>(p - buf.data());
  }
  f.write(buf.data(), used);
  f.commit();
}

void write_pcd(const Cloud& cloud, const std::string& path, bool binary) {
  AtomicFile f(path);
  const std::string n = std::to_string(cloud.size());
  f.write(
      "# .PCD v0.7 - Point Cloud Data file format (hg-gen)\nVERSION 0.7\nFIELDS x y z\nSIZE 4 4 4\n"
      "TYPE F F F\nCOUNT 1 1 1\nWIDTH " +
      n + "\nHEIGHT 1\nVIEWPOINT 0 0 0 1 0 0 0\nPOINTS " + n + "\nDATA " + (binary ? "binary" : "ascii") + "\n");
  if (binary) {
    static_assert(sizeof(float) == 4);
    std::vector<unsigned char> bytes(cloud.xyz.size() * 4);
    for (size_t i = 0; i < cloud.xyz.size(); ++i) {
      const float v = static_cast<float>(cloud.xyz[i]);
      std::uint32_t u;
      std::memcpy(&u, &v, 4);
      for (int b = 0; b < 4; ++b) bytes[4 * i + b] = static_cast<unsigned char>(u >> (8 * b));  // little endian
    }
    f.write(bytes.data(), bytes.size());
  } else {
    std::string buf;
    char tmp[64];
    for (size_t i = 0; i < cloud.xyz.size(); ++i) {
      // float text that reads back as the same float32 the binary form would hold
      char* e = std::to_chars(tmp, tmp + sizeof tmp, static_cast<float>(cloud.xyz[i])).ptr;
      buf.append(tmp, e);
      buf.push_back(i % 3 == 2 ? '\n' : ' ');
      if (buf.size() > (1 << 20)) {
        f.write(buf);
        buf.clear();
      }
    }
    f.write(buf);
  }
  f.commit();
}

nlohmann::json truth_json(const Scene& scene, const CloudOptions& o, const Cloud& cloud) {
  using nlohmann::json;
  json parts = json::array();
  for (const PlacedPart& p : scene.parts) {
    json holes = json::array();
    for (const Ring& h : p.placed.holes) holes.push_back(ring_json(h));
    parts.push_back({
        {"shape", p.shape.name},
        {"description", p.shape.description},
        {"scale", p.shape.scale},
        {"thickness", p.shape.thickness},
        {"pose",
         {{"rotation_deg", p.pose.theta * 180.0 / M_PI},
          {"translation", {p.pose.translation.x(), p.pose.translation.y()}}}},
        {"area", p.shape.exact_area},
        {"perimeter", p.shape.exact_perimeter},
        {"polygon_area", polygon_area(p.placed)},
        {"polygon_perimeter", polygon_perimeter(p.placed)},
        {"hole_count", p.placed.holes.size()},
        {"outer", ring_json(p.placed.outer)},
        {"holes", holes},
    });
  }
  const PixelGrid& g = cloud.grid;
  return {
      {"generator", "hg-gen"},
      {"format_version", 1},
      {"units", "metres"},
      {"frame",
       "table frame: x right, y up (the top of the image is +y), z up towards the camera; "
       "outer rings counter-clockwise, holes clockwise, rings open (last vertex not repeated)"},
      {"chord_tolerance", kChordTolerance},
      {"parts", parts},
      {"area", scene.total_area()},
      {"perimeter", scene.total_perimeter()},
      {"grid",
       {{"pitch", g.pitch},
        {"origin", {g.origin_x, g.origin_y}},
        {"rows", g.rows},
        {"cols", g.cols},
        {"order",
         "scan-line: rows from the top (largest y) down, columns left to right; "
         "pixel (row, col) centre = (origin_x + col*pitch, origin_y - row*pitch)"}}},
      {"noise",
       {{"in_plane_sigma", o.in_plane_sigma},
        {"depth_sigma", o.depth_sigma},
        {"dropout", o.dropout},
        {"jagged", o.jagged},
        {"coverage_subrows", o.coverage_subrows},
        {"seed", o.seed}}},
      {"points", cloud.size()},
      {"pixels_on_part", cloud.candidates},
      {"expected_points", cloud.expected_points},
  };
}

void write_json(const nlohmann::json& j, const std::string& path) {
  AtomicFile f(path);
  f.write(j.dump(1) + "\n");
  f.commit();
}

}  // namespace hg::partgen
