// What the station makes of the bus for the page (station/live.hpp): the cloud and outline placed in the
// base frame for both mountings (eye-in-hand: base<-flange x camera-to-flange with the capture's flange
// pose, as the planner places them), and the plan's smoothed edge. Expectations are computed here from the
// quaternion formula and plain 4x4 arithmetic, not with the code under test; random poses over many seeds.
#include <gtest/gtest.h>

#include <array>
#include <cmath>
#include <cstring>
#include <random>

#include "station/live.hpp"

namespace hg::station {
namespace {

using Mat4 = std::array<std::array<double, 4>, 4>;

// Rotation of a unit quaternion (w, x, y, z) by its textbook formula, with a translation.
Mat4 pose(const double q[4], const double t[3]) {
  const double w = q[0], x = q[1], y = q[2], z = q[3];
  return {{{1 - 2 * (y * y + z * z), 2 * (x * y - w * z), 2 * (x * z + w * y), t[0]},
           {2 * (x * y + w * z), 1 - 2 * (x * x + z * z), 2 * (y * z - w * x), t[1]},
           {2 * (x * z - w * y), 2 * (y * z + w * x), 1 - 2 * (x * x + y * y), t[2]},
           {0, 0, 0, 1}}};
}

Mat4 mul(const Mat4& a, const Mat4& b) {
  Mat4 c{};
  for (int i = 0; i < 4; ++i)
    for (int j = 0; j < 4; ++j)
      for (int k = 0; k < 4; ++k) c[i][j] += a[i][k] * b[k][j];
  return c;
}

std::array<double, 3> transform_point(const Mat4& m, const std::array<double, 3>& p) {
  std::array<double, 3> out{};
  for (int i = 0; i < 3; ++i) out[i] = m[i][0] * p[0] + m[i][1] * p[1] + m[i][2] * p[2] + m[i][3];
  return out;
}

Eigen::Isometry3d isometry(const Mat4& m) {
  Eigen::Isometry3d t = Eigen::Isometry3d::Identity();
  for (int i = 0; i < 3; ++i)
    for (int j = 0; j < 4; ++j) t.matrix()(i, j) = m[i][j];
  return t;
}

struct Random {
  std::mt19937 rng;
  explicit Random(unsigned seed) : rng(seed) {}
  double uniform(double a, double b) { return std::uniform_real_distribution<double>(a, b)(rng); }
  void quaternion(double q[4]) {
    double n = 0;
    for (int i = 0; i < 4; ++i) n += (q[i] = uniform(-1, 1)) * q[i];
    for (int i = 0; i < 4; ++i) q[i] /= std::sqrt(n);
  }
  void vector(double v[3], double r) {
    for (int i = 0; i < 3; ++i) v[i] = uniform(-r, r);
  }
};

// A plate cloud and its outline (one square loop) on a random plane in the camera frame.
struct Capture {
  hullgrind::plate_cloud_t cloud{};
  hullgrind::outline_t outline{};
  double flange_q[4], flange_t[3];

  Capture(Random& r, bool flange_valid) {
    r.quaternion(flange_q);
    r.vector(flange_t, 1.0);
    double axes_q[4], zero[3] = {0, 0, 0};
    r.quaternion(axes_q);
    const Mat4 axes = pose(axes_q, zero);  // columns: u axis, v axis, normal
    double origin[3];
    r.vector(origin, 0.5);
    for (auto* m : {&cloud.plane_origin, &outline.plane_origin}) std::memcpy(*m, origin, sizeof origin);
    for (int i = 0; i < 3; ++i) {
      cloud.plane_u_axis[i] = outline.plane_u_axis[i] = axes[i][0];
      cloud.plane_v_axis[i] = outline.plane_v_axis[i] = axes[i][1];
    }
    cloud.header.seq = 7;
    cloud.n = 50;
    for (int i = 0; i < cloud.n; ++i) {
      cloud.u.push_back(float(r.uniform(-0.3, 0.3)));
      cloud.v.push_back(float(r.uniform(-0.2, 0.2)));
      cloud.part.push_back(0);
    }
    outline.header.seq = 3;
    outline.cloud_seq = cloud.header.seq;
    hullgrind::outline_loop_t loop{};
    loop.u = {-0.25, 0.25, 0.25, -0.25};
    loop.v = {-0.15, -0.15, 0.15, 0.15};
    loop.n = 4;
    outline.loops.push_back(loop);
    outline.num_loops = 1;
    cloud.flange_valid = outline.flange_valid = flange_valid;
    std::memcpy(cloud.flange_position, flange_t, sizeof flange_t);
    std::memcpy(outline.flange_position, flange_t, sizeof flange_t);
    std::memcpy(cloud.flange_orientation, flange_q, sizeof flange_q);
    std::memcpy(outline.flange_orientation, flange_q, sizeof flange_q);
  }

