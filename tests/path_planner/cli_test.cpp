// hg-plan: outline JSON file in, path.json out (the schema make run writes), errors and --help; the README's
// chain hg-gen -> hg-outline -> hg-plan -> hg-robot-export; config errors that name the file and key.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <fstream>
#include <random>
#include <set>
#include <sstream>
#include <sys/wait.h>

#include <Eigen/Geometry>
#include <nlohmann/json.hpp>

#include "tests/common/cell_file.hpp"

namespace {

std::string slurp_file(const std::string& path) {
  std::stringstream ss;
  ss << std::ifstream(path).rdbuf();
  return ss.str();
}

// Per-test names: CTest runs each TEST as its own process, possibly side by side.
std::string tmp(const std::string& name) {
  return testing::TempDir() + "/pp_cli_" + testing::UnitTest::GetInstance()->current_test_info()->name() + "_" + name;
}
void write(const std::string& path, const std::string& text) { std::ofstream(path) << text; }
// A cell file like the shipped one with another tool radius.
std::string cell_with_tool(double radius) {
  return hg::test::write_test_cell(tmp("cell_" + std::to_string(radius) + ".yaml"),
                                   [&](hg::cell::Cell& c) { c.tool.radius = radius; });
}
// hg-plan with the shipped cell file unless the arguments name one.
int run(const std::string& args, std::string* out = nullptr) {
  const std::string log = tmp("out.txt");
  const std::string cell = args.find("--cell ") == std::string::npos ? " --cell " + hg::test::shipped_cell() : "";
  const int rc = std::system((std::string(HG_BIN_DIR) + "/hg-plan " + args + cell + " >" + log + " 2>&1").c_str());
  if (out) {
    std::stringstream ss;
    ss << std::ifstream(log).rdbuf();
    *out = ss.str();
  }
  return WIFEXITED(rc) ? WEXITSTATUS(rc) : -1;
}

// 0.3 x 0.2 plate with a 60 x 40 mm cut-out, both as hg-outline would write them (outer CCW, hole CW). The
// cut-out's corners are R8 fillets (every 22.5 deg): a round tool cannot reach into sharp ones (coverage).
const char* kOutline = R"({"loops": [
  {"hole": false, "area": 0.06, "perimeter": 1.0, "points": [[0,0],[0.3,0],[0.3,0.2],[0,0.2]]},
  {"hole": true, "area": 0.0024, "perimeter": 0.2, "points": [[0.16,0.088],[0.159391,0.0849385],[0.1576569,0.0823431],[0.1550615,0.080609],[0.152,0.08],[0.108,0.08],[0.1049385,0.080609],[0.1023431,0.0823431],[0.100609,0.0849385],[0.1,0.088],[0.1,0.112],[0.100609,0.1150615],[0.1023431,0.1176569],[0.1049385,0.119391],[0.108,0.12],[0.152,0.12],[0.1550615,0.119391],[0.1576569,0.1176569],[0.159391,0.1150615],[0.16,0.112]]}]})";

}  // namespace

TEST(PathPlannerCli, WritesThePathSchema) {
  write(tmp("outline.json"), kOutline);
  std::string out;
  ASSERT_EQ(run(tmp("outline.json") + " --job-id j1 --cell " + cell_with_tool(0.005) + " -o " + tmp("path.json"), &out),
            0)
      << out;
  nlohmann::json j = nlohmann::json::parse(std::ifstream(tmp("path.json")));
  EXPECT_EQ(j["job_id"], "j1");
  EXPECT_EQ(j["frame"], "robot_base");
  ASSERT_TRUE(j["waypoints"].is_array());
  int grind_loops[2] = {0, 0};
  for (const auto& w : j["waypoints"]) {
    ASSERT_EQ(w["position"].size(), 3u);
    ASSERT_EQ(w["orientation"].size(), 4u);
    double n = 0;
    for (double q : w["orientation"]) n += q * q;
    EXPECT_NEAR(n, 1, 1e-9);
    EXPECT_GT(w["speed"].get<double>(), 0);
    const std::string kind = w["kind"];
    EXPECT_TRUE(kind == "approach" || kind == "lead_in" || kind == "grind" || kind == "lead_out" || kind == "retract" ||
                kind == "travel")
        << kind;
    if (kind == "grind") ++grind_loops[w["loop"].get<int>()];
  }
  EXPECT_GT(grind_loops[0], 0);
  EXPECT_GT(grind_loops[1], 0);
  EXPECT_DOUBLE_EQ(j["tool_radius"].get<double>(), 0.005);
}

