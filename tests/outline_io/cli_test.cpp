// hg-outline end to end: a 20 x 20 square with an 8 x 8 square hole as a grid of spacing 1 (fixtures of
// make_fixtures.py) in every format; the loops must be 1 outer + 1 hole with the analytic areas.
#include <gtest/gtest.h>
#include <sys/wait.h>
#include <unistd.h>

#include <cmath>
#include <filesystem>
#include <fstream>
#include <nlohmann/json.hpp>
#include <random>
#include <sstream>

namespace fs = std::filesystem;

namespace {

const std::string kBin = std::string(HG_BIN_DIR) + "/hg-outline";
std::string data(const std::string& name) { return std::string(HG_TEST_DATA) + "/outline_io/" + name; }
constexpr int kGridPoints = 21 * 21 - 7 * 7;  // grid 0..20 without the points strictly inside [6, 14]^2

std::string read_all(const fs::path& p) {
  std::ifstream f(p, std::ios::binary);
  std::stringstream ss;
  ss << f.rdbuf();
  return ss.str();
}

struct CliRun {
  int code = -1;
  std::string out, err;
};

class OutlineIoCli : public ::testing::Test {
 protected:
  fs::path dir;
  void SetUp() override {
    dir = fs::temp_directory_path() / ("hg_outline_cli_" + std::to_string(::getpid()) + "_" +
                                       ::testing::UnitTest::GetInstance()->current_test_info()->name());
    fs::remove_all(dir);
    fs::create_directories(dir / "out");
  }
  void TearDown() override { fs::remove_all(dir); }

  CliRun run(const std::string& args) {
    std::string cmd = "timeout 120 '" + kBin + "' " + args + " > '" + (dir / "stdout").string() + "' 2> '" +
                      (dir / "stderr").string() + "'";
    int st = std::system(cmd.c_str());
    CliRun r;
    r.code = WIFEXITED(st) ? WEXITSTATUS(st) : -1;
    r.out = read_all(dir / "stdout");
    r.err = read_all(dir / "stderr");
    return r;
  }
  std::string out(const std::string& name) { return (dir / "out" / name).string(); }
};

// One outer loop of area 400 and one hole of area 64; a boundary off by up to half a spacing would
// change an area by at most half the perimeter x spacing.
void expect_square_with_hole(const nlohmann::json& j, int points_read = kGridPoints) {
  EXPECT_EQ(j["points_read"], points_read);
  ASSERT_EQ(j["loops"].size(), 2u) << j["loops"].dump();
  const auto& outer = j["loops"][0];
  const auto& hole = j["loops"][1];
  EXPECT_FALSE(outer["hole"].get<bool>());
  EXPECT_TRUE(hole["hole"].get<bool>());
  EXPECT_NEAR(outer["area"].get<double>(), 400.0, 0.5 * 80);
  EXPECT_NEAR(hole["area"].get<double>(), 64.0, 0.5 * 32);
  EXPECT_NEAR(outer["perimeter"].get<double>(), 80.0, 8);
  for (const char* key :
       {"points_used", "duplicates_merged", "alpha_radius", "mode", "order", "triangles", "search_cost"})
    EXPECT_TRUE(j.contains(key)) << key;
  for (const char* key : {"read", "triangulate", "alpha", "loops", "total"})
    EXPECT_TRUE(j["time_ms"].contains(key)) << key;
}

}  // namespace

