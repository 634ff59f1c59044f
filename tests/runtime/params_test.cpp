// runtime::Params and runtime::Config: one precedence rule (command line > config file > default), YAML
// types (real booleans, lists), and errors that name the file, the key and the nearest known key.
#include <gtest/gtest.h>

#include <algorithm>
#include <cstdio>
#include <cstdlib>
#include <random>
#include <sstream>
#include <stdexcept>
#include <string>
#include <unistd.h>
#include <vector>

#include "runtime/node.hpp"
#include "runtime/params.hpp"
#include "tests/common/temp_file.hpp"

namespace hr = hg::runtime;

namespace {

using hg::test::temp_yaml;

std::vector<hr::Param> declared() {
  return {hr::number_param("tool-radius", "0.01", "tool radius, m", 0, 1, true),
          hr::integer_param("ransac-iterations", "150", "hypotheses", 1),
          hr::text_param("small-hole", "fail", "policy", {"fail", "skip"}),
          hr::numbers_param("workspace-min", "-1,-1,0", "box corner"),
          hr::flag_param("dry-run", "do nothing"),
          hr::Param{"edge-compensation", "true", "a flag that defaults to true", false, hr::ParamType::Flag},
          hr::text_param("frame", "robot_base", "frame name")};
}

// Parses args (argv[0] added) and returns the ConfigError's message, or "" when parsing succeeded.
std::string parse_error(std::vector<std::string> args, std::vector<hr::Param> params = declared()) {
  args.insert(args.begin(), "hg-test");
  std::vector<const char*> argv;
  for (const auto& a : args) argv.push_back(a.c_str());
  hr::Params p(std::move(params));
  try {
    p.parse(int(argv.size()), argv.data());
  } catch (const hr::ConfigError& e) {
    return e.what();
  }
  return "";
}

hr::Params parsed(std::vector<std::string> args) {
  args.insert(args.begin(), "hg-test");
  std::vector<const char*> argv;
  for (const auto& a : args) argv.push_back(a.c_str());
  hr::Params p(declared());
  EXPECT_EQ(p.parse(int(argv.size()), argv.data()), hr::Params::Action::Run);
  return p;
}

bool contains(const std::string& text, const std::string& part) { return text.find(part) != std::string::npos; }

TEST(RuntimeParams, CommandLineBeatsConfigBeatsDefault) {
  const std::string cfg =
      temp_yaml("tool-radius: 0.02\nsmall-hole: skip\nworkspace-min: [-2, -3, 0.5]\ndry-run: true\n");
  const hr::Params p = parsed({"--config", cfg, "--tool-radius", "0.03", "--workspace-min=4,5,6"});
  EXPECT_EQ(p.number("tool-radius"), 0.03);                               // command line over config
  EXPECT_EQ(p.numbers("workspace-min"), (std::vector<double>{4, 5, 6}));  // command line over config list
  EXPECT_EQ(p.text("small-hole"), "skip");                                // config over default
  EXPECT_TRUE(p.flag("dry-run"));                                         // config (a YAML boolean)
  EXPECT_EQ(p.integer("ransac-iterations"), 150);                         // default
  EXPECT_EQ(p.text("frame"), "robot_base");
  EXPECT_EQ(p.origin("tool-radius"), "command line");
  EXPECT_EQ(p.origin("small-hole"), "config '" + cfg + "' line 2");
  EXPECT_EQ(p.origin("frame"), "default");
  EXPECT_TRUE(p.given("small-hole"));
  EXPECT_FALSE(p.given("frame"));
  unlink(cfg.c_str());
}

TEST(RuntimeParams, YamlBooleansAndLists) {
  const std::string cfg = temp_yaml("edge-compensation: false\ndry-run: true\nworkspace-min: [1.5, -2.25e-3, 7]\n");
  const hr::Params p = parsed({"--config", cfg});
  EXPECT_FALSE(p.flag("edge-compensation"));
  EXPECT_TRUE(p.flag("dry-run"));
  EXPECT_EQ(p.numbers("workspace-min"), (std::vector<double>{1.5, -2.25e-3, 7}));
  EXPECT_EQ(p.text("workspace-min"), "1.5,-0.00225,7");
  const hr::Params d = parsed({});
  EXPECT_TRUE(d.flag("edge-compensation"));  // its default
  EXPECT_FALSE(d.flag("dry-run"));           // a flag without a default is false
  EXPECT_TRUE(parsed({"--dry-run"}).flag("dry-run"));
  EXPECT_FALSE(parsed({"--edge-compensation=false"}).flag("edge-compensation"));
  unlink(cfg.c_str());
}

TEST(RuntimeParams, UnknownConfigKeyNamesFileKeyAndNearestKey) {
  const std::string cfg = temp_yaml("frame: base\ntool-radus: 0.02\n");
  const std::string e = parse_error({"--config", cfg});
  EXPECT_TRUE(contains(e, cfg)) << e;
  EXPECT_TRUE(contains(e, "line 2")) << e;
  EXPECT_TRUE(contains(e, "'tool-radus'")) << e;
  EXPECT_TRUE(contains(e, "nearest known: 'tool-radius'")) << e;
  unlink(cfg.c_str());
}

TEST(RuntimeParams, UnknownOptionNamesNearestKey) {
  const std::string e = parse_error({"--ransac-iteration", "3"});
  EXPECT_TRUE(contains(e, "command line")) << e;
  EXPECT_TRUE(contains(e, "unknown option --ransac-iteration")) << e;
  EXPECT_TRUE(contains(e, "nearest known: --ransac-iterations")) << e;
}

TEST(RuntimeParams, OldSnakeCaseSpellingIsRefusedNamingTheNewKey) {
  const std::string on_line = parse_error({"--tool_radius", "0.02"});
  EXPECT_TRUE(contains(on_line, "--tool_radius is the old spelling of --tool-radius")) << on_line;
  const std::string cfg = temp_yaml("small_hole: skip\n");
  const std::string in_file = parse_error({"--config", cfg});
  EXPECT_TRUE(contains(in_file, cfg)) << in_file;
  EXPECT_TRUE(contains(in_file, "key 'small_hole': old spelling of 'small-hole'")) << in_file;
  unlink(cfg.c_str());
}

// A key that moved elsewhere is refused where it used to be (command line, config file, its snake_case
// spelling), naming where it lives now; it is no nearest-known suggestion and not in --help or the docs.
TEST(RuntimeParams, MovedKeyIsRefusedNamingWhereItLivesNow) {
  std::vector<hr::Param> params = declared();
  params.push_back(hr::moved_param("table-z", "the cell file, key table-z"));
  EXPECT_EQ(parse_error({"--table-z", "0.1"}, params),
            "command line: --table-z moved: it lives in the cell file, key table-z");
  EXPECT_EQ(parse_error({"--table_z", "0.1"}, params),
            "command line: --table_z moved: it lives in the cell file, key table-z");
  const std::string cfg = temp_yaml("frame: base\ntable-z: 0.1\n");
  EXPECT_EQ(parse_error({"--config", cfg}, params),
            "config '" + cfg + "' line 2: key 'table-z': moved: it lives in the cell file, key table-z");
  unlink(cfg.c_str());
  EXPECT_FALSE(contains(parse_error({"--table-zz", "1"}, params), "nearest known: --table-z"))
      << "a moved key is no suggestion";
  hr::Params p(params);
  EXPECT_FALSE(contains(p.markdown(), "table-z"));
  EXPECT_THROW(p.set("table-z", "0"), hr::ConfigError);
  EXPECT_EQ(parse_error({}, params), "");  // declared but not given: nothing to refuse
}

TEST(RuntimeParams, BadValuesNameWhereTheyCameFrom) {
  const std::string cfg = temp_yaml("frame: base\nworkspace-min: [1, two, 3]\n");
  std::string e = parse_error({"--config", cfg});
  EXPECT_TRUE(contains(e, cfg) && contains(e, "line 2") && contains(e, "'workspace-min'")) << e;
  unlink(cfg.c_str());
  const std::string range = temp_yaml("tool-radius: 0\n");  // the range is (0, 1]
  e = parse_error({"--config", range});
  EXPECT_TRUE(contains(e, range) && contains(e, "'tool-radius'") && contains(e, "out of range")) << e;
  unlink(range.c_str());
  const std::string choice = temp_yaml("small-hole: ignore\n");
  e = parse_error({"--config", choice});
  EXPECT_TRUE(contains(e, choice) && contains(e, "'small-hole'") && contains(e, "fail | skip")) << e;
  unlink(choice.c_str());
  const std::string quoted_flag = temp_yaml("dry-run: maybe\n");
  e = parse_error({"--config", quoted_flag});
  EXPECT_TRUE(contains(e, quoted_flag) && contains(e, "'dry-run'")) << e;
  unlink(quoted_flag.c_str());
  e = parse_error({"--ransac-iterations", "2.5"});
  EXPECT_TRUE(contains(e, "command line") && contains(e, "--ransac-iterations") && contains(e, "integer")) << e;
  e = parse_error({"--tool-radius", "1.5"});
  EXPECT_TRUE(contains(e, "--tool-radius") && contains(e, "out of range")) << e;
  EXPECT_EQ(parse_error({"--tool-radius", "1"}), "");  // the upper end is included
}

TEST(RuntimeParams, HelpAndVersionAnswerBeforeAnythingElse) {
  hr::Params p(declared());
  const char* help[] = {"hg-test", "--config", "/nonexistent.yaml", "--no-such", "--help"};
  EXPECT_EQ(p.parse(5, help), hr::Params::Action::Help);  // nothing is opened or checked
  const char* version[] = {"hg-test", "--tool_radius", "--version"};
  EXPECT_EQ(p.parse(3, version), hr::Params::Action::Version);
  const std::string md = p.markdown();
  for (const hr::Param& d : declared()) EXPECT_TRUE(contains(md, "| `" + d.name + "` |")) << d.name;
}

// --help from the declarations: every word of every help text (and its range and default) in order, no
// line past column 110 however long the help, value names as declared, an alias beside its long form.
TEST(RuntimeParams, HelpIsTheDeclarationsWrappedAt110Columns) {
  std::string long_help;
  std::mt19937 rng(3);
  for (int i = 0; i < 90; ++i) long_help += std::string(1 + rng() % 12, char('a' + i % 26)) + " ";
  std::vector<hr::Param> params = declared();
  params.push_back(hr::text_param("output", "", long_help));
  params.back().alias = "-o";
  params.push_back(hr::number_param("radius", "2", "short help", 0));
  hr::set_value_names(params, {{"output", "FILE"}, {"radius", "R"}});
  EXPECT_THROW(hr::set_value_names(params, {{"no-such", "X"}}), std::invalid_argument);
  char* buffer = nullptr;
  std::size_t size = 0;
  std::FILE* out = open_memstream(&buffer, &size);
  hr::Params(params).print_options(out);
  std::fclose(out);
  const std::string text(buffer, size);
  std::free(buffer);
  std::istringstream lines(text);
  std::vector<std::string> printed_words;
  for (std::string line; std::getline(lines, line);) {
    EXPECT_LE(line.size(), 110u) << line;
    std::istringstream words(line);
    for (std::string w; words >> w;) printed_words.push_back(w);
  }
  std::istringstream expected_words(long_help);
  auto at = std::find(printed_words.begin(), printed_words.end(), "--output");
  ASSERT_NE(at, printed_words.end()) << text;
  EXPECT_EQ(*std::next(at), "FILE");
  EXPECT_EQ(*std::prev(at, 2), "-o");  // "-o FILE, --output FILE"
  EXPECT_EQ(*std::prev(at), "FILE,");
  at += 2;
  for (std::string w; expected_words >> w; ++at) {
    ASSERT_NE(at, printed_words.end());
    EXPECT_EQ(*at, w);
  }
  EXPECT_TRUE(contains(text, "--radius R ")) << text;
  EXPECT_TRUE(contains(text, "short help (>= 0) [default: 2]\n")) << text;
  EXPECT_TRUE(contains(text, "--small-hole VALUE ")) << text;  // no value name: VALUE
}

TEST(RuntimeParams, EditDistance) {
  EXPECT_EQ(hr::edit_distance("kitten", "sitting"), 3u);
  EXPECT_EQ(hr::edit_distance("", "abc"), 3u);
  EXPECT_EQ(hr::edit_distance("tool-radius", "tool-radius"), 0u);
  // Metric properties on random strings: symmetry, identity, triangle inequality, length bounds.
  std::mt19937 rng(7);
  auto random_string = [&] {
    std::string s(rng() % 9, 'a');
    for (char& c : s) c = char('a' + rng() % 3);
    return s;
  };
  for (int i = 0; i < 500; ++i) {
    const std::string a = random_string(), b = random_string(), c = random_string();
    const std::size_t ab = hr::edit_distance(a, b);
    EXPECT_EQ(ab, hr::edit_distance(b, a));
    EXPECT_EQ(ab == 0, a == b);
    EXPECT_LE(hr::edit_distance(a, c), ab + hr::edit_distance(b, c));
    EXPECT_GE(ab, a.size() > b.size() ? a.size() - b.size() : b.size() - a.size());
    EXPECT_LE(ab, std::max(a.size(), b.size()));
  }
}

TEST(RuntimeParamsDeathTest, ProcessWithBadValueExits2NamingFileAndKey) {
  const std::string cfg = temp_yaml("speed: fast\n");
  hr::ProcessInfo info{"hg-test", "a test process", "", {hr::number_param("speed", "0.05", "m/s", 0)}};
  std::vector<std::string> args = {"hg-test", "--lcm-url", "memq://", "--config", cfg};
  std::vector<char*> argv;
  for (auto& a : args) argv.push_back(a.data());
  argv.push_back(nullptr);
  EXPECT_EXIT(hr::Node(info, int(args.size()), argv.data()), testing::ExitedWithCode(2),
              "hg-test: config '" + cfg + "' line 1: key 'speed': 'fast' is not a number");
  unlink(cfg.c_str());
}

}  // namespace

