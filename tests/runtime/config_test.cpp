// runtime::Config: YAML files read into nested keys with typed lookups; a bad file names the file.
#include <gtest/gtest.h>

#include <unistd.h>

#include <string>
#include <vector>

#include "runtime/config.hpp"
#include "tests/common/temp_file.hpp"

namespace hr = hg::runtime;

namespace {

TEST(RuntimeConfig, NestedKeysAndTypes) {
  auto c = hr::Config::from_string("robot:\n  speed: 0.25\n  name: ur10e\n  box: [1, 2.5, -3]\nn: 7\n");
  EXPECT_EQ(c.get_double("robot.speed").value(), 0.25);
  EXPECT_EQ(c.get_string("robot.name").value(), "ur10e");
  EXPECT_EQ(c.get_double("n").value(), 7);
  EXPECT_EQ(c.get_doubles("robot.box").value(), (std::vector<double>{1, 2.5, -3}));
  EXPECT_FALSE(c.get_double("robot.missing").has_value());
  EXPECT_FALSE(c.has("nothing.here"));
  EXPECT_THROW(c.get_double("robot.name"), hr::ConfigError);
  EXPECT_THROW(c.get_doubles("robot.speed"), hr::ConfigError);
}

TEST(RuntimeConfig, CommentsAreNotPartOfValues) {
  auto c = hr::Config::from_string(
      "# a config\nspeed: 0.25   # m/s\nname: \"a # b\"  # quoted hash stays\nlist: [1, 2] # two\n");
  EXPECT_EQ(c.get_double("speed").value(), 0.25);
  EXPECT_EQ(c.get_string("name").value(), "a # b");
  EXPECT_EQ(c.get_doubles("list").value(), (std::vector<double>{1, 2}));
}

TEST(RuntimeConfig, BadFileNamesTheFile) {
  try {
    hr::Config::load("/nonexistent/hg.yaml");
    FAIL() << "no error";
  } catch (const hr::ConfigError& e) {
    EXPECT_NE(std::string(e.what()).find("/nonexistent/hg.yaml"), std::string::npos);
  }
  std::string bad = hg::test::temp_yaml("robot: [1, 2\n  : : :\n");
  EXPECT_THROW(hr::Config::load(bad), hr::ConfigError);
  unlink(bad.c_str());
}

}  // namespace
