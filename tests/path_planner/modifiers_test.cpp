// The path modifiers (path_planner/modifiers.hpp): a list composed from YAML, refused with the key when it
// is not usable, and each modifier's effect on sequenced passes against an independent expectation: the
// geometry of the arcs, the heights and kinds of the air moves, the robot bridge's corner rule.
#include <gtest/gtest.h>

#include "motion/motion.hpp"
#include "tests/path_planner/step_shapes.hpp"

namespace {

const std::string kCell = std::string(HG_SOURCE_DIR) + "/config/cell.yaml";

PlannerConfig config_of(const std::string& yaml) {
  return config_from(lookup_from({{"cell", kCell}}, hg::runtime::Config::from_string(yaml, "test.yaml")));
}

std::string config_error(const std::string& yaml) {
  try {
    config_of(yaml);
  } catch (const hg::runtime::ConfigError& e) {
    return e.what();
  }
  return "";
}

// A square outer loop and a square hole (0.2 m, 0.04 m), sequenced from (-1, -1).
ToolPath square_passes(const SequenceOptions& o) {
  Ring hole = rect(0.08, 0.08, 0.12, 0.12);
  std::reverse(hole.begin(), hole.end());
  const std::vector<GrindLoop> loops = {{resample_ring(rect(0, 0, 0.2, 0.2), 0.005, deg(10)), false, 0},
                                        {resample_ring(hole, 0.005, deg(10)), true, 1}};
  return ToolPath{sequence(loops, Vec2(-1, -1), o), Eigen::Isometry3d::Identity(), Vec3(-1, -1, 0.3)};
}

template <class M, class... A>
ToolPath applied(ToolPath p, A... args) {
  M(args...).apply(p);
  return p;
}

}  // namespace

TEST(PathPlannerModifiers, ListComposedFromYaml) {
  EXPECT_EQ(config_of("").modifiers, (std::vector<std::string>{"leads", "approach", "retract", "corner-speeds"}));
  EXPECT_EQ(config_of("path-modifiers: [leads, retract]\n").modifiers, (std::vector<std::string>{"leads", "retract"}));
  EXPECT_TRUE(config_of("path-modifiers: []\n").modifiers.empty());
  // On the command line, a,b,c; it wins over the file.
  EXPECT_EQ(config_from(lookup_from({{"cell", kCell}, {"path-modifiers", "approach,corner-speeds"}},
                                    hg::runtime::Config::from_string("path-modifiers: [leads]\n", "test.yaml")))
                .modifiers,
            (std::vector<std::string>{"approach", "corner-speeds"}));
  const JobParams job = config_of("").defaults;
  EXPECT_EQ(
      compose_modifiers(config_of("path-modifiers: [approach, corner-speeds]\n").modifiers, job, config_of("")).size(),
      2u);
  // The shipped file lists them all.
  const PlannerConfig shipped = config_from(lookup_from(
      {{"cell", kCell}}, hg::runtime::Config::load(std::string(HG_SOURCE_DIR) + "/config/path_planner.yaml")));
  EXPECT_EQ(shipped.modifiers, modifier_names());
}

TEST(PathPlannerModifiers, AnUnusableListIsRefusedNamingTheKey) {
  for (const auto& [yaml, what] : std::vector<std::pair<std::string, std::string>>{
           {"path-modifiers: [leads, spiral]\n", "unknown path modifier 'spiral'"},
           {"path-modifiers: [retract, approach]\n", "'approach' after 'retract'"},
           {"path-modifiers: [leads, leads]\n", "'leads' is listed twice"},
           {"path-modifiers: [[leads]]\n", "element 0"}}) {
    const std::string e = config_error(yaml);
    EXPECT_NE(e.find("test.yaml"), std::string::npos) << e;
    EXPECT_NE(e.find("path-modifiers"), std::string::npos) << e;
    EXPECT_NE(e.find(what), std::string::npos) << e;
  }
}

