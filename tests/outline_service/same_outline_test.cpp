// hg-outline and hg-outline-service decide holes with the one rule of the outline core: on one cloud
// (with 3x3 dropout gaps the rule drops, and real cut-outs) both give the same loops.
#include <gtest/gtest.h>

#include <unistd.h>

#include <cstdio>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <string>

#include <nlohmann/json.hpp>

#include "tools/bench/core/synthetic_clouds.hpp"
#include "outline_service/outline_service.hpp"

namespace {

hullgrind::plate_cloud_t plate_cloud(const std::vector<hg::outline::Vec2>& pts) {
  hullgrind::plate_cloud_t c{};
  c.status = hullgrind::plate_cloud_t::STATUS_OK;
  c.n = int32_t(pts.size());
  for (const auto& p : pts) {
    c.u.push_back(float(p.x));
    c.v.push_back(float(p.y));
    c.part.push_back(0);
  }
  return c;
}

}  // namespace

TEST(OutlineSameRule, HgOutlineAndTheServiceGiveTheSameOutline) {
  const auto dir = std::filesystem::temp_directory_path() / ("hg_same_outline_" + std::to_string(getpid()));
  std::filesystem::create_directories(dir);
  for (const char* mode : {"global", "local"})
    for (std::uint64_t seed : {1, 2}) {
      SCOPED_TRACE(std::string(mode) + " seed " + std::to_string(seed));
      hg::outline::synth::PlateSpec spec;
      spec.W = 150, spec.H = 90, spec.hole_diameters = {5, 8, 12};
      spec.uniform_amp = 0.3, spec.dropout = 0.04, spec.clustered = 0.02, spec.seed = seed;
      const auto plate = hg::outline::synth::make_plate(spec);
      const hullgrind::plate_cloud_t cloud = plate_cloud(plate.points);
      // The very floats the service reads, written in full (17 digits) so that the reader gets them back exactly.
      const auto xyz = dir / "cloud.xyz", json = dir / "outline.json";
      {
        std::ofstream f(xyz);
        char line[96];
        for (std::size_t i = 0; i < cloud.u.size(); ++i) {
          std::snprintf(line, sizeof line, "%.17g %.17g\n", double(cloud.u[i]), double(cloud.v[i]));
          f << line;
        }
      }
      const std::string cmd = std::string(HG_BIN_DIR) + "/hg-outline '" + xyz.string() + "' --alpha-mode " + mode +
                              " -o '" + json.string() + "' > /dev/null";
      ASSERT_EQ(std::system(cmd.c_str()), 0) << cmd;
      const nlohmann::json cli = nlohmann::json::parse(std::ifstream(json));

      hg::outline_service::ServiceOptions opt;  // the service's defaults, as its parameter table gives them
      opt.alpha_mode = hg::outline::parse_alpha_mode(mode);
      for (const auto& p : hg::outline_service::process_info().params)
        if (p.name == "min-hole-spacings") opt.min_hole_spacings = std::stod(p.default_value);
      const auto svc = hg::outline_service::compute(cloud, opt);
      ASSERT_EQ(svc.outline.status, +hullgrind::outline_t::STATUS_OK) << svc.outline.error_text;

      EXPECT_GT(svc.holes_dropped, 0) << "the cloud should exercise the hole rule";
      EXPECT_EQ(cli["holes_dropped"].get<int>(), svc.holes_dropped);
      ASSERT_EQ(cli["loops"].size(), svc.outline.loops.size());
      for (std::size_t k = 0; k < svc.outline.loops.size(); ++k) {
        const auto& a = cli["loops"][k];
        const auto& b = svc.outline.loops[k];
        EXPECT_EQ(a["hole"].get<bool>(), b.hole);
        ASSERT_EQ(a["points"].size(), std::size_t(b.n));
        for (int i = 0; i < b.n; ++i) {
          EXPECT_EQ(a["points"][i][0].get<double>(), b.u[i]);
          EXPECT_EQ(a["points"][i][1].get<double>(), b.v[i]);
        }
      }
      // And the truth: one plate, its three cut-outs (4 % dropout with 3x3 gaps, +-0.3 noise).
      int holes = 0;
      for (const auto& l : svc.outline.loops) holes += l.hole;
      EXPECT_EQ(holes, 3);
      EXPECT_EQ(int(svc.outline.loops.size()) - holes, 1);
    }
  std::filesystem::remove_all(dir);
}