TEST_F(OutlineIoCli, EveryFormatGivesTheSquareWithItsHole) {
  for (const char* f : {"grid_hole.xyz", "grid_hole.csv", "grid_hole_ascii.pcd", "grid_hole_binary.pcd",
                        "grid_hole_compressed.pcd", "grid_hole_ascii.ply", "grid_hole_binary.ply"}) {
    SCOPED_TRACE(f);
    fs::remove(out("o.json"));
    CliRun r = run("'" + data(f) + "' --alpha-radius 1.5 -o '" + out("o.json") + "'");
    ASSERT_EQ(r.code, 0) << r.err;
    auto j = nlohmann::json::parse(read_all(out("o.json")));
    expect_square_with_hole(j);
    EXPECT_EQ(j["alpha_radius"], 1.5);
    // Planar input: no z, no plane; every z equal, the plane z = that z with the input's axes.
    if (j["input"]["has_z"].get<bool>()) {
      ASSERT_TRUE(j.contains("plane"));
      EXPECT_EQ(j["plane"]["normal"], nlohmann::json::parse("[0, 0, 1]"));
      EXPECT_EQ(j["plane"]["u"], nlohmann::json::parse("[1, 0, 0]"));
    } else {
      EXPECT_FALSE(j.contains("plane"));
    }
    // Planar input keeps the input's units and axes: the outer loop spans exactly [0, 20]^2.
    double minx = 1e9, maxx = -1e9, miny = 1e9, maxy = -1e9;
    for (auto& p : j["loops"][0]["points"]) {
      minx = std::min(minx, p[0].get<double>()), maxx = std::max(maxx, p[0].get<double>());
      miny = std::min(miny, p[1].get<double>()), maxy = std::max(maxy, p[1].get<double>());
    }
    EXPECT_EQ(minx, 0.0);
    EXPECT_EQ(maxx, 20.0);
    EXPECT_EQ(miny, 0.0);
    EXPECT_EQ(maxy, 20.0);
  }
}

TEST_F(OutlineIoCli, JsonOnStdoutAndAutomaticRadiusFindsTheHole) {
  CliRun r = run("'" + data("grid_hole.xyz") + "' --mode ds --order hilbert");
  ASSERT_EQ(r.code, 0) << r.err;
  auto j = nlohmann::json::parse(r.out);
  expect_square_with_hole(j);
  EXPECT_EQ(j["mode"], "ds");
  EXPECT_EQ(j["order"], "hilbert");
  EXPECT_EQ(j["threads"], 1);                        // ds is never split into strips
  EXPECT_GT(j["alpha_radius"].get<double>(), 0.70);  // must exceed a grid triangle's circumradius, sqrt(2)/2
}

TEST_F(OutlineIoCli, ThreadsOutOfRangeIsAUsageErrorNamingTheKey) {
  CliRun r = run("'" + data("grid_hole.xyz") + "' --threads -1");
  EXPECT_NE(r.code, 0);
  EXPECT_NE(r.err.find("threads"), std::string::npos) << r.err;
  CliRun ok = run("'" + data("grid_hole.xyz") + "' --threads 2");  // too small to split: one thread, same loops
  ASSERT_EQ(ok.code, 0) << ok.err;
  auto j = nlohmann::json::parse(ok.out);
  expect_square_with_hole(j);
  EXPECT_EQ(j["threads"], 1);
}

TEST_F(OutlineIoCli, TiltedCloudIsProjectedOntoItsPlane) {
  CliRun r = run("'" + data("grid_hole_tilted.xyz") + "' --alpha-radius 1.5 -o '" + out("t.json") + "'");
  ASSERT_EQ(r.code, 0) << r.err;
  auto j = nlohmann::json::parse(read_all(out("t.json")));
  expect_square_with_hole(j);
  ASSERT_TRUE(j.contains("plane"));
  // make_fixtures.py: rotation 30 deg about x, then 20 deg about z: normal = Rz * (0, -sin 30, cos 30).
  const double a = 30 * M_PI / 180, b = 20 * M_PI / 180;
  const double n[3] = {std::sin(b) * std::sin(a), -std::cos(b) * std::sin(a), std::cos(a)};
  double dot = 0;
  for (int k = 0; k < 3; ++k) dot += n[k] * j["plane"]["normal"][k].get<double>();
  EXPECT_NEAR(dot, 1.0, 1e-9);
  // points_3d: same count as points; consecutive 3-D distances equal the plane distances.
  for (auto& loop : j["loops"]) {
    const auto& p2 = loop["points"];
    const auto& p3 = loop["points_3d"];
    ASSERT_EQ(p2.size(), p3.size());
    for (std::size_t i = 0; i + 1 < p2.size(); ++i) {
      double d2 = std::hypot(p2[i + 1][0].get<double>() - p2[i][0].get<double>(),
                             p2[i + 1][1].get<double>() - p2[i][1].get<double>());
      double d3 = std::sqrt(std::pow(p3[i + 1][0].get<double>() - p3[i][0].get<double>(), 2) +
                            std::pow(p3[i + 1][1].get<double>() - p3[i][1].get<double>(), 2) +
                            std::pow(p3[i + 1][2].get<double>() - p3[i][2].get<double>(), 2));
      EXPECT_NEAR(d2, d3, 1e-9);
      // Boundary edges join grid neighbours: 1 along a side, sqrt(2) across a corner of the hole.
      EXPECT_TRUE(std::abs(d2 - 1) < 1e-9 || std::abs(d2 - std::sqrt(2.0)) < 1e-9) << d2;
    }
  }
}