TEST(PathPlannerModifiers, SequencingAloneGivesTheLoopsAsGround) {
  SequenceOptions o;
  o.z = 0.002;
  const ToolPath p = square_passes(o);
  ASSERT_EQ(p.passes.size(), 2u);
  for (const Pass& pass : p.passes) {
    const auto& w = pass.waypoints;
    EXPECT_EQ(w.front().kind, kApproach);
    EXPECT_EQ(w.front().speed, o.approach_speed);
    EXPECT_EQ(w.front().position, w.back().position);  // round the loop to its start
    for (std::size_t i = 1; i < w.size(); ++i) {
      EXPECT_EQ(w[i].kind, kGrind);
      EXPECT_EQ(w[i].speed, o.grind_speed);
      EXPECT_EQ(w[i].position.z(), 0.002);
    }
  }
}

TEST(PathPlannerModifiers, LeadArcsAreTangentCircleArcsOnTheAirSide) {
  const SequenceOptions o;
  const ToolPath bare = square_passes(o);
  const double radius = 0.01, sweep = deg(90), speed = 0.013;
  const ToolPath led = applied<LeadArcs>(bare, radius, sweep, 0.001, speed);
  for (std::size_t e = 0; e < bare.passes.size(); ++e) {
    const Pass& b = bare.passes[e];
    const auto& w = led.passes[e].waypoints;
    const Vec2 p0 = b.waypoints.front().position.head<2>();
    // The radius: 0.3 x the radius of a circle of the hole's area (0.04^2 m^2: 6.8 mm) in the hole, else as given.
    const double r = b.hole ? 0.3 * std::sqrt(0.04 * 0.04 / kPi) : radius;
    const Vec2 centre = p0 + r * b.away;
    std::size_t in = 0, out = 0;
    for (const auto& x : w) {
      if (x.kind != kLeadIn && x.kind != kLeadOut && &x != &w.front()) continue;
      EXPECT_NEAR((x.position.head<2>() - centre).norm(), r, 1e-12);
      EXPECT_GE((x.position.head<2>() - p0).dot(b.away), -1e-15);  // on the air side of the edge's tangent
      EXPECT_EQ(x.orientation.coeffs(), b.waypoints.front().orientation.coeffs());
      (x.kind == kLeadOut ? out : in) += 1;
    }
    // The lead-in starts `sweep` round the circle from p0 and ends at p0 moving along the tangent.
    const Vec2 s = w.front().position.head<2>() - centre, q = p0 - centre;
    EXPECT_NEAR(std::acos(std::clamp(s.dot(q) / (r * r), -1.0, 1.0)), sweep, 1e-9);
    EXPECT_EQ(w.front().kind, kApproach);
    EXPECT_EQ(w.front().speed, o.approach_speed);
    const std::size_t end = in - 1;  // index of p0: the lead-in's points, then the loop
    EXPECT_EQ(w[end].position, b.waypoints.front().position);
    EXPECT_EQ(w[end].kind, kLeadIn);
    EXPECT_EQ(w[end].speed, speed);
    const Vec2 last_move = (w[end].position - w[end - 1].position).head<2>().normalized();
    EXPECT_GT(last_move.dot(b.tangent), std::cos(sweep / double(in - 1)));  // within one chord's turn
    EXPECT_EQ(w.size(), b.waypoints.size() + (in - 1) + out);
    EXPECT_EQ(w.back().kind, kLeadOut);
  }
}

