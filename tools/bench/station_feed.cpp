// hg-bench-station-feed: the camera of tools/bench/station_bench.py. Reads one point cloud file (hg-gen's
// 1.59 M-point preset high-4, binary PCD) and, for every START on HG_JOB_REQUEST, publishes it as one
// plate_cloud_t on HG_PLATE_CLOUD, lying flat under the simulated cell's camera (config/cell-sim.yaml: at
// 0.5, 0, 1.5 m looking down), centred on its optical axis. The pipeline's camera bridge renders clouds of
// at most ~0.2 M points; this puts a cloud of the size the station's speed targets name through the same
// outline service, planner, robot bridge and station. --rate HZ publishes it at a camera's rate instead, from
// the start and whatever the jobs (tools/bench/foxglove_bench.py). A benchmark tool, not a test.
#include <lcm/lcm-cpp.hpp>

#include <algorithm>
#include <chrono>
#include <csignal>
#include <cstdio>
#include <limits>
#include <string>

#include "outline_io/cloud.hpp"
#include "hullgrind/job_request_t.hpp"
#include "hullgrind/plate_cloud_t.hpp"
#include "runtime/channels.hpp"
#include "runtime/params.hpp"
#include "runtime/version.hpp"

namespace {

volatile std::sig_atomic_t g_stop = 0;
void on_signal(int) { g_stop = 1; }

const char* kUsageHead =
    "usage: hg-bench-station-feed --cloud FILE [options]\n"
    "Publishes FILE (.pcd/.ply/.xyz, metres) as one plate_cloud_t on HG_PLATE_CLOUD for every job_request_t\n"
    "START heard on HG_JOB_REQUEST: the points' x, y as the plane's u, v, centred, the plane --distance metres\n"
    "from the camera along its optical axis; with --rate HZ > 0 instead HZ times a second from the start, as a\n"
    "free-running camera. Runs until SIGINT/SIGTERM, then prints how many it published. For\n"
    "tools/bench/station_bench.py and tools/bench/foxglove_bench.py.\n";

std::vector<hg::runtime::Param> feed_params() {
  using namespace hg::runtime;
  std::vector<Param> params = {
      text_param("cloud", "", "point cloud file, .pcd/.ply/.xyz, metres (required)"),
      text_param("lcm-url", "", "LCM URL (default: $LCM_DEFAULT_URL, else LCM's)"),
      number_param("distance", "1.49", "camera to plane along the optical axis, m", 0,
                   std::numeric_limits<double>::infinity(), true),
      number_param("rate", "0", "clouds per second from the start (0: one per START)", 0, 100)};
  set_value_names(params, {{"cloud", "FILE"}, {"lcm-url", "URL"}, {"distance", "M"}, {"rate", "HZ"}});
  return params;
}

// The cloud as a plate_cloud_t in the camera frame: plane normal towards the camera (-z), u = camera x,
// v = normal x u = -y (the bridge's convention), points centred on the optical axis.
hullgrind::plate_cloud_t plate_cloud(const hg::outline_io::Cloud& c, double distance) {
  double lo[2] = {std::numeric_limits<double>::max(), std::numeric_limits<double>::max()};
  double hi[2] = {-lo[0], -lo[1]};
  for (std::size_t i = 0; i < c.size(); ++i)
    for (int k = 0; k < 2; ++k) lo[k] = std::min(lo[k], c.xyz[3 * i + k]), hi[k] = std::max(hi[k], c.xyz[3 * i + k]);
  hullgrind::plate_cloud_t m{};
  m.header.frame_id = "camera";
  m.plane_origin[2] = distance;
  m.plane_normal[2] = -1;
  m.plane_u_axis[0] = 1;
  m.plane_v_axis[1] = -1;
  m.thickness = 0.01;
  for (std::size_t i = 0; i < c.size(); ++i) {
    m.u.push_back(float(c.xyz[3 * i] - 0.5 * (lo[0] + hi[0])));
    m.v.push_back(float(c.xyz[3 * i + 1] - 0.5 * (lo[1] + hi[1])));
  }
  m.n = std::int32_t(m.u.size());
  m.part.assign(m.u.size(), 0);
  m.num_parts = 1;
  return m;
}

struct Feed {
  lcm::LCM* lcm;
  hullgrind::plate_cloud_t cloud;
  bool quiet = false;  // --rate: no line per cloud
  void send_cloud(const std::string& why) {
    cloud.header.utime =
        std::chrono::duration_cast<std::chrono::microseconds>(std::chrono::system_clock::now().time_since_epoch())
            .count();
    cloud.source_frame_seq = cloud.header.seq;
    lcm->publish(hg::channels::kPlateCloud, &cloud);
    if (!quiet) {
      std::printf("published cloud %lld (%d points) %s\n", static_cast<long long>(cloud.header.seq), cloud.n,
                  why.c_str());
      std::fflush(stdout);
    }
    ++cloud.header.seq;
  }
  void on_request(const lcm::ReceiveBuffer*, const std::string&, const hullgrind::job_request_t* r) {
    if (r->action == hullgrind::job_request_t::ACTION_START && !quiet) send_cloud("for job " + r->job_id);
  }
};

// --rate: a cloud every 1/rate s on a fixed schedule (a late one does not shift the next), LCM served between.
void run_at_rate(Feed& feed, lcm::LCM& lcm, double rate) {
  using clock = std::chrono::steady_clock;
  const auto period = std::chrono::duration_cast<clock::duration>(std::chrono::duration<double>(1 / rate));
  auto next = clock::now();
  while (!g_stop) {
    if (clock::now() >= next) {
      feed.send_cloud("");
      next += period;
      continue;
    }
    auto wait = std::chrono::duration_cast<std::chrono::milliseconds>(next - clock::now()).count();
    lcm.handleTimeout(static_cast<int>(std::clamp<long long>(wait, 1, 200)));
  }
}

}  // namespace