TEST_F(OutlineIoCli, PicturesAndTriangles) {
  CliRun r = run("'" + data("grid_hole_binary.pcd") + "' --alpha-radius 1.5 -o '" + out("o.json") + "' --svg '" +
                 out("o.svg") + "' --png '" + out("o.png") + "' --triangles '" + out("o.tri") + "' --draw-triangles");
  ASSERT_EQ(r.code, 0) << r.err;
  auto j = nlohmann::json::parse(read_all(out("o.json")));
  const std::string svg = read_all(out("o.svg"));
  EXPECT_NE(svg.find("</svg>"), std::string::npos);
  const std::string png = read_all(out("o.png"));
  ASSERT_GT(png.size(), 8u);
  EXPECT_EQ(png.substr(1, 3), "PNG");
  // Triangles: one "i j k" per line, as many as the JSON says, indices into the points as read.
  std::istringstream tri(read_all(out("o.tri")));
  std::string line;
  std::size_t lines = 0;
  while (std::getline(tri, line)) {
    std::istringstream ls(line);
    long a = -1, b = -1, c = -1;
    std::string rest;
    ASSERT_TRUE(ls >> a >> b >> c) << line;
    EXPECT_FALSE(ls >> rest);
    for (long v : {a, b, c}) EXPECT_TRUE(v >= 0 && v < kGridPoints) << line;
    ++lines;
  }
  EXPECT_EQ(lines, j["triangles"].get<std::size_t>());
  // Euler for a triangulated square with one hole: triangles = 2 n - h - 2 + 2 * holes (no holes in a DT):
  // a Delaunay triangulation of n points with h on the hull has 2 n - h - 2 triangles; hull = 80 grid points.
  EXPECT_EQ(lines, static_cast<std::size_t>(2 * kGridPoints - 80 - 2));
}

TEST_F(OutlineIoCli, CorruptFileFailsNamesTheFileAndWritesNothing) {
  const std::string bad = data("grid_hole_truncated.pcd");
  CliRun r = run("'" + bad + "' -o '" + out("o.json") + "' --svg '" + out("o.svg") + "' --png '" + out("o.png") +
                 "' --triangles '" + out("o.tri") + "'");
  EXPECT_NE(r.code, 0);
  EXPECT_NE(r.err.find(bad + ": byte "), std::string::npos) << r.err;
  EXPECT_NE(r.err.find("truncated data"), std::string::npos) << r.err;
  EXPECT_TRUE(r.out.empty());
  EXPECT_TRUE(fs::is_empty(dir / "out")) << "no output, not even a temp file";
  // Same for a text file with a bad number, and for a file that does not exist.
  std::ofstream(dir / "bad.xyz") << "0 0\n1 0\n0 one\n";
  r = run("'" + (dir / "bad.xyz").string() + "' -o '" + out("o.json") + "'");
  EXPECT_EQ(r.code, 2);  // a bad input file (docs/RUNNING.md, the failure contract)
  EXPECT_NE(r.err.find((dir / "bad.xyz").string() + ": line 3: bad number 'one'"), std::string::npos) << r.err;
  r = run("'" + (dir / "missing.ply").string() + "'");
  EXPECT_EQ(r.code, 2);
  EXPECT_NE(r.err.find("missing.ply"), std::string::npos) << r.err;
  // Collinear points are rejected by the core: the message names the file too.
  std::ofstream(dir / "line.xyz") << "0 0\n1 1\n2 2\n3 3\n";
  r = run("'" + (dir / "line.xyz").string() + "' -o '" + out("o.json") + "'");
  EXPECT_EQ(r.code, 2);
  EXPECT_NE(r.err.find((dir / "line.xyz").string()), std::string::npos) << r.err;
  EXPECT_TRUE(fs::is_empty(dir / "out"));
}