// Positional arguments are declared as any parameter: filled in order, checked against type and range, named
// in errors as --help shows them; one more than declared is an error.
TEST(RuntimeParams, PositionalArgumentsAreDeclaredAndChecked) {
  const std::vector<hr::Param> bench = {hr::positional(hr::integer_param("vertices", "10000", "about this many", 100)),
                                        hr::positional(hr::integer_param("runs", "21", "runs", 1)),
                                        hr::flag_param("verbose", "more")};
  std::vector<const char*> argv = {"hg-test", "500", "--verbose"};
  hr::Params p(bench);
  ASSERT_EQ(p.parse(int(argv.size()), argv.data()), hr::Params::Action::Run);
  EXPECT_EQ(p.integer("vertices"), 500);
  EXPECT_EQ(p.integer("runs"), 21);  // its default
  EXPECT_TRUE(p.flag("verbose"));
  EXPECT_EQ(parse_error({"50"}, bench), "command line: VERTICES: 50 is out of range (>= 100)");
  EXPECT_EQ(parse_error({"500", "x"}, bench), "command line: RUNS: 'x' is not an integer");
  EXPECT_EQ(parse_error({"500", "2", "3"}, bench), "command line: unexpected argument '3'");
  EXPECT_TRUE(contains(parse_error({"--vertices", "500"}, bench), "unknown option --vertices")) << "not an option";
  const std::string file = temp_yaml("runs: 3\n");
  EXPECT_TRUE(contains(parse_error({"--config", file}, bench), "a command-line argument, not a config key"));
  hr::Params shown(bench);
  EXPECT_TRUE(contains(shown.markdown(), "| `VERTICES` (argument) | integer | `10000` | >= 100 |"));
}

