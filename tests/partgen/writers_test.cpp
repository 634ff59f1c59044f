// Writers and hg-gen: what is written parses back (with readers written here, independent of the
// writers) to the same points and the same ground truth.
#include "sim/partgen/presets.hpp"
#include "sim/partgen/shapes.hpp"
#include "sim/partgen/synth.hpp"
#include "sim/partgen/writers.hpp"

#include <gtest/gtest.h>
#include <nlohmann/json.hpp>

#include <cstdint>
#include <cstdlib>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <numbers>
#include <sstream>
#include <string>
#include <vector>

using namespace hg::partgen;
namespace fs = std::filesystem;

namespace {
fs::path temp_dir(const std::string& name) {
  const fs::path d = fs::temp_directory_path() / ("hg-partgen-" + name + "-" + std::to_string(::getpid()));
  fs::remove_all(d);
  fs::create_directories(d);
  return d;
}

std::vector<double> read_xyz(const fs::path& p) {
  std::ifstream in(p);
  std::vector<double> v;
  std::string line;
  while (std::getline(in, line)) {
    std::istringstream ls(line);
    double x, y, z;
    std::string rest;
    EXPECT_TRUE(static_cast<bool>(ls >> x >> y >> z)) << line;
    EXPECT_FALSE(static_cast<bool>(ls >> rest)) << "extra field in " << line;
    v.insert(v.end(), {x, y, z});
  }
  return v;
}

// Minimal PCD reader: header key/value lines up to DATA, then ascii rows or little-endian float32s.
std::vector<double> read_pcd(const fs::path& p, std::string* data_kind) {
  std::ifstream in(p, std::ios::binary);
  std::string line;
  size_t points = 0;
  while (std::getline(in, line)) {
    if (line.empty() || line[0] == '#') continue;
    std::istringstream ls(line);
    std::string key;
    ls >> key;
    if (key == "FIELDS") {
      std::string a, b, c;
      ls >> a >> b >> c;
      EXPECT_EQ(a + b + c, "xyz");
    } else if (key == "SIZE") {
      int a, b, c;
      ls >> a >> b >> c;
      EXPECT_EQ(a * 100 + b * 10 + c, 444);
    } else if (key == "TYPE") {
      EXPECT_EQ(line, "TYPE F F F");
    } else if (key == "POINTS") {
      ls >> points;
    } else if (key == "DATA") {
      ls >> *data_kind;
      break;
    }
  }
  std::vector<double> v;
  if (*data_kind == "binary") {
    std::vector<unsigned char> bytes(points * 12);
    in.read(reinterpret_cast<char*>(bytes.data()), static_cast<std::streamsize>(bytes.size()));
    EXPECT_EQ(in.gcount(), static_cast<std::streamsize>(bytes.size()));
    EXPECT_EQ(in.peek(), EOF) << "bytes after the last point";
    for (size_t i = 0; i < points * 3; ++i) {
      std::uint32_t u = 0;
      for (int b = 0; b < 4; ++b) u |= std::uint32_t(bytes[4 * i + b]) << (8 * b);
      float f;
      std::memcpy(&f, &u, 4);
      v.push_back(f);
    }
  } else {
    double x;
    while (in >> x) v.push_back(x);
  }
  EXPECT_EQ(v.size(), points * 3);
  return v;
}

Cloud sample_cloud(Scene& scene, CloudOptions& o) {
  scene = single_part_scene(make_shape("plate-hole-slot"), 0.05);
  o.pitch = 0.003;
  o.in_plane_sigma = 0.0002;
  o.depth_sigma = 0.0003;
  o.dropout = 0.02;
  o.jagged = true;
  o.seed = 77;
  return synthesize(scene, o);
}

int run(const std::string& args) {
  const std::string cmd = std::string(HG_BIN_DIR) + "/hg-gen " + args + " > /dev/null 2>&1";
  const int rc = std::system(cmd.c_str());
  return WIFEXITED(rc) ? WEXITSTATUS(rc) : -1;
}
}  // namespace

TEST(PartgenWriters, XyzAndPcdReadBackToTheSamePoints) {
  Scene scene;
  CloudOptions o;
  const Cloud c = sample_cloud(scene, o);
  const fs::path d = temp_dir("rw");
  write_xyz(c, d / "a.xyz");
  write_pcd(c, d / "a.pcd", true);
  write_pcd(c, d / "b.pcd", false);
  const auto xyz = read_xyz(d / "a.xyz");
  std::string kind;
  const auto bin = read_pcd(d / "a.pcd", &kind);
  EXPECT_EQ(kind, "binary");
  const auto asc = read_pcd(d / "b.pcd", &kind);
  EXPECT_EQ(kind, "ascii");
  ASSERT_EQ(xyz.size(), c.xyz.size());
  ASSERT_EQ(bin.size(), c.xyz.size());
  ASSERT_EQ(asc.size(), c.xyz.size());
  for (size_t i = 0; i < c.xyz.size(); ++i) {
    ASSERT_NEAR(xyz[i], c.xyz[i], 0.5e-7 + 1e-15);  // 7 decimals
    ASSERT_EQ(bin[i], double(float(c.xyz[i])));     // float32 exactly
    ASSERT_EQ(float(asc[i]), float(c.xyz[i]));      // ascii float text round-trips
  }
  // No temporary files left behind.
  int files = 0;
  for (const auto& e : fs::directory_iterator(d)) files += e.is_regular_file();
  EXPECT_EQ(files, 3);
  fs::remove_all(d);
}