TEST_F(OutlineIoCli, BadOptionsExitTwoAndHelpTellsTheOptions) {
  const std::string in = "'" + data("grid_hole.xyz") + "'";
  for (const std::string& args :
       {in + " --mode fast", in + " --order random", in + " --alpha-radius -1", in + " --alpha-radius x",
        in + " --bogus", std::string(""), in + " " + in, in + " --alpha-radius 1 --auto-factor 2", in + " -o"}) {
    CliRun r = run(args);
    EXPECT_EQ(r.code, 2) << args;
    EXPECT_NE(r.err.find("hg-outline: "), std::string::npos) << args;
    EXPECT_TRUE(r.out.empty()) << args;
  }
  CliRun h = run("--help");
  EXPECT_EQ(h.code, 0);
  for (const char* opt : {"--alpha-radius", "--auto-factor", "--mode", "ordinary",       "ds",
                          "dshi",           "--order",       "as-is",  "hilbert",        "--outer-only",
                          "-o FILE",        "--svg",         "--png",  "--triangles",    "--draw-triangles",
                          ".pcd",           ".ply",          ".csv",   "points_skipped", "NaN"})
    EXPECT_NE(h.out.find(opt), std::string::npos) << opt;
}

TEST_F(OutlineIoCli, AlphaModeAndHoleRuleOptions) {
  const std::string in = "'" + data("grid_hole.xyz") + "'";
  for (const std::string& args : {in + " --alpha-mode tilted", in + " --alpha-mode local --alpha-radius 1",
                                  in + " --min-hole-spacings -1", in + " --min-hole-spacings x"}) {
    CliRun r = run(args);
    EXPECT_EQ(r.code, 2) << args;
    EXPECT_NE(r.err.find("hg-outline: "), std::string::npos) << args;
  }
  CliRun h = run("--help");
  for (const char* opt : {"--alpha-mode", "global", "local", "--min-hole-spacings"})
    EXPECT_NE(h.out.find(opt), std::string::npos) << opt;
  for (const char* mode : {"global", "local"}) {
    CliRun r = run(in + " --alpha-mode " + mode + " --min-hole-spacings 0");
    ASSERT_EQ(r.code, 0) << r.err;
    const auto j = nlohmann::json::parse(r.out);
    EXPECT_EQ(j["alpha_mode"].get<std::string>(), mode);
    EXPECT_EQ(j["holes_dropped"].get<int>(), 0);
    EXPECT_GT(j["spacing"].get<double>(), 0);
  }
}

TEST_F(OutlineIoCli, OuterOnlyKeepsTheHoleFilled) {
  CliRun r = run("'" + data("grid_hole.xyz") + "' --alpha-radius 1.5 --outer-only");
  ASSERT_EQ(r.code, 0) << r.err;
  auto j = nlohmann::json::parse(r.out);
  ASSERT_EQ(j["loops"].size(), 1u);
  EXPECT_NEAR(j["loops"][0]["area"].get<double>(), 400.0, 40);
}

