// Parameters declared once (name, type, default, help, range) and read the same way by every process and
// command-line tool: the command line wins over the --config file, which wins over the default. Keys are
// kebab-case (--tool-radius, as --lcm-url); an old snake_case spelling is refused naming the new key, and
// an unknown key (command line or config file) is an error naming the file and the nearest known key.
#pragma once

#include <cstdint>
#include <cstdio>
#include <functional>
#include <limits>
#include <map>
#include <string>
#include <vector>

#include "runtime/config.hpp"
#include "runtime/quantities.hpp"

namespace hg::runtime {

enum class ParamType { Text, Number, Integer, Flag, Numbers, Names };

struct Param {
  std::string name;           // kebab-case: --name on the command line, key name in the config file
  std::string default_value;  // as text (lists as "a,b,c"); empty: no default
  std::string help;
  bool is_flag = false;              // a flag takes no value on the command line ("true" when given)
  ParamType type = ParamType::Text;  // a flag is always ParamType::Flag
  double min = -std::numeric_limits<double>::infinity();  // Number / Integer / every element of Numbers
  double max = std::numeric_limits<double>::infinity();
  bool min_open = false;               // true: the value must be > min, not >= min
  std::vector<std::string> choices{};  // Text: the only values accepted (empty: any)
  std::string alias{};                 // a short command-line spelling, e.g. "-o"
  // Not a parameter any more: where the value lives now (e.g. "config/cell.yaml key max-speed"). Given on
  // the command line or in a config file it is refused with this; --help and the docs do not list it.
  std::string moved_to{};
  std::string value_name{};  // what --help shows for the value ("FILE"); empty: VALUE
  // An argument by position (hg-plan-bench VERTICES RUNS), not --name: the positional arguments fill the
  // declared positional parameters in their order and are checked as any value; one more is an error.
  bool positional = false;
  // --name ARG...: every argument after it belongs to it (hg-overview --planner-args: the planner's own
  // command line, parsed with the planner's declarations); read with Params::rest.
  bool rest = false;

  ParamType kind() const { return is_flag ? ParamType::Flag : type; }
};

// Declaration helpers: number_param("tool-radius", "0.01", "effective tool radius, m", 0, inf, /*open*/ true).
Param text_param(std::string name, std::string def, std::string help, std::vector<std::string> choices = {});
Param number_param(std::string name, std::string def, std::string help,
                   double min = -std::numeric_limits<double>::infinity(),
                   double max = std::numeric_limits<double>::infinity(), bool min_open = false);
Param integer_param(std::string name, std::string def, std::string help,
                    double min = -std::numeric_limits<double>::infinity(),
                    double max = std::numeric_limits<double>::infinity());
Param numbers_param(std::string name, std::string def, std::string help);
// A list of names: "a,b,c" on the command line, a YAML list [a, b, c] in a config file; "" is the empty list.
Param names_param(std::string name, std::string def, std::string help);
// A job quantity as a parameter (runtime/quantities.hpp): its key, meaning, unit and one range, and `note`
// (what the parameter is for: "job default"): quantity_param(quantity::kStep, "0.002", "job default").
Param quantity_param(const quantity::Quantity& q, std::string def, const std::string& note);
Param flag_param(std::string name, std::string help);
// An argument by position (see Param::positional): positional(integer_param("runs", "21", "...", 1)).
Param positional(Param p);
// --name ARG...: the rest of the command line (see Param::rest).
Param rest_param(std::string name, std::string help);
// A key that moved elsewhere (see Param::moved_to): refused naming where it lives now.
Param moved_param(std::string name, std::string now);
// Names the values --help shows ({"output", "FILE"}: --output FILE); throws std::invalid_argument for a
// name that is not declared.
void set_value_names(std::vector<Param>& params, const std::map<std::string, std::string>& value_names);

// Levenshtein distance (for "did you mean").
std::size_t edit_distance(const std::string& a, const std::string& b);

class Params {
 public:
  enum class Action { Run, Help, HelpMarkdown, Version };