TEST(PathPlannerCli, FailuresAndHelp) {
  std::string out;
  EXPECT_EQ(run("--help", &out), 0);
  EXPECT_NE(out.find("usage: hg-plan"), std::string::npos);
  EXPECT_NE(out.find("--small-hole"), std::string::npos);
  write(tmp("bad.json"), "{\"loops\": [{\"points\": [[0, 0], [1]]}]}");
  EXPECT_EQ(run(tmp("bad.json"), &out), 2);
  EXPECT_NE(out.find("loops[0].points[1]"), std::string::npos) << out;
  write(tmp("outline.json"), kOutline);
  const std::string big_tool = cell_with_tool(0.03);
  EXPECT_EQ(run(tmp("outline.json") + " --cell " + big_tool, &out), 1);  // 40 mm hole, 60 mm tool
  EXPECT_NE(out.find("hole 1 is too small"), std::string::npos) << out;
  EXPECT_EQ(run(tmp("outline.json") + " --cell " + big_tool + " --small-hole skip -o " + tmp("p2.json"), &out), 0)
      << out;
  EXPECT_NE(out.find("warning: skipped"), std::string::npos) << out;
  const std::string small_box =
      hg::test::write_test_cell(tmp("box.yaml"), [](hg::cell::Cell& c) { c.workspace_max.x() = 0.6; });
  EXPECT_EQ(run(tmp("outline.json") + " --cell " + small_box, &out), 1);
  EXPECT_NE(out.find("outside the workspace box"), std::string::npos) << out;
  EXPECT_EQ(run(tmp("outline.json") + " --no_such_option 1", &out), 2);
}