namespace {

// An organized binary PCD (WIDTH 21 x HEIGHT 21, fields x y z) of the 20 x 20 square whose hole pixels
// (strictly inside [6, 14]^2) gave no return: NaN x y z there, as depth cameras write them.
std::string organized_square_with_nan_hole() {
  std::string s =
      "VERSION 0.7\nFIELDS x y z\nSIZE 4 4 4\nTYPE F F F\nCOUNT 1 1 1\nWIDTH 21\nHEIGHT 21\nPOINTS 441\nDATA binary\n";
  const float nan = std::nanf("");
  for (int j = 0; j <= 20; ++j)
    for (int i = 0; i <= 20; ++i) {
      const bool hole = i > 6 && i < 14 && j > 6 && j < 14;
      const float p[3] = {hole ? nan : static_cast<float>(i), hole ? nan : static_cast<float>(j), hole ? nan : 0.5f};
      s.append(reinterpret_cast<const char*>(p), sizeof p);
    }
  return s;
}

}  // namespace

TEST_F(OutlineIoCli, NoReturnPixelsAreSkippedAndCountedInJsonAndSummary) {
  std::ofstream(dir / "org.pcd", std::ios::binary) << organized_square_with_nan_hole();
  CliRun r = run("'" + (dir / "org.pcd").string() + "' --alpha-radius 1.5");
  ASSERT_EQ(r.code, 0) << r.err;
  auto j = nlohmann::json::parse(r.out);
  EXPECT_EQ(j["points_read"], 441);
  EXPECT_EQ(j["points_skipped"], 49);
  EXPECT_EQ(j["points_used"], kGridPoints);
  expect_square_with_hole(j, 441);  // the same outline as the fixture without the hole's pixels
  for (const auto& loop : j["loops"])
    for (const auto& idx : loop["point_index"]) {  // indices are file positions of returned pixels
      const int k = idx.get<int>(), i = k % 21, jj = k / 21;
      EXPECT_FALSE(i > 6 && i < 14 && jj > 6 && jj < 14) << k;
    }
  r = run("'" + (dir / "org.pcd").string() + "' --alpha-radius 1.5 -o '" + out("o.json") + "'");
  ASSERT_EQ(r.code, 0) << r.err;
  EXPECT_NE(r.out.find(": 441 points (49 skipped, " + std::to_string(kGridPoints) + " used), 1 outer loops, 1 holes"),
            std::string::npos)
      << r.out;
  // Text with NaN/Inf values: skipped the same way.
  std::ofstream(dir / "nan.xyz") << "0 0\nnan 1\n4 0\n2 inf\n0 4\n";
  r = run("'" + (dir / "nan.xyz").string() + "' --alpha-radius 100");
  ASSERT_EQ(r.code, 0) << r.err;
  j = nlohmann::json::parse(r.out);
  EXPECT_EQ(j["points_skipped"], 2);
  EXPECT_EQ(j["points_used"], 3);
}

TEST_F(OutlineIoCli, CollinearInSpaceAndTooFewFinitePointsAreErrors) {
  // A 3-D cloud on one line in space fails like the collinear 2-D cloud: exit 2 (a bad input file), the same message.
  std::ofstream(dir / "line3d.xyz") << "0 0 0\n1 2 3\n2 4 6\n3 6 9\n";
  std::ofstream(dir / "line2d.xyz") << "0 0\n1 2\n2 4\n3 6\n";
  const CliRun r3 = run("'" + (dir / "line3d.xyz").string() + "' -o '" + out("o.json") + "'");
  const CliRun r2 = run("'" + (dir / "line2d.xyz").string() + "' -o '" + out("o.json") + "'");
  EXPECT_EQ(r3.code, 2);
  EXPECT_EQ(r2.code, 2);
  const std::string msg = ": all 4 distinct points are collinear\n";
  EXPECT_EQ(r3.err, "hg-outline: error: " + (dir / "line3d.xyz").string() + msg);
  EXPECT_EQ(r2.err, "hg-outline: error: " + (dir / "line2d.xyz").string() + msg);
  EXPECT_TRUE(fs::is_empty(dir / "out"));
  // Fewer than 3 finite points.
  std::ofstream(dir / "few.xyz") << "0 0 1\nnan 0 1\n1 1 1\n0 inf 1\n";
  const CliRun f = run("'" + (dir / "few.xyz").string() + "'");
  EXPECT_EQ(f.code, 2);
  EXPECT_NE(f.err.find("few.xyz: need at least 3 distinct points, got 2 finite points (2 non-finite skipped)"),
            std::string::npos)
      << f.err;
}

