// hg-plan: outline JSON file in, path.json out (the schema make run writes), errors and --help.
#include <gtest/gtest.h>

#include <cmath>
#include <cstdio>
#include <fstream>
#include <sstream>
#include <sys/wait.h>

#include <nlohmann/json.hpp>

namespace {

// Per-test names: CTest runs each TEST as its own process, possibly side by side.
std::string tmp(const std::string& name) {
  return testing::TempDir() + "/pp_cli_" + testing::UnitTest::GetInstance()->current_test_info()->name() + "_" + name;
}
void write(const std::string& path, const std::string& text) { std::ofstream(path) << text; }
int run(const std::string& args, std::string* out = nullptr) {
  const std::string log = tmp("out.txt");
  const int rc = std::system((std::string(HG_BIN_DIR) + "/hg-plan " + args + " >" + log + " 2>&1").c_str());
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
  ASSERT_EQ(run(tmp("outline.json") + " --job-id j1 --tool_radius 0.005 -o " + tmp("path.json"), &out), 0) << out;
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
    EXPECT_TRUE(kind == "approach" || kind == "lead_in" || kind == "grind" || kind == "lead_out" ||
                kind == "retract" || kind == "travel")
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
  EXPECT_NE(out.find("--small_hole"), std::string::npos);
  write(tmp("bad.json"), "{\"loops\": [{\"points\": [[0, 0], [1]]}]}");
  EXPECT_EQ(run(tmp("bad.json"), &out), 2);
  EXPECT_NE(out.find("loops[0].points[1]"), std::string::npos) << out;
  write(tmp("outline.json"), kOutline);
  EXPECT_EQ(run(tmp("outline.json") + " --tool_radius 0.03", &out), 1);  // 40 mm hole, 60 mm tool
  EXPECT_NE(out.find("hole 1 is too small"), std::string::npos) << out;
  EXPECT_EQ(run(tmp("outline.json") + " --tool_radius 0.03 --small_hole skip -o " + tmp("p2.json"), &out), 0) << out;
  EXPECT_NE(out.find("warning: skipped"), std::string::npos) << out;
  EXPECT_EQ(run(tmp("outline.json") + " --workspace_max 0.6,1,1", &out), 1);
  EXPECT_NE(out.find("outside the workspace box"), std::string::npos) << out;
  EXPECT_EQ(run(tmp("outline.json") + " --no_such_option 1", &out), 2);
}
