// The camera source registry (camera_bridge/source_registry.hpp): the bridge's --help lists every registered
// source and its parameters, an unknown source's error names every choice, each factory reads its own
// section (command line and config file), and the flat names of before are refused naming the new key.
#include <gtest/gtest.h>

#include <array>
#include <cstdio>
#include <memory>
#include <set>
#include <string>
#include <vector>

#include "camera_bridge/camera_bridge.hpp"
#include "camera_bridge/source_registry.hpp"
#include "camera_bridge/sources.hpp"
#include "tests/common/temp_file.hpp"

using namespace hg::camera_bridge;
namespace hr = hg::runtime;

namespace {

// The sources this tree ships (camera_bridge/CMakeLists.txt and sources.cpp), written out here.
const std::vector<std::string> kShipped = {"synthetic", "files", "openni2", "genicam"};

struct Output {
  int status = -1;
  std::string out;  // stdout and stderr
};

Output run_bridge(const std::string& args) {
  Output r;
  const std::string cmd = std::string(HG_BIN_DIR) + "/hg-camera-bridge " + args + " 2>&1";
  FILE* p = popen(cmd.c_str(), "r");
  if (!p) return r;
  std::array<char, 4096> buf{};
  while (std::size_t n = std::fread(buf.data(), 1, buf.size(), p)) r.out.append(buf.data(), n);
  r.status = pclose(p);
  return r;
}

hr::Params parsed(std::vector<std::string> args) {
  hr::Params params(hr::process_params(process_info().params));
  args.insert(args.begin(), "hg-camera-bridge");
  std::vector<const char*> argv;
  for (const std::string& a : args) argv.push_back(a.c_str());
  params.parse(static_cast<int>(argv.size()), argv.data());
  return params;
}

}  // namespace

TEST(CameraSourceRegistry, HoldsTheShippedSourcesOnceEach) {
  std::set<std::string> names;
  for (const SourceEntry& e : registered_sources()) {
    EXPECT_TRUE(names.insert(e.name).second) << "registered twice: " << e.name;
    EXPECT_TRUE(e.missing.empty() ? bool(e.make) : !e.make) << e.name << ": a factory exactly when in the build";
    for (const hr::Param& p : e.params) EXPECT_EQ(p.name.find('.'), std::string::npos) << e.name << ": " << p.name;
  }
  EXPECT_EQ(names, std::set<std::string>(kShipped.begin(), kShipped.end()));
}

TEST(CameraSourceRegistry, HelpListsEverySourceAndItsParameters) {
  const Output help = run_bridge("--help");
  ASSERT_EQ(help.status, 0) << help.out;
  for (const SourceEntry& e : registered_sources()) {
    EXPECT_NE(help.out.find("\n  " + e.name + ": "), std::string::npos) << "--help does not list " << e.name;
    for (const hr::Param& p : e.params)
      EXPECT_NE(help.out.find("--" + e.name + "." + p.name + " "), std::string::npos)
          << "--help lacks --" << e.name << "." << p.name;
  }
  const Output md = run_bridge("--help-markdown");
  for (const std::string& name : kShipped) EXPECT_NE(md.out.find(name), std::string::npos) << name;
}

TEST(CameraSourceRegistry, AnUnknownSourceIsRefusedNamingEveryChoice) {
  const Output r = run_bridge("--source no-such-camera");
  EXPECT_EQ(WEXITSTATUS(r.status), hr::kExitBadInput) << r.out;
  EXPECT_NE(r.out.find("no-such-camera"), std::string::npos) << r.out;
  for (const std::string& name : kShipped) EXPECT_NE(r.out.find(name), std::string::npos) << name << ": " << r.out;
  // The registry's own check says the same for a Params that skipped the declared choices.
  hr::Params loose({hr::text_param("source", "x", ""), hr::text_param("trigger", "continuous", "")});
  try {
    make_source(loose, false, 0);
    FAIL() << "no error for source 'x'";
  } catch (const hr::ConfigError& e) {
    for (const std::string& name : kShipped) EXPECT_NE(std::string(e.what()).find(name), std::string::npos) << e.what();
  }
}

