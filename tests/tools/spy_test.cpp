// tools/spy shows large messages: on a headless X server (Xvfb), lcm-spy as tools/spy starts it decodes
// 1 MB plate clouds (more fragments than the kernel's default UDP receive buffer holds). Runs in its own
// network namespace.
#include <gtest/gtest.h>
#include <sys/stat.h>

#include <unistd.h>

#include <chrono>
#include <filesystem>
#include <fstream>
#include <lcm/lcm-cpp.hpp>
#include <sstream>
#include <thread>

#include "hullgrind/plate_cloud_t.hpp"
#include "tests/common/child_process.hpp"

namespace {

using namespace std::chrono_literals;

const char* kUrl = "udpm://239.255.76.67:7667?ttl=0";

std::string slurp(const std::string& path) {
  std::stringstream ss;
  ss << std::ifstream(path).rdbuf();
  return ss.str();
}
bool exists(const std::string& path) {
  struct stat st {};
  return ::stat(path.c_str(), &st) == 0;
}
template <class F>
bool eventually(F done, std::chrono::seconds limit) {
  const auto end = std::chrono::steady_clock::now() + limit;
  while (std::chrono::steady_clock::now() < end) {
    if (done()) return true;
    std::this_thread::sleep_for(50ms);
  }
  return done();
}

// 1 MB on the wire: 100 000 points of u, v (float) and part (int16).
hullgrind::plate_cloud_t big_cloud(int seq) {
  hullgrind::plate_cloud_t c{};
  c.header.seq = seq;
  c.header.frame_id = "camera";
  c.n = 100000;
  for (int i = 0; i < c.n; ++i) {
    c.u.push_back(float(i % 400) * 0.001f);
    c.v.push_back(float(i / 400) * 0.001f);
    c.part.push_back(0);
  }
  c.num_parts = 1;
  return c;
}

}  // namespace

TEST(ToolsSpy, DecodesAOneMegabyteCloudHeadless) {
  // A folder of this process's own: /tmp is shared with other tests and earlier runs, and an old spy.out
  // would answer the wait below before this spy has written a line.
  const std::string dir = testing::TempDir() + "hg-spy-test-" + std::to_string(getpid());
  std::filesystem::create_directories(dir);
  // A display with neither a lock nor a socket: a socket left by an Xvfb that died would pass the wait for
  // this one's.
  int display = 90;
  while (exists("/tmp/.X" + std::to_string(display) + "-lock") || exists("/tmp/.X11-unix/X" + std::to_string(display)))
    ++display;
  const std::string d = ":" + std::to_string(display);
  hg::test::ChildProcess xvfb(
      {"Xvfb", d, "-screen", "0", "1024x768x24", "-nolisten", "tcp"},
      hg::test::ChildOptions().search_in_path().stdout_to(dir + "/xvfb.log").stderr_to(dir + "/xvfb.log"));
  ASSERT_TRUE(xvfb.started());
  ASSERT_TRUE(eventually([&] { return exists("/tmp/.X11-unix/X" + std::to_string(display)); }, 30s))
      << slurp(dir + "/xvfb.log");

  const std::string out = dir + "/spy.out";
  hg::test::ChildProcess spy({std::string(HG_SOURCE_DIR) + "/tools/spy", "--lcm-url", kUrl, "--build",
                              std::string(HG_BIN_DIR) + "/..", "--check", "HG_PLATE_CLOUD", "3", "120"},
                             hg::test::ChildOptions().set_env("DISPLAY", d).stdout_to(out).stderr_to(dir + "/spy.err"));
  ASSERT_TRUE(spy.started());
  // The spy prints its URL once its LCM listens with the enlarged buffer.
  ASSERT_TRUE(eventually([&] { return slurp(out).find("spy: ") != std::string::npos || spy.wait().has_value(); }, 120s))
      << slurp(dir + "/spy.err");
  ASSERT_NE(slurp(out).find("UDP receive buffer"), std::string::npos) << slurp(out) << slurp(dir + "/spy.err");

  lcm::LCM lcm(kUrl);
  ASSERT_TRUE(lcm.good());
  std::optional<int> code;
  for (int seq = 0; seq < 20 && !code; ++seq) {  // three decoded end the check; the rest is slack for startup
    hullgrind::plate_cloud_t c = big_cloud(seq);
    ASSERT_GE(c.getEncodedSize(), 1000000);
    ASSERT_EQ(lcm.publish("HG_PLATE_CLOUD", &c), 0);
    code = spy.wait(500ms);
  }
  if (!code) code = spy.wait(30s);
  ASSERT_TRUE(code.has_value()) << "the spy did not finish: " << slurp(out);
  EXPECT_EQ(*code, 0) << slurp(out) << slurp(dir + "/spy.err");
  EXPECT_NE(slurp(out).find("decoded as hullgrind.plate_cloud_t, n = 100000"), std::string::npos) << slurp(out);
  if (!HasFailure()) std::filesystem::remove_all(dir);  // kept when something failed, to read
}