// The shipped config file is read whole (every key known to hg-plan); a bad one stops hg-plan with exit 2
// and one line naming the file, the key and what is wrong; the command line beats the file.
TEST(PathPlannerCli, ConfigFileErrorsNameTheFileAndKey) {
  std::string out;
  write(tmp("outline.json"), kOutline);
  const std::string shipped = std::string(HG_SOURCE_DIR) + "/config/path_planner.yaml";
  // (its coverage policy fails this outline's tight hole corners: skip, so that the run must succeed)
  ASSERT_EQ(run("--config " + shipped + " --small-hole skip " + tmp("outline.json") + " -o " + tmp("p.json"), &out), 0)
      << out;
  struct Case {
    std::string yaml, expected;
  } cases[] = {
      {"safe_height: 0.05\n", "line 1: key 'safe_height': old spelling of 'safe-height'"},
      {"grind-speed: 0.02\nsafe-heigt: 0.05\n", "line 2: key 'safe-heigt': unknown key (nearest known: 'safe-height')"},
      {"step: -0.01\n", "key 'step': -0.01 is out of range ([1e-04, 0.05])"},  // the quantity's one range
      // The tool is the cell's: no parameter (runtime/quantities.hpp names it tool_radius, tilt).
      {"tool-radius: 0.01\n",
       "key 'tool-radius': moved: it lives in the cell file (--cell, default config/cell.yaml), key tool.radius"},
      {"spindle-clockwise: sometimes\n", "key 'spindle-clockwise': 'sometimes' is not true or false"},
      {"camera-xyz: [0.5, 0, 1.2]\n",
       "key 'camera-xyz': moved: it lives in the cell file (--cell, default "
       "config/cell.yaml), key calibration.camera-to-base"},
      {"plane-u: [1, zero, 0]\n", "key 'plane-u': element 1 is not a number"},
      {"small-hole: ignore\n", "key 'small-hole': 'ignore' is not one of fail | skip"},
  };
  for (const Case& c : cases) {
    const std::string file = tmp("bad.yaml");
    write(file, c.yaml);
    EXPECT_EQ(run("--config " + file + " " + tmp("outline.json"), &out), 2) << c.yaml;
    EXPECT_NE(out.find("config '" + file + "'"), std::string::npos) << out;
    EXPECT_NE(out.find(c.expected), std::string::npos) << out;
    EXPECT_EQ(std::count(out.begin(), out.end(), '\n'), 1) << out;  // one line
  }
  EXPECT_EQ(run(tmp("outline.json") + " --safe_height 0.05", &out), 2);
  EXPECT_NE(out.find("--safe_height is the old spelling of --safe-height"), std::string::npos) << out;
  // Precedence: the file's value over the default, the command line's over the file's (the grind speed: the
  // fastest grind waypoint; corners only lower it).
  write(tmp("r.yaml"), "grind-speed: 0.015\nsmall-hole: skip\n");
  ASSERT_EQ(run("--config " + tmp("r.yaml") + " " + tmp("outline.json") + " -o " + tmp("f.json"), &out), 0) << out;
  ASSERT_EQ(
      run("--config " + tmp("r.yaml") + " --grind-speed 0.012 " + tmp("outline.json") + " -o " + tmp("c.json"), &out),
      0);
  ASSERT_EQ(run(tmp("outline.json") + " --small-hole skip -o " + tmp("d.json"), &out), 0) << out;  // 10 mm: skip
  auto grind_speed = [](const std::string& path) {
    std::stringstream ss;
    ss << std::ifstream(path).rdbuf();
    double fastest = 0;
    const nlohmann::json planned = nlohmann::json::parse(ss.str());
    for (const auto& w : planned["waypoints"])
      if (w["kind"] == "grind") fastest = std::max(fastest, w["speed"].get<double>());
    return fastest;
  };
  EXPECT_EQ(grind_speed(tmp("f.json")), 0.015);
  EXPECT_EQ(grind_speed(tmp("c.json")), 0.012);
  EXPECT_EQ(grind_speed(tmp("d.json")), 0.02);  // the declared default
  // The tool is the cell's: the path carries the cell's tool radius and tilt.
  const nlohmann::json d = nlohmann::json::parse(std::ifstream(tmp("d.json")));
  const hg::cell::Cell cell = hg::cell::read_cell(hg::test::shipped_cell());
  EXPECT_EQ(d["tool_radius"].get<double>(), cell.tool.radius);
  EXPECT_EQ(d["tilt"].get<double>(), cell.tool.tilt);
}