TEST(CameraSourceRegistry, EachFactoryReadsItsOwnSection) {
  auto synthetic = make_source(parsed({"--source", "synthetic", "--synthetic.scene", "l-bracket"}), false, 0);
  auto* s = dynamic_cast<hg::sim::SyntheticSource*>(synthetic.get());
  ASSERT_NE(s, nullptr);
  EXPECT_EQ(s->spec().name, "l-bracket");
  // A config file's section is the same key.
  const std::string cfg = hg::test::temp_yaml("source: files\nfiles:\n  path: /nonexistent/depth-dir\n  loop: true\n");
  auto files = make_source(parsed({"--config", cfg}), false, 0);
  unlink(cfg.c_str());
  EXPECT_NE(files->describe().find("/nonexistent/depth-dir"), std::string::npos) << files->describe();
  ASSERT_NE(dynamic_cast<FilesSource*>(files.get()), nullptr);
  EXPECT_FALSE(dynamic_cast<FilesSource*>(files.get())->finished()) << "files.loop read";
  // A missing required value names its key.
  try {
    make_source(parsed({"--source", "files"}), false, 0);
    FAIL() << "no error without --files.path";
  } catch (const hr::ConfigError& e) {
    EXPECT_NE(std::string(e.what()).find("files.path"), std::string::npos) << e.what();
  }
}

TEST(CameraSourceRegistry, FlatNamesOfBeforeAreRefusedNamingTheNewKey) {
  for (const auto& [old, now] :
       std::vector<std::pair<std::string, std::string>>{{"--scene three-parts", "--synthetic.scene"},
                                                        {"--files /tmp", "--files.path"},
                                                        {"--uri hg-virtual://demo", "--openni2.uri"},
                                                        {"--genicam-device x", "--genicam.device"},
                                                        {"--genicam-format c16", "--genicam.format"}}) {
    const Output r = run_bridge(old);
    EXPECT_EQ(WEXITSTATUS(r.status), hr::kExitBadInput) << old << ": " << r.out;
    EXPECT_NE(r.out.find(now), std::string::npos) << old << ": " << r.out;
  }
  // An unknown key inside a section is an error naming it.
  const Output r = run_bridge("--genicam.devise x");
  EXPECT_EQ(WEXITSTATUS(r.status), hr::kExitBadInput) << r.out;
  EXPECT_NE(r.out.find("--genicam.device"), std::string::npos) << "nearest known: " << r.out;
}

TEST(CameraSourceRegistry, ASourceMissingFromTheBuildSaysWhyInHelpAndError) {
  SourceEntry here{"here",
                   "a source that is built",
                   {},
                   [](const SourceContext&) { return std::unique_ptr<hg::camera::DepthSource>(); },
                   ""};
  SourceEntry gone{"gone", "", {}, nullptr, "libgone-dev was not there when the project was configured"};
  const std::vector<SourceEntry> list{here, gone};
  const std::string help = sources_help(list);
  EXPECT_NE(help.find("  here: a source that is built"), std::string::npos) << help;
  EXPECT_NE(help.find("  gone: NOT in this build: libgone-dev was not there"), std::string::npos) << help;
  hr::Params params({hr::text_param("source", "gone", "")});
  try {
    make_source(params, false, 0, list);
    FAIL() << "no error for a source not in the build";
  } catch (const hr::ConfigError& e) {
    EXPECT_NE(std::string(e.what()).find("'gone' is not available in this build: libgone-dev"), std::string::npos)
        << e.what();
  }
  params.set("source", "elsewhere");
  try {
    make_source(params, false, 0, list);
    FAIL() << "no error for an unknown source";
  } catch (const hr::ConfigError& e) {
    EXPECT_NE(std::string(e.what()).find("must be here or gone, not 'elsewhere'"), std::string::npos) << e.what();
  }
}