  Params() = default;
  explicit Params(std::vector<Param> declared);

  // A tool with subcommands (hg-lcm-send [--lcm-url URL] COMMAND [options]): parse() takes the options before
  // the first positional argument, the command, and leaves it and everything after it in positional(), for
  // the command's own Params (parse(argc - k, argv + k): the command word stands in for the program name).
  void stop_at_command() { stop_at_command_ = true; }

  // Parses argv[1..] and loads --config FILE. Every value is checked against its type and range before
  // this returns, so a bad value stops the program at start. Throws ConfigError naming the command line or
  // the config file and the key. --help, --help-markdown and --version only return their Action.
  Action parse(int argc, const char* const* argv);
  // Replaces the config file (tests, tools that take a config from elsewhere); checks it as parse does.
  void use_config(Config config);
  void set(const std::string& name, const std::string& value);  // as if given on the command line

  const std::vector<Param>& declared() const { return declared_; }
  const Param* find(const std::string& name) const;
  const std::vector<std::string>& positional() const { return positional_; }
  const Config& config() const { return config_; }

  // Lookups (command line > config > default). Throw ConfigError on a value of the wrong type.
  std::string text(const std::string& name) const;
  double number(const std::string& name) const;
  std::int64_t integer(const std::string& name) const;
  bool flag(const std::string& name) const;
  std::vector<double> numbers(const std::string& name) const;    // "a,b,c" on the command line, a YAML list
  bool given(const std::string& name) const;                     // on the command line or in the config
  std::vector<std::string> rest(const std::string& name) const;  // the arguments after --name (Param::rest)
  // A list of names, as numbers().
  std::vector<std::string> names(const std::string& name) const;

  // Where the value of `name` comes from: "command line", "config 'FILE' line N" or "default".
  std::string origin(const std::string& name) const;
  // An error about parameter `name` naming where its value came from and the key.
  ConfigError error(const std::string& name, const std::string& what) const;

  // The options as --help lists them, and as a Markdown table (docs).
  void print_options(std::FILE* out) const;
  std::string markdown() const;

 private:
  int command_index(int argc, const char* const* argv) const;
  void parse_option(int& i, int argc, const char* const* argv, std::string& config_path);
  void assign_positional();
  void check_config_keys() const;
  void check_values() const;
  std::string unknown_key_message(const std::string& key, bool command_line) const;

  std::vector<Param> declared_;
  std::map<std::string, std::string> cli_;
  std::vector<std::string> positional_;
  std::map<std::string, std::vector<std::string>> rest_;
  Config config_;
  bool stop_at_command_ = false;
};

// The failure contract of every program and tool (docs/RUNNING.md): 0 success; kExitFailed, it ran and failed;
// kExitBadInput, a bad command line, config, cell or input file. A failure is exactly one line on stderr
// naming the file (and line) or the key.
inline constexpr int kExitFailed = 1;
inline constexpr int kExitBadInput = 2;

// The version every executable prints for --version.
const char* version();

// For a command-line tool's main: prints what --help (usage), --help-markdown or --version asked for, on
// standard output; returns the exit code (0).
int answer(Params::Action action, const std::string& program, const Params& params,
           const std::function<void(std::FILE*, const Params&)>& usage);

// The start of a command-line tool's main: parses argv into `params`. Returns -1 when the tool is to run;
// else the exit code, having answered: 0 after --help (usage), --help-markdown or --version;
// kExitBadInput after a bad command line or config file, which is one line on stderr,
// "PROGRAM: <what, naming the option or the file and key> (see --help)".
int parse_tool(Params& params, int argc, const char* const* argv, const std::string& program,
               const std::function<void(std::FILE*, const Params&)>& usage);
// The usage every simple tool prints: `head`, the options as declared, the built-in options.
std::function<void(std::FILE*, const Params&)> usage_with(std::string head);

}  // namespace hg::runtime