// A value that contradicts the cell file stops hg-plan with exit 2 and one line naming the option, its value,
// the cell file and the cell's key and value; a broken cell file names the file and the key.
TEST(PathPlannerCli, ContradictingTheCellExits2NamingBoth) {
  std::string out;
  write(tmp("outline.json"), kOutline);
  const hg::cell::Cell cell = hg::cell::read_cell(hg::test::shipped_cell());
  ASSERT_EQ(cell.max_speed, 0.25);  // the expectations below are written for the shipped cell
  const std::string c = hg::test::shipped_cell();
  struct Case {
    std::string args, expected;
  } cases[] = {
      {"--travel-speed 0.4", "command line: --travel-speed: 0.4 exceeds " + c + " max-speed 0.25"},
      {"--grind-speed 0.26", "command line: --grind-speed: 0.26 exceeds " + c + " max-speed 0.25"},
      {"--approach-speed 1", "command line: --approach-speed: 1 exceeds " + c + " max-speed 0.25"},
      {"--tool-radius 0.005",
       "--tool-radius moved: it lives in the cell file (--cell, default config/cell.yaml), key tool.radius"},
      {"--chamfer-angle 0.5", "unknown option --chamfer-angle"},  // a chamfer is no tilt: the tilt is the cell's
      {"--base-frame base",
       "--base-frame moved: it lives in the cell file (--cell, default config/cell.yaml), key frames.base"},
      {"--max-speed 0.1",
       "--max-speed moved: it lives in the cell file (--cell, default config/cell.yaml), key max-speed"},
      {"--table-z -0.5", "--table-z moved: it lives in the cell file (--cell, default config/cell.yaml), key table-z"},
  };
  for (const Case& k : cases) {
    EXPECT_EQ(run(k.args + " " + tmp("outline.json"), &out), 2) << k.args;
    EXPECT_NE(out.find(k.expected), std::string::npos) << out;
    EXPECT_EQ(std::count(out.begin(), out.end(), '\n'), 1) << out;
  }
  // The same values in a config file name the config file, its line and key, and the cell.
  write(tmp("fast.yaml"), "step: 0.002\ntravel-speed: 0.4\n");
  EXPECT_EQ(run("--config " + tmp("fast.yaml") + " " + tmp("outline.json"), &out), 2);
  EXPECT_NE(out.find("config '" + tmp("fast.yaml") + "' line 2: key 'travel-speed': 0.4 exceeds " + c + " max-speed"),
            std::string::npos)
      << out;
  // Equal to the cell is no contradiction.
  EXPECT_EQ(run("--travel-speed 0.25 --small-hole skip " + tmp("outline.json") + " -o " + tmp("eq.json"), &out), 0)
      << out;
  // A broken cell file: exit 2, the file and the key.
  std::string text = slurp_file(c);
  text.replace(text.find("max-accel: 2.0"), 14, "max-accel: fast");
  write(tmp("broken.yaml"), text);
  EXPECT_EQ(run("--cell " + tmp("broken.yaml") + " " + tmp("outline.json"), &out), 2);
  EXPECT_NE(out.find(tmp("broken.yaml") + ": max-accel: expected a number, got 'fast'"), std::string::npos) << out;
}

namespace {

std::string slurp(const std::string& path) {
  std::stringstream ss;
  ss << std::ifstream(path).rdbuf();
  return ss.str();
}
int run_tool(const std::string& command, std::string* out) {
  const std::string log = tmp("tool.txt");
  const int rc = std::system((std::string(HG_BIN_DIR) + "/" + command + " >" + log + " 2>&1").c_str());
  *out = slurp(log);
  return WIFEXITED(rc) ? WEXITSTATUS(rc) : -1;
}
double segment_distance(double px, double py, const nlohmann::json& a, const nlohmann::json& b) {
  const double ax = a[0], ay = a[1], dx = double(b[0]) - ax, dy = double(b[1]) - ay;
  const double L2 = dx * dx + dy * dy;
  const double t = L2 == 0 ? 0 : std::clamp(((px - ax) * dx + (py - ay) * dy) / L2, 0.0, 1.0);
  return std::hypot(ax + t * dx - px, ay + t * dy - py);
}
double ring_distance(double px, double py, const nlohmann::json& ring) {
  double d = INFINITY;
  for (std::size_t i = 0; i < ring.size(); ++i)
    d = std::min(d, segment_distance(px, py, ring[i], ring[(i + 1) % ring.size()]));
  return d;
}

}  // namespace

