#include "runtime/params.hpp"
#include "runtime/version.hpp"

#include <algorithm>
#include <charconv>
#include <cctype>
#include <cmath>
#include <sstream>
#include <stdexcept>

#ifndef HG_VERSION
#define HG_VERSION "unknown"
#endif

namespace hg::runtime {
namespace {

bool parse_bool(const std::string& v, bool& out) {
  if (v == "true" || v == "1" || v == "yes" || v == "on") return out = true, true;
  if (v == "false" || v == "0" || v == "no" || v == "off") return out = false, true;
  return false;
}

bool parse_double(const std::string& s, double& out) {
  char* end = nullptr;
  out = std::strtod(s.c_str(), &end);
  return !s.empty() && *end == '\0' && std::isfinite(out);
}

std::string number_text(double v) {  // the shortest text that reads back as v
  char buf[32];
  const auto r = std::to_chars(buf, buf + sizeof buf, v);
  return std::string(buf, r.ptr);
}

std::string range_text(const Param& p) {
  const bool lo = std::isfinite(p.min), hi = std::isfinite(p.max);
  if (!lo && !hi) return "";
  if (lo && !hi) return std::string(p.min_open ? "> " : ">= ") + number_text(p.min);
  if (!lo) return "<= " + number_text(p.max);
  return std::string(p.min_open ? "(" : "[") + number_text(p.min) + ", " + number_text(p.max) + "]";
}

const char* type_name(ParamType t) {
  switch (t) {
    case ParamType::Number: return "number";
    case ParamType::Integer: return "integer";
    case ParamType::Flag: return "true|false";
    case ParamType::Numbers: return "list of numbers";
    case ParamType::Names: return "list of names";
    default: return "text";
  }
}

bool is_list(ParamType t) { return t == ParamType::Numbers || t == ParamType::Names; }

bool is_builtin(const std::string& name) { return name == "config" || name == "help" || name == "version"; }

// `text` broken at spaces so that no line goes past column `width`; the first line starts at column `first`,
// the others are indented to column `indent`.
std::string wrapped(const std::string& text, std::size_t first, std::size_t indent, std::size_t width) {
  std::string out, line;
  std::size_t column = first;
  std::istringstream words(text);
  for (std::string word; words >> word;) {
    if (!line.empty() && column + line.size() + 1 + word.size() > width) {
      out += line + "\n" + std::string(indent, ' ');
      line.clear();
      column = indent;
    }
    line += (line.empty() ? "" : " ") + word;
  }
  return out + line;
}

// How --help and errors name a positional argument: its value name, else its name in capitals.
std::string shown(const Param& p) {
  if (!p.value_name.empty()) return p.value_name;
  std::string upper = p.name;
  for (char& c : upper) c = c == '-' ? '_' : char(std::toupper(static_cast<unsigned char>(c)));
  return upper;
}

}  // namespace

Param positional(Param p) {
  p.positional = true;
  return p;
}
Param rest_param(std::string name, std::string help) {
  Param p{std::move(name), "", std::move(help)};
  p.rest = true;
  p.value_name = "ARG...";
  return p;
}

Param text_param(std::string name, std::string def, std::string help, std::vector<std::string> choices) {
  Param p{std::move(name), std::move(def), std::move(help)};
  p.choices = std::move(choices);
  return p;
}
Param number_param(std::string name, std::string def, std::string help, double min, double max, bool min_open) {
  Param p{std::move(name), std::move(def), std::move(help), false, ParamType::Number, min, max, min_open};
  return p;
}
Param integer_param(std::string name, std::string def, std::string help, double min, double max) {
  return Param{std::move(name), std::move(def), std::move(help), false, ParamType::Integer, min, max};
}
Param quantity_param(const quantity::Quantity& q, std::string def, const std::string& note) {
  return number_param(quantity::key(q), std::move(def), std::string(q.what) + ", " + q.unit + " (" + note + ")", q.min,
                      q.max);
}
Param numbers_param(std::string name, std::string def, std::string help) {
  return Param{std::move(name), std::move(def), std::move(help), false, ParamType::Numbers};
}
Param names_param(std::string name, std::string def, std::string help) {
  return Param{std::move(name), std::move(def), std::move(help), false, ParamType::Names};
}
Param flag_param(std::string name, std::string help) { return Param{std::move(name), "", std::move(help), true}; }
Param moved_param(std::string name, std::string now) {
  Param p{std::move(name), "", ""};
  p.moved_to = std::move(now);
  return p;
}

void set_value_names(std::vector<Param>& params, const std::map<std::string, std::string>& value_names) {
  for (const auto& [name, value_name] : value_names) {
    auto p = std::find_if(params.begin(), params.end(), [&](const Param& q) { return q.name == name; });
    if (p == params.end()) throw std::invalid_argument("set_value_names: no parameter '" + name + "'");
    p->value_name = value_name;
  }
}

std::size_t edit_distance(const std::string& a, const std::string& b) {
  std::vector<std::size_t> row(b.size() + 1);
  for (std::size_t j = 0; j <= b.size(); ++j) row[j] = j;
  for (std::size_t i = 1; i <= a.size(); ++i) {
    std::size_t diagonal = row[0];
    row[0] = i;
    for (std::size_t j = 1; j <= b.size(); ++j) {
      const std::size_t up = row[j];
      row[j] = std::min({row[j] + 1, row[j - 1] + 1, diagonal + (a[i - 1] == b[j - 1] ? 0 : 1)});
      diagonal = up;
    }
  }
  return row[b.size()];
}

const char* version() { return HG_VERSION; }

bool answer_version(int argc, const char* const* argv, const char* name) {
  for (int i = 1; i < argc; ++i)
    if (std::string(argv[i]) == "--version") {
      std::printf("%s %s\n", name, version());
      return true;
    }
  return false;
}

int answer(Params::Action action, const std::string& program, const Params& params,
           const std::function<void(std::FILE*, const Params&)>& usage) {
  if (action == Params::Action::Help) usage(stdout, params);
  else if (action == Params::Action::HelpMarkdown)
    std::fputs(params.markdown().c_str(), stdout);
  else if (action == Params::Action::Version)
    std::printf("%s %s\n", program.c_str(), version());
  return 0;
}

int parse_tool(Params& params, int argc, const char* const* argv, const std::string& program,
               const std::function<void(std::FILE*, const Params&)>& usage) {
  try {
    const Params::Action action = params.parse(argc, argv);
    return action == Params::Action::Run ? -1 : answer(action, program, params, usage);
  } catch (const std::exception& e) {  // ConfigError: the option, or the config file and its key
    std::fprintf(stderr, "%s: %s (see --help)\n", program.c_str(), e.what());
    return kExitBadInput;
  }
}

std::function<void(std::FILE*, const Params&)> usage_with(std::string head) {
  return [head = std::move(head)](std::FILE* f, const Params& params) {
    std::fputs(head.c_str(), f);
    std::fputs("Options (command line > --config FILE > default):\n", f);
    params.print_options(f);
    std::fputs(
        "  --config FILE                    a YAML file with any of these options as keys (the command line "
        "wins)\n"
        "  --help                           this text; --help-markdown: the options as a table; --version\n",
        f);
  };
}

Params::Params(std::vector<Param> declared) : declared_(std::move(declared)) {}

const Param* Params::find(const std::string& name) const {
  for (const Param& p : declared_)
    if (p.name == name || (!p.alias.empty() && p.alias == name)) return &p;
  return nullptr;
}

std::string Params::unknown_key_message(const std::string& key, bool command_line) const {
  const std::string dash = command_line ? "--" : "'", end = command_line ? "" : "'";
  std::string kebab = key;
  std::replace(kebab.begin(), kebab.end(), '_', '-');
  if (const Param* moved = find(kebab); moved && !moved->moved_to.empty())
    return (command_line ? "--" + key + " " : std::string()) + "moved: it lives in " + moved->moved_to;
  if (kebab != key && find(kebab))
    return (command_line ? "--" + key + " is the " : std::string()) + "old spelling of " + dash + kebab + end +
           " (keys are kebab-case)";
  const Param* nearest = nullptr;
  std::size_t best = std::string::npos;
  for (const Param& p : declared_) {
    if (!p.moved_to.empty() || p.positional) continue;
    const std::size_t d = edit_distance(kebab, p.name);
    if (d < best) best = d, nearest = &p;
  }
  return (command_line ? "unknown option --" + key : std::string("unknown key")) +
         (nearest ? " (nearest known: " + dash + nearest->name + end + ")" : std::string());
}

// The index of the command (the first positional argument) in a tool with subcommands; argc otherwise.
int Params::command_index(int argc, const char* const* argv) const {
  if (!stop_at_command_) return argc;
  for (int i = 1; i < argc; ++i) {
    const std::string a = argv[i];
    const Param* p = find(a.rfind("--", 0) == 0 ? a.substr(2) : a);
    if (a.rfind("--", 0) != 0 && !(a.size() == 2 && a[0] == '-' && p)) return i;
    if (a.find('=') == std::string::npos && a != "--config" && p && !p->is_flag) ++i;  // skip its value
    else if (a == "--config")
      ++i;
  }
  return argc;
}

// One option at argv[i] (--name, --name=value, --name value, -x value); i ends on the last argument used.
void Params::parse_option(int& i, int end, const char* const* argv, std::string& config_path) {
  const std::string a = argv[i];
  const bool is_alias = a.rfind("--", 0) != 0;
  std::string name = is_alias ? a : a.substr(2), value;
  bool has_value = false;
  if (auto eq = name.find('='); eq != std::string::npos) {
    value = name.substr(eq + 1), name = name.substr(0, eq), has_value = true;
  }
  const Param* p = name == "config" ? nullptr : find(name);
  if (p && (!p->moved_to.empty() || p->positional)) p = nullptr;
  if (!p && name != "config") throw ConfigError("command line: " + unknown_key_message(name, true));
  if (p && p->rest) {
    rest_[p->name].assign(argv + i + 1, argv + end);
    i = end;
    return;
  }
  if (p && p->is_flag) {
    cli_[p->name] = has_value ? value : "true";
    return;
  }
  if (!has_value) {
    if (i + 1 >= end) throw ConfigError("command line: option " + a + " needs a value");
    value = argv[++i];
  }
  if (p) cli_[p->name] = value;
  else
    config_path = value;
}

// The positional arguments into the declared positional parameters, in order (none declared: the program
// reads positional() itself).
void Params::assign_positional() {
  std::vector<const Param*> slots;
  for (const Param& p : declared_)
    if (p.positional) slots.push_back(&p);
  if (slots.empty() || stop_at_command_) return;
  if (positional_.size() > slots.size())
    throw ConfigError("command line: unexpected argument '" + positional_[slots.size()] + "'");
  for (std::size_t k = 0; k < positional_.size(); ++k) cli_[slots[k]->name] = positional_[k];
}

Params::Action Params::parse(int argc, const char* const* argv) {
  const int end = command_index(argc, argv);
  // --help and --version first: they answer whatever else the command line says, and touch nothing.
  for (int i = 1; i < end; ++i) {
    const std::string a = argv[i];
    if (a == "--help" || a == "-h") return Action::Help;
    if (a == "--help-markdown") return Action::HelpMarkdown;
    if (a == "--version") return Action::Version;
  }
  std::string config_path;
  for (int i = 1; i < end; ++i) {
    const std::string a = argv[i];
    if (a == "--") {
      positional_.insert(positional_.end(), argv + i + 1, argv + end);
      break;
    }
    const bool is_alias = a.size() == 2 && a[0] == '-' && find(a);
    if (a.rfind("--", 0) != 0 && !is_alias) positional_.push_back(a);
    else
      parse_option(i, end, argv, config_path);
  }
  positional_.insert(positional_.end(), argv + end, argv + argc);
  assign_positional();
  if (!config_path.empty()) use_config(Config::load(config_path));
  check_values();
  return Action::Run;
}

void Params::use_config(Config config) {
  config_ = std::move(config);
  check_config_keys();
}

void Params::set(const std::string& name, const std::string& value) {
  const Param* p = find(name);
  if (!p || !p->moved_to.empty()) throw ConfigError("command line: " + unknown_key_message(name, true));
  cli_[p->name] = value;
}

void Params::check_config_keys() const {
  for (const std::string& key : config_.keys())
    if (const Param* p = find(key); !p || !p->moved_to.empty() || is_builtin(key))
      throw config_.error(key, unknown_key_message(key, false));
    else if (p->positional || p->rest)
      throw config_.error(key, "a command-line argument, not a config key");
}

void Params::check_values() const {
  for (const Param& p : declared_) {
    if (!p.moved_to.empty() || (!given(p.name) && p.default_value.empty())) continue;  // optional: read if at all
    switch (p.kind()) {
      case ParamType::Number: number(p.name); break;
      case ParamType::Integer: integer(p.name); break;
      case ParamType::Flag: flag(p.name); break;
      case ParamType::Numbers: numbers(p.name); break;
      case ParamType::Names: names(p.name); break;
      case ParamType::Text: text(p.name); break;
    }
  }
}

std::string Params::origin(const std::string& name) const {
  if (cli_.count(name)) return "command line";
  if (config_.has(name)) {
    const int line = config_.line_of(name);
    return "config '" + config_.source() + "'" + (line > 0 ? " line " + std::to_string(line) : "");
  }
  return "default";
}

ConfigError Params::error(const std::string& name, const std::string& what) const {
  if (const Param* p = find(name); p && p->positional) return ConfigError("command line: " + shown(*p) + ": " + what);
  if (cli_.count(name)) return ConfigError("command line: --" + name + ": " + what);
  return ConfigError(origin(name) + ": key '" + name + "': " + what);
}

bool Params::given(const std::string& name) const { return cli_.count(name) || config_.has(name) || rest_.count(name); }

std::vector<std::string> Params::rest(const std::string& name) const {
  const auto it = rest_.find(name);
  return it == rest_.end() ? std::vector<std::string>{} : it->second;
}

std::string Params::text(const std::string& name) const {
  const Param* p = find(name);
  if (!p) throw ConfigError("no such parameter '" + name + "'");
  std::string v;
  if (auto it = cli_.find(name); it != cli_.end()) v = it->second;
  else if (config_.is_list(name) && p->kind() == ParamType::Names) {
    const std::vector<std::string> list = config_.get_strings(name).value();
    for (const std::string& s : list) v += (v.empty() ? "" : ",") + s;
  } else if (config_.is_list(name)) {
    const std::vector<double> list = config_.get_doubles(name).value();
    for (double d : list) v += (v.empty() ? "" : ",") + number_text(d);
  } else if (auto s = config_.get_string(name))
    v = *s;
  else
    v = p->is_flag && p->default_value.empty() ? "false" : p->default_value;
  if (!p->choices.empty() && std::find(p->choices.begin(), p->choices.end(), v) == p->choices.end()) {
    std::string all;
    for (const std::string& c : p->choices) all += (all.empty() ? "" : " | ") + c;
    throw error(name, "'" + v + "' is not one of " + all);
  }
  return v;
}

double Params::number(const std::string& name) const {
  const std::string v = text(name);
  double d = 0;
  if (!parse_double(v, d)) throw error(name, "'" + v + "' is not a number");
  const Param& p = *find(name);
  if (d < p.min || (p.min_open && d == p.min) || d > p.max)
    throw error(name, v + " is out of range (" + range_text(p) + ")");
  return d;
}

std::int64_t Params::integer(const std::string& name) const {
  const std::string v = text(name);
  char* end = nullptr;
  const long long d = std::strtoll(v.c_str(), &end, 10);
  if (v.empty() || *end != '\0') throw error(name, "'" + v + "' is not an integer");
  const Param& p = *find(name);
  if (double(d) < p.min || double(d) > p.max) throw error(name, v + " is out of range (" + range_text(p) + ")");
  return d;
}

bool Params::flag(const std::string& name) const {
  const std::string v = text(name);
  bool b = false;
  if (!parse_bool(v, b)) throw error(name, "'" + v + "' is not true or false");
  return b;
}

std::vector<double> Params::numbers(const std::string& name) const {
  if (!cli_.count(name) && config_.is_list(name)) {
    std::vector<double> out = *config_.get_doubles(name);
    const Param& p = *find(name);
    for (double d : out)
      if (d < p.min || d > p.max) throw error(name, number_text(d) + " is out of range (" + range_text(p) + ")");
    return out;
  }
  std::vector<double> out;
  std::stringstream ss(text(name));
  std::string item;
  while (std::getline(ss, item, ',')) {
    double d = 0;
    if (!parse_double(item, d)) throw error(name, "'" + item + "' is not a number (a list is a,b,c)");
    out.push_back(d);
  }
  return out;
}

std::vector<std::string> Params::names(const std::string& name) const {
  std::vector<std::string> out;
  std::stringstream ss(text(name));
  std::string item;
  while (std::getline(ss, item, ','))
    if (!item.empty()) out.push_back(item);
  return out;
}

void Params::print_options(std::FILE* out) const {
  if (declared_.empty()) std::fprintf(out, "  (none)\n");
  for (const Param& p : declared_) {
    if (!p.moved_to.empty()) continue;
    std::string value;
    if (!p.is_flag)
      value = !p.value_name.empty()         ? " " + p.value_name
              : is_list(p.kind())           ? " A,B,.."
              : p.kind() == ParamType::Flag ? " true|false"
                                            : " VALUE";
    std::string left = "  " + (p.alias.empty() ? "" : p.alias + value + ", ") + "--" + p.name + value;
    if (p.positional) left = "  " + shown(p);
    if (p.rest) left = "  --" + p.name + " " + p.value_name;
    std::string extra;
    if (!p.choices.empty()) {
      for (const std::string& c : p.choices) extra += (extra.empty() ? " {" : "|") + c;
      extra += "}";
    }
    if (const std::string r = range_text(p); !r.empty()) extra += " (" + r + ")";
    if (!p.default_value.empty()) extra += " [default: " + p.default_value + "]";
    // Help from column 35, wrapped at column 110 so that a long description stays readable.
    const std::size_t first = std::max<std::size_t>(left.size(), 34) + 1;
    std::fprintf(out, "%-34s %s\n", left.c_str(), wrapped(p.help + extra, first, 35, 110).c_str());
  }
}

std::string Params::markdown() const {
  std::ostringstream md;
  md << "| key | type | default | range | what |\n|---|---|---|---|---|\n";
  for (const Param& p : declared_) {
    if (!p.moved_to.empty()) continue;
    std::string range = range_text(p);
    for (const std::string& c : p.choices) range += (range.empty() ? "" : " \\| ") + c;
    auto cell = [](const std::string& text) {  // a '|' inside a cell would end it
      std::string out;
      for (char c : text) out += c == '|' ? std::string("\\|") : std::string(1, c);
      return out;
    };
    const std::string help = cell(p.help);
    const std::string key = p.positional ? shown(p) + "` (argument)" : p.rest ? p.name + " ARG...`" : p.name + "`";
    md << "| `" << key << " | " << cell(type_name(p.kind())) << " | "
       << (p.default_value.empty() ? "" : "`" + p.default_value + "`") << " | " << range << " | " << help << " |\n";
  }
  return md.str();
}

}  // namespace hg::runtime