  std::array<double, 3> camera_point(double u, double v) const {
    std::array<double, 3> p{};
    for (int i = 0; i < 3; ++i) p[i] = cloud.plane_origin[i] + u * cloud.plane_u_axis[i] + v * cloud.plane_v_axis[i];
    return p;
  }
};

// The cloud frame's points (docs/station.md: "HGC1", uint32 n, int64 seq, float32 xyz * n).
std::vector<std::array<float, 3>> frame_points(const std::string& f) {
  EXPECT_EQ(f.substr(0, 4), "HGC1");
  std::uint32_t n;
  std::memcpy(&n, f.data() + 4, 4);
  EXPECT_EQ(f.size(), 16 + 12 * std::size_t(n));
  std::vector<std::array<float, 3>> out(n);
  std::memcpy(out.data(), f.data() + 16, 12 * std::size_t(n));
  return out;
}

hullgrind::grind_path_t one_waypoint_plan(const std::string& job) {
  hullgrind::grind_path_t p{};
  p.job_id = job;
  p.outline_seq = 3;
  p.n = 1;
  p.position = {{0, 0, 0}};
  p.orientation = {{1, 0, 0, 0}};
  p.speed = {0};
  p.kind = {0};
  p.loop_index = {0};
  return p;
}

void expect_near(const std::array<double, 3>& want, double x, double y, double z, double tol, int seed) {
  EXPECT_NEAR(x, want[0], tol) << "seed " << seed;
  EXPECT_NEAR(y, want[1], tol) << "seed " << seed;
  EXPECT_NEAR(z, want[2], tol) << "seed " << seed;
}

TEST(StationLive, EyeInHandCloudAndOutlineArePlacedWithTheCapturesFlangePose) {
  for (int seed = 0; seed < 200; ++seed) {
    Random r(seed);
    double cf_q[4], cf_t[3];
    r.quaternion(cf_q);
    r.vector(cf_t, 0.2);
    const Mat4 camera_to_flange = pose(cf_q, cf_t);
    LiveOptions o;
    o.camera_to_base = Eigen::Isometry3d(Eigen::Translation3d(5, 5, 5));  // must not be used
    o.camera_to_flange = isometry(camera_to_flange);
    LiveState live(o);
    const Capture c(r, true);
    const Mat4 to_base = mul(pose(c.flange_q, c.flange_t), camera_to_flange);
    live.on_cloud(c.cloud, 1000);
    live.on_outline(c.outline, 2000);
    live.on_path(one_waypoint_plan("j"), 3000);

    auto frame = live.cloud_for("j");
    ASSERT_TRUE(frame) << "seed " << seed;
    const auto pts = frame_points(*frame);
    ASSERT_EQ(pts.size(), std::size_t(c.cloud.n));
    for (std::size_t i = 0; i < pts.size(); ++i)
      expect_near(transform_point(to_base, c.camera_point(c.cloud.u[i], c.cloud.v[i])), pts[i][0], pts[i][1], pts[i][2],
                  1e-5, seed);
    const Json loop = live.job("j")["outline"]["loops"][0]["xyz"];
    ASSERT_EQ(loop.size(), 12u);
    for (int k = 0; k < 4; ++k)
      expect_near(transform_point(to_base, c.camera_point(c.outline.loops[0].u[k], c.outline.loops[0].v[k])),
                  loop[3 * k], loop[3 * k + 1], loop[3 * k + 2], 1e-9, seed);
  }
}

TEST(StationLive, FixedCameraUsesTheCellsCameraToBaseAndIgnoresAFlangePose) {
  for (int seed = 0; seed < 50; ++seed) {
    Random r(1000 + seed);
    double q[4], t[3];
    r.quaternion(q);
    r.vector(t, 2.0);
    LiveOptions o;
    o.camera_to_base = isometry(pose(q, t));
    LiveState live(o);
    const Capture c(r, true);  // a flange pose on the message: not this cell's business
    live.on_cloud(c.cloud, 1000);
    const auto pts = frame_points(*live.cloud_for(""));
    for (std::size_t i = 0; i < pts.size(); ++i)
      expect_near(transform_point(pose(q, t), c.camera_point(c.cloud.u[i], c.cloud.v[i])), pts[i][0], pts[i][1],
                  pts[i][2], 1e-5, seed);
  }
}

TEST(StationLive, EyeInHandCaptureWithoutAFlangePoseIsDrawnNowhereAndSaysWhy) {
  Random r(5);
  LiveOptions o;
  o.camera_to_flange = Eigen::Isometry3d::Identity();
  LiveState live(o);
  Capture c(r, false);
  live.on_cloud(c.cloud, 1000);
  EXPECT_EQ(live.cloud_for(""), nullptr);
  c.outline.flange_valid = true;
  c.outline.flange_orientation[0] = 2;  // not a unit quaternion
  live.on_outline(c.outline, 2000);
  live.on_path(one_waypoint_plan("j"), 3000);
  const Json outline = live.job("j")["outline"];
  EXPECT_TRUE(outline["loops"].empty());
  EXPECT_NE(outline["placement_error"].get<std::string>().find("unit quaternion"), std::string::npos);
  std::vector<std::string> events;
  bool lost = false;
  live.events_since(0, events, lost);
  ASSERT_FALSE(events.empty());
  EXPECT_NE(events.front().find("no flange pose"), std::string::npos) << events.front();
}

TEST(StationLive, ThePlansSmoothedEdgeIsKeptPerLoopAndCarriesTheUnreachedStretches) {
  for (int seed = 0; seed < 100; ++seed) {
    Random r(2000 + seed);
    hullgrind::grind_path_t p = one_waypoint_plan("j");
    std::vector<int> counts;
    for (int loop = 0; loop < 3; ++loop) {
      counts.push_back(8 + int(r.uniform(0, 60)));  // chords within 8 % of the radius
      const double radius = r.uniform(0.02, 0.3), z = r.uniform(-0.1, 0.1);
      for (int i = 0; i < counts.back(); ++i) {
        const double a = 2 * M_PI * i / counts.back();
        p.edge.push_back({radius * std::cos(a), radius * std::sin(a), z});
        p.edge_loop.push_back(std::int16_t(loop));
      }
    }
    p.num_edge_points = std::int32_t(p.edge.size());
    hullgrind::edge_stretch_t s{};
    s.loop_index = 1;
    s.start = r.uniform(0, 0.05);
    s.length = r.uniform(0.001, 0.05);
    p.unreached = {s};
    p.num_unreached = 1;
    const Json plan = plan_json(p, nullptr);
    ASSERT_EQ(plan["edge"].size(), 3u) << "seed " << seed;
    std::size_t k = 0;
    for (int loop = 0; loop < 3; ++loop) {
      const Json& e = plan["edge"][loop];
      EXPECT_EQ(e["loop_index"], loop);
      ASSERT_EQ(e["xyz"].size(), 3u * counts[loop]);
      for (int i = 0; i < counts[loop]; ++i, ++k)
        for (int d = 0; d < 3; ++d) EXPECT_EQ(e["xyz"][3 * i + d].get<double>(), p.edge[k][d]);
    }
    // The stretch lies on loop 1's ring (no outline given): every point at that ring's radius, and its
    // polyline as long as the stretch (up to the chords of the ring).
    const Json& xyz = plan["unreached"][0]["xyz"];
    ASSERT_GE(xyz.size(), 6u) << "seed " << seed;
    const double radius = std::hypot(plan["edge"][1]["xyz"][0].get<double>(), plan["edge"][1]["xyz"][1].get<double>());
    double length = 0;
    for (std::size_t i = 0; i < xyz.size(); i += 3) {
      EXPECT_LE(std::hypot(xyz[i].get<double>(), xyz[i + 1].get<double>()), radius + 1e-9);
      EXPECT_GE(std::hypot(xyz[i].get<double>(), xyz[i + 1].get<double>()), radius * 0.9);
      if (i >= 3)
        length += std::hypot(xyz[i].get<double>() - xyz[i - 3].get<double>(),
                             xyz[i + 1].get<double>() - xyz[i - 2].get<double>());
    }
    EXPECT_NEAR(length, s.length, 1e-9) << "seed " << seed;
  }
}

// A START this station sent is a job of the live state at once (REQUESTED, its part), whatever the bus's round
// trip takes; the first status from a process replaces that state, and a job nobody started here and
// nobody reported stays unknown.
TEST(StationLive, AStartThisStationSentIsKnownAsRequestedUntilAProcessAnswers) {
  LiveState live(LiveOptions{});
  hullgrind::job_request_t r{};
  r.job_id = "st-abc";
  r.part_id = "plate-7";
  r.action = hullgrind::job_request_t::ACTION_START;
  live.on_requested(r, 1000);
  const Json j = live.job("st-abc");
  ASSERT_TRUE(j.is_object());
  EXPECT_EQ(j["state"], "REQUESTED");
  EXPECT_EQ(j["part_id"], "plate-7");
  EXPECT_TRUE(j["statuses"].empty());
  EXPECT_EQ(live.jobs().size(), 1u);
  EXPECT_TRUE(live.job("st-other").is_null());

  hullgrind::job_status_t s{};
  s.job_id = "st-abc";
  s.part_id = "plate-7";
  s.source = "hg-robot-bridge";
  s.state = hullgrind::job_status_t::STATE_ACCEPTED;
  live.on_status(s, 2000);
  EXPECT_EQ(live.job("st-abc")["state"], "ACCEPTED");
  live.on_requested(r, 3000);  // the same request again (a retried POST): the answer stays
  EXPECT_EQ(live.job("st-abc")["state"], "ACCEPTED");
}

}  // namespace
}  // namespace hg::station