// The README's chain on a generated 3-D cloud (table frame = robot base frame, table top at z = 0):
// hg-gen -> hg-outline -> hg-plan --outline-frame robot_base -> hg-robot-export. Without the flag
// hg-plan takes the cloud as the camera's view and fails, printing the transform and the workspace box.
// The grind waypoints are checked against hg-gen's ground truth: a tool radius from the true edge, on the
// plate's top surface.
TEST(PathPlannerCli, ChainOnAGenerated3dCloudInTheBaseFrame) {
  const double pitch = 0.002, noise = 0.0002, radius = 0.006;
  // Along the edges: the outline runs through the outermost pixel centres, within one pitch inside the true
  // edge (the planner's edge compensation, given the pitch, moves it out by about half of that), plus
  // noise; at the corners, which the alpha shape and the smoothing round off, within two pitches.
  const double tolerance = pitch + 4 * noise, corner_tolerance = 2 * pitch;
  for (int seed : {1, 2, 3}) {
    SCOPED_TRACE("seed " + std::to_string(seed));
    const std::string cloud = tmp("cloud.xyz"), outline = tmp("o.json"), path = tmp("p.json"),
                      script = tmp("job.script");
    std::string out;
    ASSERT_EQ(run_tool("hg-gen --shape plate-hole-slot --pitch 0.002 --noise 0.0002 --depth-noise 0.0005 --seed " +
                           std::to_string(seed) + " -o " + cloud,
                       &out),
              0)
        << out;
    ASSERT_EQ(run_tool("hg-outline " + cloud + " -o " + outline, &out), 0) << out;
    const nlohmann::json o = nlohmann::json::parse(slurp(outline));
    EXPECT_EQ(o["frame"], "cloud");
    ASSERT_TRUE(o.contains("plane")) << "a cloud with depth noise is projected onto its plane";

    const std::string cell = cell_with_tool(radius);  // the shipped cell with this test's tool
    EXPECT_EQ(run_tool("hg-plan " + outline + " --cell " + cell + " -o " + path, &out), 1) << out;
    EXPECT_NE(out.find("camera-to-base applied: [1 0 0 0.5; 0 -1 0 0; 0 0 -1 1.2; 0 0 0 1]"), std::string::npos)
        << out;  // the shipped cell's calibration
    EXPECT_NE(out.find("outside the workspace box (-1.0000, -1.0000, 0.0000) .. (1.5000, 1.0000, 1.0000)"),
              std::string::npos)
        << out;
    EXPECT_NE(out.find("--outline-frame robot_base"), std::string::npos) << out;

    ASSERT_EQ(run_tool("hg-plan " + outline + " --outline-frame robot_base --cell " + cell + " -o " + path, &out), 0)
        << out;
    EXPECT_NE(out.find("camera-to-base applied: none (identity)"), std::string::npos) << out;
    ASSERT_EQ(run_tool("hg-robot-export --config " + std::string(HG_SOURCE_DIR) + "/config/robot_bridge.yaml --cell " +
                           cell + " -o " + script + " " + path,
                       &out),
              0)
        << out;

    const nlohmann::json p = nlohmann::json::parse(slurp(path));
    const nlohmann::json truth = nlohmann::json::parse(slurp(cloud + ".truth.json"))["parts"][0];
    const double top = truth["thickness"];
    const std::string s = slurp(script);
    std::size_t moves = 0;
    for (std::size_t at = s.find("  move"); at != std::string::npos; at = s.find("  move", at + 1)) ++moves;
    EXPECT_EQ(moves, p["waypoints"].size()) << "one move per waypoint in the exported script";
    std::vector<double> errors;
    for (const auto& w : p["waypoints"]) {
      if (w["kind"] != "grind") continue;
      const double x = w["position"][0], y = w["position"][1], z = w["position"][2];
      double d = ring_distance(x, y, truth["outer"]);
      for (const auto& h : truth["holes"]) d = std::min(d, ring_distance(x, y, h));
      ASSERT_NEAR(d, radius, corner_tolerance) << "grind waypoint at (" << x << ", " << y << ")";
      errors.push_back(std::abs(d - radius));
      ASSERT_NEAR(z, top, 4 * 0.0005 / std::sqrt(1000.0) + 1e-4)
          << "on the plate's top surface (plane fit of ~20k points)";
    }
    ASSERT_GT(errors.size(), 300u);
    std::nth_element(errors.begin(), errors.begin() + long(errors.size() * 9 / 10), errors.end());
    EXPECT_LT(errors[errors.size() * 9 / 10], tolerance) << "90 % of the grind waypoints a tool radius from the edge";
  }
}