// --name ARG...: the rest of the command line belongs to the option, unparsed (it is another program's).
TEST(RuntimeParams, RestOptionTakesEveryArgumentAfterIt) {
  const std::vector<hr::Param> decl = {hr::text_param("out", "", "folder"),
                                       hr::rest_param("planner-args", "the planner's command line")};
  std::vector<const char*> argv = {"hg-test", "log", "--out", "o", "--planner-args", "--config", "x.yaml", "--out"};
  hr::Params p(decl);
  ASSERT_EQ(p.parse(int(argv.size()), argv.data()), hr::Params::Action::Run);
  EXPECT_EQ(p.text("out"), "o");
  EXPECT_EQ(p.rest("planner-args"), (std::vector<std::string>{"--config", "x.yaml", "--out"}));
  EXPECT_EQ(p.positional(), std::vector<std::string>{"log"});
  EXPECT_TRUE(p.given("planner-args"));
  hr::Params none(decl);
  EXPECT_TRUE(none.rest("planner-args").empty());
}

// A tool with subcommands: the options before the command are the tool's, the command and what follows are
// left for the command's own declarations (--help after the command is the command's).
TEST(RuntimeParams, StopsAtTheCommand) {
  std::vector<const char*> argv = {"hg-test", "--lcm-url", "memq://", "job", "--job-id", "j", "--help"};
  hr::Params global({hr::text_param("lcm-url", "udpm://", "bus")});
  global.stop_at_command();
  ASSERT_EQ(global.parse(int(argv.size()), argv.data()), hr::Params::Action::Run);
  EXPECT_EQ(global.text("lcm-url"), "memq://");
  ASSERT_EQ(global.positional(), (std::vector<std::string>{"job", "--job-id", "j", "--help"}));
  hr::Params job({hr::text_param("job-id", "", "job")});
  EXPECT_EQ(job.parse(int(argv.size()) - 3, argv.data() + 3), hr::Params::Action::Help);
  std::vector<const char*> top = {"hg-test", "--help", "job"};
  hr::Params again({hr::text_param("lcm-url", "udpm://", "bus")});
  again.stop_at_command();
  EXPECT_EQ(again.parse(int(top.size()), top.data()), hr::Params::Action::Help);
}
