// The outline file (outline_io/outline_file.hpp): random outlines written and read back exactly, hg-outline's
// JSON read by the same reader, and every defect reported with the file and the key that holds it.
#include <gtest/gtest.h>

#include <cmath>
#include <random>
#include <string>

#include "outline_io/outline_file.hpp"
#include "outline_io/outline_writers.hpp"

using namespace hg::outline_io;
using Json = nlohmann::json;

namespace {

// A random outline: up to 5 loops of 0..40 points over many magnitudes, with or without plane, frame, spacing.
OutlineFile random_outline(std::mt19937_64& rng) {
  std::uniform_real_distribution<double> unit(-1, 1), expo(-12, 6);
  auto number = [&] { return unit(rng) * std::pow(10.0, expo(rng)); };
  OutlineFile f;
  if (rng() % 2) f.frame = std::string("frame_") + char('a' + rng() % 26);
  if (rng() % 2) f.spacing = std::abs(number()) + 1e-300;
  if (rng() % 2)
    f.plane = Plane{{number(), number(), number()},
                    {number(), number(), number()},
                    {number(), number(), number()},
                    {number(), number(), number()}};
  const int loops = int(rng() % 6);
  for (int k = 0; k < loops; ++k) {
    OutlineLoop l{rng() % 2 == 0, {}};
    const int n = int(rng() % 41);
    for (int i = 0; i < n; ++i) l.points.push_back({number(), number()});
    f.loops.push_back(std::move(l));
  }
  return f;
}

void expect_equal(const OutlineFile& a, const OutlineFile& b) {
  EXPECT_EQ(a.frame, b.frame);
  EXPECT_EQ(a.spacing, b.spacing);
  ASSERT_EQ(a.plane.has_value(), b.plane.has_value());
  if (a.plane) {
    EXPECT_EQ(a.plane->origin, b.plane->origin);
    EXPECT_EQ(a.plane->normal, b.plane->normal);
    EXPECT_EQ(a.plane->u, b.plane->u);
    EXPECT_EQ(a.plane->v, b.plane->v);
  }
  ASSERT_EQ(a.loops.size(), b.loops.size());
  for (std::size_t k = 0; k < a.loops.size(); ++k) {
    EXPECT_EQ(a.loops[k].hole, b.loops[k].hole);
    ASSERT_EQ(a.loops[k].points.size(), b.loops[k].points.size());
    for (std::size_t i = 0; i < a.loops[k].points.size(); ++i) {
      EXPECT_EQ(a.loops[k].points[i].x, b.loops[k].points[i].x);  // exact: the text keeps every bit
      EXPECT_EQ(a.loops[k].points[i].y, b.loops[k].points[i].y);
    }
  }
}

// The reader's message for `text`, or "" when it reads.
std::string error_of(const std::string& text) {
  try {
    parse_outline_file(text, "f.json");
  } catch (const ReadError& e) {
    return e.what();
  }
  return "";
}

}  // namespace

TEST(OutlineFile, RoundTripOfRandomOutlinesIsExact) {
  for (std::uint64_t seed = 0; seed < 300; ++seed) {
    std::mt19937_64 rng(seed);
    const OutlineFile f = random_outline(rng);
    SCOPED_TRACE("seed " + std::to_string(seed));
    expect_equal(parse_outline_file(outline_file_json(f).dump(rng() % 2 ? 1 : -1), "f.json"), f);
  }
}

TEST(OutlineFile, ADefectNamesTheFileAndItsKey) {
  // Each seed: a valid random file with one defect put in a random place; the message names that place.
  int checked = 0;
  for (std::uint64_t seed = 0; seed < 200; ++seed) {
    std::mt19937_64 rng(seed);
    OutlineFile f = random_outline(rng);
    if (f.loops.empty()) f.loops.push_back({false, {{0, 0}, {1, 0}, {0, 1}}});
    Json j = Json::parse(outline_file_json(f).dump());
    std::string key;
    const std::size_t k = rng() % f.loops.size();
    switch (rng() % 5) {
      case 0: {
        if (f.loops[k].points.empty()) continue;
        const std::size_t i = rng() % f.loops[k].points.size();
        j["loops"][k]["points"][i] = rng() % 2 ? Json::array({"x", 1}) : Json::array({1, 2, 3});
        key = "loops[" + std::to_string(k) + "].points[" + std::to_string(i) + "]";
        break;
      }
      case 1: j["loops"][k]["hole"] = "yes", key = "loops[" + std::to_string(k) + "].hole"; break;
      case 2: j["loops"][k].erase("points"), key = "loops[" + std::to_string(k) + "].points"; break;
      case 3: j["spacing"] = -1, key = "spacing"; break;
      default:
        j["plane"] = {{"origin", {0, 0, 0}}, {"normal", {0, 0, "one"}}, {"u", {1, 0, 0}}, {"v", {0, 1, 0}}};
        key = "plane.normal";
    }
    const std::string e = error_of(j.dump());
    EXPECT_EQ(e.rfind("f.json: " + key + ": ", 0), 0u) << "seed " << seed << ": " << e;
    ++checked;
  }
  EXPECT_GT(checked, 150);
  EXPECT_EQ(error_of("{\"loops\": [").rfind("f.json: byte 12: not JSON: ", 0), 0u);  // 11 bytes: at the end
  EXPECT_EQ(error_of("{}").rfind("f.json: loops: ", 0), 0u);
  EXPECT_EQ(error_of("[]").rfind("f.json: (top level): ", 0), 0u);
  EXPECT_EQ(error_of("{\"loops\": [], \"frame\": 3}").rfind("f.json: frame: ", 0), 0u);
  EXPECT_EQ(error_of("{\"loops\": [], \"unknown\": {\"x\": 1}}"), "");  // other keys are ignored
}

TEST(OutlineFile, HgOutlinesJsonIsAnOutlineFile) {
  // The writer of hg-outline, the job recorder and hg-overview (outline_json) adds its statistics to the
  // outline file: the reader finds the same loops, plane, frame and spacing in it.
  hg::outline::Result r;
  r.spacing = 0.0021;
  r.loops.push_back({false, 1, 4, {{0, 0}, {1, 0}, {1, 1}, {0, 1}}, {0, 1, 2, 3}});
  r.loops.push_back({true, 0.01, 0.4, {{0.4, 0.4}, {0.4, 0.5}, {0.5, 0.5}, {0.5, 0.4}}, {4, 5, 6, 7}});
  PlanarPoints planar;
  planar.projected = true;
  planar.plane = {{0, 0, 1.19}, {0, 0, -1}, {1, 0, 0}, {0, -1, 0}};
  RunInfo info;
  info.frame = "camera";
  const OutlineFile f = parse_outline_file(outline_json(r, planar, info).dump(1), "hg-outline.json");
  EXPECT_EQ(f.frame, "camera");
  EXPECT_EQ(f.spacing, 0.0021);
  ASSERT_TRUE(f.plane);
  EXPECT_EQ(f.plane->normal, (std::array<double, 3>{0, 0, -1}));
  EXPECT_EQ(f.plane->v, (std::array<double, 3>{0, -1, 0}));
  ASSERT_EQ(f.loops.size(), 2u);
  EXPECT_FALSE(f.loops[0].hole);
  EXPECT_TRUE(f.loops[1].hole);
  EXPECT_EQ(f.loops[1].points[2].x, 0.5);
  EXPECT_EQ(f.loops[1].points[1].y, 0.5);
}