TEST(PartgenWriters, TruthJsonHoldsThePlacedPolygons) {
  Scene scene;
  CloudOptions o;
  const Cloud c = sample_cloud(scene, o);
  const fs::path d = temp_dir("truth");
  write_json(truth_json(scene, o, c), d / "t.json");
  std::ifstream in(d / "t.json");
  const nlohmann::json j = nlohmann::json::parse(in);
  EXPECT_EQ(j.at("points").get<size_t>(), c.size());
  EXPECT_EQ(j.at("grid").at("pitch").get<double>(), o.pitch);
  EXPECT_EQ(j.at("noise").at("seed").get<std::uint64_t>(), 77u);
  EXPECT_EQ(j.at("noise").at("jagged").get<bool>(), true);
  const auto& part = j.at("parts").at(0);
  EXPECT_EQ(part.at("shape"), "plate-hole-slot");
  const double pi = std::numbers::pi;
  EXPECT_NEAR(part.at("area").get<double>(), 0.1 - pi * 0.0025 - (0.0032 + pi * 0.0004), 1e-12);
  // Rebuild the polygon from the JSON and compare with the scene's placed polygon, and measure it.
  PolygonWithHoles poly;
  for (const auto& p : part.at("outer")) poly.outer.emplace_back(p.at(0).get<double>(), p.at(1).get<double>());
  for (const auto& h : part.at("holes")) {
    Ring& r = poly.holes.emplace_back();
    for (const auto& p : h) r.emplace_back(p.at(0).get<double>(), p.at(1).get<double>());
  }
  ASSERT_EQ(poly.holes.size(), 2u);
  EXPECT_EQ(poly.outer, scene.parts[0].placed.outer);  // full double precision in the JSON
  EXPECT_EQ(poly.holes[1], scene.parts[0].placed.holes[1]);
  EXPECT_GT(signed_area(poly.outer), 0);
  EXPECT_LT(signed_area(poly.holes[0]), 0);
  EXPECT_NEAR(polygon_area(poly), part.at("area").get<double>(), part.at("perimeter").get<double>() * 0.05e-3);
  // The cloud's points sit on the polygon of the JSON: the bulk of them inside.
  size_t inside = 0;
  for (size_t i = 0; i < c.size(); ++i) inside += contains(poly, c.xyz[3 * i], c.xyz[3 * i + 1]);
  EXPECT_GT(inside, c.size() * 95 / 100);
  fs::remove_all(d);
}

TEST(PartgenWriters, HgGenWritesCloudAndTruthAndIsDeterministic) {
  const fs::path d = temp_dir("cli");
  const std::string a = (d / "a.xyz").string(), b = (d / "b.xyz").string();
  const std::string args = "--preset low-1 --noise 0.0002 --dropout 0.02 --jagged --seed 3 -o ";
  ASSERT_EQ(run(args + a), 0);
  ASSERT_EQ(run(args + b), 0);
  std::ifstream fa(a), fb(b);
  std::stringstream sa, sb;
  sa << fa.rdbuf();
  sb << fb.rdbuf();
  EXPECT_EQ(sa.str(), sb.str());
  const auto pts = read_xyz(a);
  std::ifstream tj(a + ".truth.json");
  const nlohmann::json truth = nlohmann::json::parse(tj);
  EXPECT_EQ(truth.at("points").get<size_t>() * 3, pts.size());
  EXPECT_EQ(truth.at("preset").at("paper_points").get<size_t>(), 3716u);
  EXPECT_EQ(truth.at("cloud_file"), "a.xyz");
  // PCD by extension, and the 1.59 M-point preset in binary.
  ASSERT_EQ(run("--preset high-4 -o " + (d / "h.pcd").string()), 0);
  std::string kind;
  const auto h = read_pcd(d / "h.pcd", &kind);
  EXPECT_EQ(kind, "binary");
  EXPECT_NEAR(double(h.size() / 3), 1591649.0, 0.03 * 1591649);
  fs::remove_all(d);
}

TEST(PartgenWriters, HgGenRejectsBadInputWithoutWriting) {
  const fs::path d = temp_dir("bad");
  const std::string out = (d / "x.xyz").string();
  EXPECT_EQ(run("--shape dinghy -o " + out), 2);
  EXPECT_EQ(run("--shape ring-flange --pitch abc -o " + out), 2);
  EXPECT_EQ(run("--shape ring-flange --pitch -1 -o " + out), 2);
  EXPECT_EQ(run("--shape ring-flange --dropout 2 -o " + out), 2);
  EXPECT_EQ(run("--shape ring-flange --thickness 0.5 -o " + out), 2);
  EXPECT_EQ(run("--preset low-1 --shape ring-flange -o " + out), 2);
  EXPECT_EQ(run("--frobnicate"), 2);
  EXPECT_EQ(run("--all " + (d / "all").string() + " --pitch 0.001"), 2);
  EXPECT_EQ(run("--all " + (d / "all").string() + " --format ply"), 2);
  EXPECT_EQ(run("--preset low-1"), 2);  // no -o
  EXPECT_EQ(run("--shape ring-flange -o " + (d / "no-such-dir" / "x.xyz").string()), 1);
  EXPECT_FALSE(fs::exists(out));
  EXPECT_FALSE(fs::exists(d / "all"));
  EXPECT_EQ(run("--help"), 0);
  EXPECT_EQ(run("--list"), 0);
  fs::remove_all(d);
}