namespace {

// Grind loops of a path file: the distinct loop indices of its grind waypoints.
std::set<int> ground_loops(const nlohmann::json& path) {
  std::set<int> loops;
  for (const auto& w : path["waypoints"])
    if (w["kind"] == "grind") loops.insert(w["loop"].get<int>());
  return loops;
}

}  // namespace

// Issue 23: a new user's chain with the shipped cell (10 mm tool) and no --pixel-pitch: hg-plan takes the
// spacing from the outline ("spacing") and every loop of every bundled sample is ground, the 40 mm slots
// (two tool diameters) included. Before, both samples failed (unreached stretches of their holes; demo-scene
// called its 40 mm slot too small for the tool).
TEST(PathPlannerCli, EveryBundledSamplePlansWithTheShippedCell) {
  for (const std::string sample : {"plate-hole-slot-low", "demo-scene"}) {
    SCOPED_TRACE(sample);
    const std::string outline = tmp(sample + ".json"), path = tmp(sample + ".path.json");
    std::string out;
    ASSERT_EQ(
        run_tool("hg-outline " + std::string(HG_SOURCE_DIR) + "/data/samples/" + sample + ".xyz -o " + outline, &out),
        0)
        << out;
    ASSERT_EQ(run(outline + " --outline-frame robot_base -o " + path, &out), 0) << out;
    EXPECT_NE(out.find("(the outline's point spacing)"), std::string::npos) << out;
    EXPECT_EQ(out.find("warning"), std::string::npos) << out;
    const nlohmann::json o = nlohmann::json::parse(slurp(outline));
    const std::set<int> ground = ground_loops(nlohmann::json::parse(slurp(path)));
    EXPECT_EQ(ground.size(), o["loops"].size()) << "every loop ground";
  }
}

// Issue 23: a 300 x 200 mm plate with a D60 hole, tilted 20 deg about x and 10 deg about y, seen on a 2 mm
// camera grid in the base frame with 0.2 mm in-plane and 0.5 mm depth noise, plans with the shipped cell
// (before: "pixel pitch unknown ... at a concave corner or bend tighter than the tool"), and every grind
// waypoint lies on the plate's plane.
TEST(PathPlannerCli, NoisyTilted3dCloudPlansWithTheShippedCell) {
  const double a = 20 * M_PI / 180, b = 10 * M_PI / 180, p = 0.002;
  const Eigen::Vector3d n(std::sin(b) * std::cos(a), -std::sin(a), std::cos(b) * std::cos(a));
  const Eigen::Vector3d ex(std::cos(b), 0, -std::sin(b)), ey = n.cross(ex);
  const Eigen::Vector3d centre(0.5, 0, 0.2);
  for (int seed : {1, 2, 3}) {
    SCOPED_TRACE("seed " + std::to_string(seed));
    std::mt19937 rng(seed);
    std::normal_distribution<double> in_plane(0, 0.0002), depth(0, 0.0005);
    std::ofstream cloud(tmp("tilted.xyz"));
    cloud.precision(9);
    for (int i = -120; i <= 120; ++i)
      for (int j = -120; j <= 120; ++j) {
        const double X = i * p, Y = j * p, Z = -(n.x() * X + n.y() * Y) / n.z();
        const Eigen::Vector3d q(X, Y, Z);
        const double u = q.dot(ex), v = q.dot(ey);
        if (std::abs(u) > 0.15 || std::abs(v) > 0.1 || u * u + v * v < 0.03 * 0.03) continue;
        cloud << centre.x() + X + in_plane(rng) << ' ' << centre.y() + Y + in_plane(rng) << ' '
              << centre.z() + Z + depth(rng) << '\n';
      }
    cloud.close();
    std::string out;
    ASSERT_EQ(run_tool("hg-outline " + tmp("tilted.xyz") + " -o " + tmp("tilted.json"), &out), 0) << out;
    ASSERT_EQ(run(tmp("tilted.json") + " --outline-frame robot_base -o " + tmp("tilted.path.json"), &out), 0) << out;
    const nlohmann::json path = nlohmann::json::parse(slurp(tmp("tilted.path.json")));
    EXPECT_EQ(ground_loops(path).size(), 2u) << "the outer edge and the hole";
    for (const auto& w : path["waypoints"]) {
      if (w["kind"] != "grind") continue;
      const Eigen::Vector3d q(w["position"][0], w["position"][1], w["position"][2]);
      ASSERT_NEAR((q - centre).dot(n), 0, 1e-3) << "a grind waypoint off the plate's plane";
    }
  }
}