int main(int argc, char** argv) {
  hg::runtime::Params p(feed_params());
  if (const int rc =
          hg::runtime::parse_tool(p, argc, argv, "hg-bench-station-feed", hg::runtime::usage_with(kUsageHead));
      rc >= 0)
    return rc;
  const std::string file = p.text("cloud"), url = p.text("lcm-url");
  const double distance = p.number("distance"), rate = p.number("rate");
  if (file.empty() || !p.positional().empty()) {
    std::fprintf(stderr, "hg-bench-station-feed: command line: %s (see --help)\n",
                 file.empty() ? "need --cloud FILE" : ("unexpected argument '" + p.positional()[0] + "'").c_str());
    return hg::runtime::kExitBadInput;
  }
  Feed feed{};
  try {
    feed.cloud = plate_cloud(hg::outline_io::read_cloud_file(file), distance);
  } catch (const std::exception& e) {
    std::fprintf(stderr, "hg-bench-station-feed: %s\n", e.what());
    return hg::runtime::kExitBadInput;
  }
  lcm::LCM lcm(url);
  if (!lcm.good()) {
    std::fprintf(stderr, "hg-bench-station-feed: LCM failed to start (%s)\n", url.c_str());
    return 1;
  }
  feed.lcm = &lcm;
  lcm.subscribe(hg::channels::kJobRequest, &Feed::on_request, &feed);
  std::signal(SIGINT, on_signal);
  std::signal(SIGTERM, on_signal);
  std::printf("listening: %d points from %s\n", feed.cloud.n, file.c_str());
  std::fflush(stdout);
  feed.quiet = rate > 0;
  if (feed.quiet) run_at_rate(feed, lcm, rate);
  else
    while (!g_stop) lcm.handleTimeout(200);
  std::printf("published %lld clouds\n", static_cast<long long>(feed.cloud.header.seq));
  return 0;
}