TEST(PathPlannerModifiers, ApproachAndRetractAreVerticalMovesAtSafeHeight) {
  SequenceOptions o;
  o.z = 0.001;
  const ToolPath bare = square_passes(o);
  const ToolPath a = applied<Approach>(bare, 0.07, 0.25);
  const ToolPath r = applied<Retract>(bare, 0.06, 0.04);
  for (std::size_t e = 0; e < bare.passes.size(); ++e) {
    const auto& b = bare.passes[e].waypoints;
    const auto& wa = a.passes[e].waypoints;
    const auto& wr = r.passes[e].waypoints;
    ASSERT_EQ(wa.size(), b.size() + 1);
    ASSERT_EQ(wr.size(), b.size() + 1);
    EXPECT_EQ(wa[0].position, b.front().position + Vec3(0, 0, 0.07));
    EXPECT_EQ(wa[0].kind, e == 0 ? kApproach : kTravel);
    EXPECT_EQ(wa[0].loop, -1);
    EXPECT_EQ(wa[0].speed, 0.25);
    EXPECT_EQ(wr.back().position, b.back().position + Vec3(0, 0, 0.06));
    EXPECT_EQ(wr.back().kind, kRetract);
    EXPECT_EQ(wr.back().speed, 0.04);
    for (std::size_t i = 0; i < b.size(); ++i) {
      EXPECT_EQ(wa[i + 1].position, b[i].position);
      EXPECT_EQ(wr[i].position, b[i].position);
    }
  }
}

TEST(PathPlannerModifiers, CornerSpeedsMeetTheRobotBridgesCornerRule) {
  // Over random accelerations the lowered path passes the corner rule (motion::first_corner_fault, the check
  // the robot bridge makes), only speeds change, and speeds only go down.
  std::mt19937 rng(3);
  std::uniform_real_distribution<double> accel(0.05, 5);
  SequenceOptions o;
  o.grind_speed = 0.05;
  const ToolPath bare = applied<Retract>(
      applied<Approach>(applied<LeadArcs>(square_passes(o), 0.01, deg(90), 0.002, 0.05), 0.05, 0.3), 0.05, 0.05);
  for (int k = 0; k < 20; ++k) {
    const double a = accel(rng);
    const ToolPath slowed = applied<CornerSpeeds>(bare, a);
    const auto before = flatten(bare), after = flatten(slowed);
    ASSERT_EQ(before.size(), after.size());
    std::vector<Vec3> position;
    std::vector<double> speed;
    int lowered = 0;
    for (std::size_t i = 0; i < after.size(); ++i) {
      EXPECT_EQ(after[i].position, before[i].position);
      EXPECT_LE(after[i].speed, before[i].speed);
      lowered += after[i].speed < before[i].speed;
      position.push_back(after[i].position);
      speed.push_back(after[i].speed);
    }
    EXPECT_EQ(slowed.speeds_lowered, lowered);
    EXPECT_FALSE(hg::motion::first_corner_fault(position, speed, bare.start, a)) << "max_accel " << a;
  }
}

TEST(PathPlannerModifiers, PlanWithoutLeadsGrindsFromTheEntry) {
  // A plan with the list cut down to approach + retract: no lead kinds, every loop entered from above.
  PlannerConfig cfg = config_of("path-modifiers: [approach, retract, corner-speeds]\n");
  cfg.camera_to_base = pose_from_xyz_rpy(Vec3(0.5, 0, 1.2), Vec3(kPi, 0, 0));  // the plate at z = 0.01
  cfg.limits.workspace_min = Vec3(-1, -1, 0);
  cfg.limits.workspace_max = Vec3(2, 1, 1);
  cfg.limits.table_z = 0;
  OutlineInput in;
  in.plane = {Vec3(0, 0, 1.19), Vec3(1, 0, 0), Vec3(0, -1, 0), Vec3(0, 0, -1)};
  in.loops = {{false, rect(0, 0, 0.3, 0.1)}};
  const PlanResult r = plan(in, {}, cfg, std::nullopt);
  ASSERT_TRUE(r.ok) << r.reason;
  for (const auto& w : r.path) EXPECT_TRUE(w.kind != kLeadIn && w.kind != kLeadOut);
  ASSERT_GE(r.path.size(), 3u);
  EXPECT_EQ(r.path[0].kind, kApproach);
  EXPECT_EQ(r.path[1].kind, kApproach);
  EXPECT_EQ(r.path[2].kind, kGrind);
  EXPECT_EQ(r.path.back().kind, kRetract);
}