// Issue 23: a noise-free flat cloud (every z equal: the plate's top at 12 mm in robot base coordinates)
// planned with --outline-frame robot_base lands on its own points: hg-outline writes its plane z = 12 mm, and
// the grind waypoints are a tool radius from the true edge at that height (before: no plane, the camera's
// default plane put the path 0.5 m off in x and 2 mm below). A 2-D outline (no z, no plane) in the base frame
// is on that frame's z = 0.
TEST(PathPlannerCli, FlatCloudInTheBaseFrameIsPlannedOnItsOwnPlane) {
  std::string out;
  ASSERT_EQ(run_tool("hg-gen --shape plate-hole-slot --pitch 0.002 -o " + tmp("flat.xyz"), &out), 0) << out;
  ASSERT_EQ(run_tool("hg-outline " + tmp("flat.xyz") + " -o " + tmp("flat.json"), &out), 0) << out;
  const nlohmann::json o = nlohmann::json::parse(slurp(tmp("flat.json")));
  ASSERT_TRUE(o.contains("plane")) << "a flat 3-D cloud has its plane z = its z";
  ASSERT_EQ(run(tmp("flat.json") + " --outline-frame robot_base -o " + tmp("flat.path.json"), &out), 0) << out;
  const nlohmann::json truth = nlohmann::json::parse(slurp(tmp("flat.xyz") + ".truth.json"))["parts"][0];
  const double top = truth["thickness"];
  std::size_t grind = 0;
  const nlohmann::json path = nlohmann::json::parse(slurp(tmp("flat.path.json")));
  for (const auto& w : path["waypoints"]) {
    if (w["kind"] != "grind") continue;
    ++grind;
    const double x = w["position"][0], y = w["position"][1], z = w["position"][2];
    double d = ring_distance(x, y, truth["outer"]);
    for (const auto& h : truth["holes"]) d = std::min(d, ring_distance(x, y, h));
    ASSERT_NEAR(d, 0.01, 0.004) << "grind waypoint at (" << x << ", " << y << ")";
    ASSERT_NEAR(z, top, 1e-9);
  }
  EXPECT_GT(grind, 300u);
  // The same loops without plane and z: x, y of the base frame on z = 0 (the table top: the grind points
  // 5 mm above it, --z-offset, to be above the table).
  nlohmann::json two_d = o;
  two_d.erase("plane");
  write(tmp("flat2d.json"), two_d.dump());
  ASSERT_EQ(
      run(tmp("flat2d.json") + " --outline-frame robot_base --z-offset 0.005 -o " + tmp("flat2d.path.json"), &out), 0)
      << out;
  EXPECT_NE(out.find("its loops are x, y of robot_base, on z = 0"), std::string::npos) << out;
  const nlohmann::json path2d = nlohmann::json::parse(slurp(tmp("flat2d.path.json")));
  EXPECT_EQ(ground_loops(path2d).size(), 3u);
  for (const auto& w : path2d["waypoints"])
    if (w["kind"] == "grind") ASSERT_NEAR(w["position"][2].get<double>(), 0.005, 1e-9);
}