namespace {

// A jittered grid of w x h points (spacing 1, noise up to 0.3 of it), full-precision doubles written with
// 17 significant digits, in scan-line order.
void write_jittered_grid(const fs::path& path, int w, int h, unsigned seed) {
  std::mt19937_64 rng(seed);
  std::uniform_real_distribution<double> jitter(-0.3, 0.3);
  std::ofstream f(path);
  f.precision(17);
  for (int y = 0; y < h; ++y)
    for (int x = 0; x < w; ++x) f << 1000.125 + x + jitter(rng) << ' ' << -2000.5 + y + jitter(rng) << '\n';
}

}  // namespace

TEST_F(OutlineIoCli, JsonSplitsTheSearchCostIntoPointLocationAndCavitySearch) {
  // search_cost = search_cost_locate + search_cost_cavity. Ordinary tests every live triangle for each
  // point: with the ghost triangles of the hull, m inserted points have 2m - 2 of them (Euler), so n
  // points cost sum_{m=3}^{n-1} (2m - 2) = n (n - 3) exactly. DSHI's walk from the previous insertion's
  // triangle visits a few triangles per point: with BRIO rounds as many on 19 200 points as on 1 200; in
  // scan order (as-is) a few more as the rows get longer, still a tiny fraction of ordinary's n - 3.
  for (unsigned seed : {1u, 2u, 3u}) {
    SCOPED_TRACE(seed);
    write_jittered_grid(dir / "small.xyz", 40, 30, seed);
    write_jittered_grid(dir / "large.xyz", 160, 120, seed);
    auto stats = [&](const std::string& file, const std::string& options) {
      const CliRun r = run("'" + (dir / file).string() + "' " + options);
      EXPECT_EQ(r.code, 0) << r.err;
      return nlohmann::json::parse(r.out);
    };
    for (const nlohmann::json& j : {stats("small.xyz", "--mode ordinary"), stats("small.xyz", "--mode dshi"),
                                    stats("large.xyz", "--mode dshi --order as-is")}) {
      ASSERT_TRUE(j.contains("search_cost_locate") && j.contains("search_cost_cavity")) << j.dump();
      EXPECT_EQ(j["search_cost"].get<std::uint64_t>(),
                j["search_cost_locate"].get<std::uint64_t>() + j["search_cost_cavity"].get<std::uint64_t>());
    }
    const nlohmann::json ord = stats("small.xyz", "--mode ordinary");
    const std::uint64_t n = ord["points_used"];
    ASSERT_EQ(n, 40u * 30u);
    EXPECT_EQ(ord["search_cost_locate"].get<std::uint64_t>(), n * (n - 3));
    for (const char* order : {"brio", "as-is"}) {
      const nlohmann::json small = stats("small.xyz", std::string("--mode dshi --order ") + order);
      const nlohmann::json large = stats("large.xyz", std::string("--mode dshi --order ") + order);
      const double per_small = small["search_cost_locate"].get<double>() / small["points_used"].get<double>();
      const double per_large = large["search_cost_locate"].get<double>() / large["points_used"].get<double>();
      SCOPED_TRACE(order);
      EXPECT_GE(per_small, 1.0);  // at least the triangle found
      EXPECT_LT(per_small, 16.0);
      EXPECT_LT(per_large, 16.0);
      if (std::string(order) == "brio") {
        EXPECT_LT(per_large, 1.25 * per_small) << "DSHI's walk must not grow with the number of points";
      }
      EXPECT_GT(small["search_cost_cavity"].get<std::uint64_t>(), 0u);
    }
  }
}
