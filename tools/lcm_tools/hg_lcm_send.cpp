// hg-lcm-send: publishes hullgrind messages from the command line, for demos and tests (docs/monitoring.md).
#include <lcm/lcm-cpp.hpp>

#include <algorithm>
#include <chrono>
#include <climits>
#include <cstdint>
#include <csignal>
#include <cstdio>
#include <random>
#include <sstream>
#include <string>
#include <thread>
#include <unistd.h>

#include "cli.hpp"
#include "hullgrind/heartbeat_t.hpp"
#include "hullgrind/job_request_t.hpp"
#include "registry.hpp"
#include "runtime/channels.hpp"
#include "runtime/quantities.hpp"
#include "sample.hpp"
#include "runtime/params.hpp"

namespace {

using namespace hg::lcmtools;

volatile std::sig_atomic_t g_stop = 0;
void on_signal(int) { g_stop = 1; }

const char* kUsageHead = R"(usage: hg-lcm-send [--lcm-url URL] COMMAND [options]
Publishes hullgrind messages; COMMAND --help lists only that command's options.
)";

using hg::runtime::Param;

// The job parameters of job and replan (not given: 0, "configured default"); the quantities' ranges are the
// ones the planner and the DDS gateway check (runtime/quantities.hpp).
std::vector<Param> job_params() {
  using namespace hg::runtime;
  std::vector<Param> p = {text_param("part-id", "", "the part")};
  const hullgrind::job_request_t fields{};
  hg::quantity::for_each_job_quantity(
      [&p](const hg::quantity::Quantity& q, double) { p.push_back(quantity_param(q, "", "not given: the default")); },
      fields);
  p.push_back(text_param("direction", "", "grinding direction", hg::job::direction_names()));
  p.push_back(flag_param("flipped", "plan for the flipped part"));
  return p;
}

// job, approve, reject, replan, query: one job_request_t on HG_JOB_REQUEST.
std::vector<Param> request_params(const std::string& command) {
  using namespace hg::runtime;
  std::vector<Param> p = {
      text_param("job-id", "", command == "query" ? "the job (default: every job)" : "the job (required)")};
  if (command == "job" || command == "replan")
    for (Param& q : job_params()) p.push_back(std::move(q));
  if (command == "job") p.push_back(text_param("action", "start", "the request's action", {"start", "abort", "reset"}));
  if (command != "query" && command != "job")
    p.push_back(text_param("by", "", command == "replan" ? "the operator asking" : "the operator deciding (required)"));
  if (command == "approve") {
    p.push_back(text_param("exclude-loops", "", "outline loops not to grind, e.g. 3,5 (recorded as excluded)"));
    p.push_back(integer_param("revision", "0", "the plan revision approved (0: the latest)", 0, INT32_MAX));
  }
  p.push_back(integer_param("seq", "0", "header.seq", 0, double(INT64_MAX)));
  p.push_back(text_param("channel", hg::channels::kJobRequest, "the channel"));
  return p;
}

struct Command {
  std::string name, summary;
  std::vector<Param> params;
};

// Every command with its options, declared once: parsing, checks, --help and --help-markdown.
std::vector<Command> commands() {
  using namespace hg::runtime;
  const double big = double(1LL << 40);
  return {
      {"job", "one job_request_t on HG_JOB_REQUEST (zero parameters mean \"configured default\")",
       request_params("job")},
      {"approve",
       "APPROVE the plan the robot bridge holds AWAITING_APPROVAL, without the loops listed (their edge is "
       "recorded as excluded by \"operator NAME\")",
       request_params("approve")},
      {"reject", "REJECT the plan held: the job ends REJECTED, nothing moves", request_params("reject")},
      {"replan", "REPLAN a job awaiting approval on its outline with these parameters: the next plan revision",
       request_params("replan")},
      {"query", "QUERY: every process answers its last status of the job (of every job it holds without --job-id)",
       request_params("query")},
      {"sample",
       "N rounds of well-formed messages of each type, seq S..S+N-1, every field a function of seq "
       "(docs/monitoring.md), header.utime the time of sending",
       {text_param("type", "", "T[,T...] or all (every type that has a channel) (required)"),
        integer_param("count", "10", "rounds; 0: until SIGINT/SIGTERM", 0, big),
        number_param("rate", "100", "rounds per second; 0: as fast as possible", 0, 1e6),
        integer_param("start-seq", "0", "seq of the first round", 0, big),
        text_param("channel", "", "the channel (default: the type's, runtime/channels.hpp)")}},
      {"garbage",
       "N messages that must not decode, in turn: random bytes, a valid message cut short, a valid message "
       "with trailing bytes, a valid message whose header string length lies",
       {text_param("channel", "", "the channel (required)"), integer_param("count", "20", "messages", 0, big),
        number_param("rate", "100", "messages per second; 0: as fast as possible", 0, 1e6),
        integer_param("seed", "1", "random seed", 0, double(INT64_MAX))}},
      {"heartbeat",
       "heartbeat_t on HG_HEARTBEAT until SIGINT/SIGTERM, state OK, for a process that has no LCM library of "
       "its own (tools/supervisor announces itself so)",
       {text_param("process", "", "the process's name (required)"),
        integer_param("pid", "0", "its pid (0: the parent's)", 0, INT32_MAX),
        number_param("rate", "1", "heartbeats per second", 0.01, 1000),
        text_param("state-text", "", "the heartbeat's state_text")}},
      {"json",
       "one message of type T given as JSON in hg-lcm-dump's --full form (its \"msg\" object)",
       {text_param("type", "", "the message type (required)"), text_param("channel", "", "the channel (required)"),
        positional(text_param("json", "", "the message as JSON (required)"))}},
  };
}

std::vector<Param> global_params() {
  std::vector<Param> params = {hg::runtime::text_param(
      "lcm-url", default_lcm_url(), "LCM provider [$LCM_DEFAULT_URL, else udpm://239.255.76.67:7667?ttl=0]")};
  hg::runtime::set_value_names(params, {{"lcm-url", "URL"}});
  return params;
}

void usage(std::FILE* f, const hg::runtime::Params& global) {
  std::fputs(kUsageHead, f);
  std::fputs("Options before COMMAND:\n", f);
  global.print_options(f);
  std::fputs("  --help, --help-markdown, --version this text, the options as Markdown tables, the version\n", f);
  for (const Command& c : commands()) {
    std::fprintf(f, "\n%s: %s\n", c.name.c_str(), c.summary.c_str());
    hg::runtime::Params(c.params).print_options(f);
  }
}

std::string markdown(const hg::runtime::Params& global) {
  std::string md = global.markdown();
  for (const Command& c : commands())
    md += "\n### hg-lcm-send " + c.name + "\n\n" + c.summary + ".\n\n" + hg::runtime::Params(c.params).markdown();
  return md;
}

struct Pacer {
  double rate;
  std::chrono::steady_clock::time_point start = std::chrono::steady_clock::now();
  long long n = 0;
  void wait() {
    if (rate <= 0) return;
    auto due = start + std::chrono::duration_cast<std::chrono::steady_clock::duration>(
                           std::chrono::duration<double>(static_cast<double>(n++) / rate));
    while (!g_stop && std::chrono::steady_clock::now() < due)
      std::this_thread::sleep_for(std::min<std::chrono::steady_clock::duration>(due - std::chrono::steady_clock::now(),
                                                                                std::chrono::milliseconds(100)));
  }
};

int64_t now_utime() {
  return std::chrono::duration_cast<std::chrono::microseconds>(std::chrono::system_clock::now().time_since_epoch())
      .count();
}

bool publish(lcm::LCM& lcm, const std::string& channel, const std::vector<uint8_t>& bytes) {
  if (lcm.publish(channel, bytes.data(), static_cast<unsigned>(bytes.size())) != 0) {
    std::fprintf(stderr, "hg-lcm-send: publish of %zu bytes on %s failed\n", bytes.size(), channel.c_str());
    return false;
  }
  return true;
}

// "3,5" -> {3, 5}: loop indices of the outline (0..32767).
std::vector<std::int16_t> loop_list(const std::string& text) {
  std::vector<std::int16_t> out;
  std::stringstream ss(text);
  for (std::string item; std::getline(ss, item, ',');) {
    std::size_t used = 0;
    long v = -1;
    try {
      v = std::stol(item, &used);
    } catch (const std::exception&) {
      used = 0;
    }
    if (used == 0 || used != item.size() || v < 0 || v > 32767)
      throw UsageError("--exclude-loops: '" + item + "' is not a loop index (0..32767)");
    out.push_back(std::int16_t(v));
  }
  if (out.empty()) throw UsageError("--exclude-loops: no loop given");
  return out;
}

// The job parameters given (START, REPLAN) into the request; those not given stay 0, "configured default".
void set_job_params(const hg::runtime::Params& p, hullgrind::job_request_t& m) {
  m.part_id = p.text("part-id");
  hg::quantity::for_each_job_quantity(
      [&p](const hg::quantity::Quantity& q, double& to) {
        if (p.given(hg::quantity::key(q))) to = p.number(hg::quantity::key(q));
      },
      m);
  if (p.given("direction")) m.direction = std::int8_t(*hg::job::direction_from_name(p.text("direction")));
  m.flipped = p.flag("flipped");
}

std::int8_t action_of(const std::string& v) {
  using R = hullgrind::job_request_t;
  return v == "abort" ? R::ACTION_ABORT : v == "reset" ? R::ACTION_RESET : R::ACTION_START;
}

// job, approve, reject, replan, query: the request the command line asks for. Throws UsageError.
hullgrind::job_request_t request_of(const std::string& command, const hg::runtime::Params& p) {
  using R = hullgrind::job_request_t;
  R m{};
  m.action = command == "approve"  ? R::ACTION_APPROVE
             : command == "reject" ? R::ACTION_REJECT
             : command == "replan" ? R::ACTION_REPLAN
             : command == "query"  ? R::ACTION_QUERY
                                   : action_of(p.text("action"));
  m.job_id = p.text("job-id");
  if (command == "job" || command == "replan") set_job_params(p, m);
  const std::string by = p.find("by") ? p.text("by") : "";
  if (command == "approve") {
    if (p.given("exclude-loops")) m.excluded_loops = loop_list(p.text("exclude-loops"));
    m.plan_revision = std::int32_t(p.integer("revision"));
  }
  m.header.seq = p.integer("seq");
  if (command != "query" && m.job_id.empty()) throw UsageError(command + ": --job-id is required");
  if ((command == "approve" || command == "reject") && by.empty())
    throw UsageError(command + ": --by NAME is required (the record keeps who decided)");
  if (!by.empty()) m.actor = "operator " + by;
  m.num_excluded = std::int32_t(m.excluded_loops.size());
  return m;
}

int cmd_request(lcm::LCM& lcm, const std::string& command, const hg::runtime::Params& p) {
  hullgrind::job_request_t m = request_of(command, p);
  const std::string channel = p.text("channel");
  m.header.utime = now_utime();
  if (lcm.publish(channel, &m) != 0) {
    std::fprintf(stderr, "hg-lcm-send: publish on %s failed\n", channel.c_str());
    return 1;
  }
  std::fprintf(stderr, "hg-lcm-send: published job_request_t (%s, action %d) job_id=%s on %s\n", command.c_str(),
               int(m.action), m.job_id.c_str(), channel.c_str());
  return 0;
}

// A heartbeat_t for a process that has no LCM library of its own (the Python supervisor announces itself
// on the bus with it), once per period until SIGINT/SIGTERM.
int cmd_heartbeat(lcm::LCM& lcm, const hg::runtime::Params& p) {
  hullgrind::heartbeat_t m{};
  m.state = hullgrind::heartbeat_t::STATE_OK;
  m.last_latency = -1;
  m.process = p.text("process");
  m.pid = static_cast<int32_t>(p.integer("pid"));
  const double rate = p.number("rate");
  m.state_text = p.text("state-text");
  if (m.process.empty()) throw UsageError("heartbeat: --process is required");
  if (m.pid == 0) m.pid = static_cast<int32_t>(getppid());
  const auto start = std::chrono::steady_clock::now();
  Pacer pacer{rate};
  while (!g_stop) {
    pacer.wait();
    if (g_stop) break;
    m.header.utime = now_utime();
    m.uptime = std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
    if (lcm.publish(hg::channels::kHeartbeat, &m) != 0) {
      std::fprintf(stderr, "hg-lcm-send: publish on %s failed\n", hg::channels::kHeartbeat);
      return 1;
    }
    ++m.header.seq;
  }
  return 0;
}

std::vector<const Struct*> parse_types(const Schema& schema, const std::string& list) {
  if (list == "all") return message_types(schema);
  std::vector<const Struct*> out;
  std::stringstream ss(list);
  std::string name;
  while (std::getline(ss, name, ',')) {
    const Struct* s = schema.find(name);
    if (!s) throw UsageError("unknown type '" + name + "'");
    out.push_back(s);
  }
  if (out.empty()) throw UsageError("--type is empty");
  return out;
}

int cmd_sample(lcm::LCM& lcm, const Schema& schema, const hg::runtime::Params& p) {
  const std::string type_list = p.text("type"), channel = p.text("channel");
  const long long count = p.integer("count"), start_seq = p.integer("start-seq");
  const double rate = p.number("rate");
  if (type_list.empty()) throw UsageError("sample: --type is required");
  std::vector<const Struct*> types = parse_types(schema, type_list);
  Pacer pacer{rate};
  long long sent = 0;
  for (long long i = 0; (count == 0 || i < count) && !g_stop; ++i) {
    pacer.wait();
    if (g_stop) break;
    for (const Struct* t : types) {
      std::string ch = !channel.empty() ? channel : default_channel(*t);
      if (ch.empty()) ch = "HG_SAMPLE_" + t->name;
      if (!publish(lcm, ch, schema.encode(*t, sample_message(schema, *t, start_seq + i, now_utime())))) return 1;
      ++sent;
    }
  }
  std::fprintf(stderr, "hg-lcm-send: published %lld sample messages\n", sent);
  return 0;
}

// Messages that must fail to decode, each for a different reason.
std::vector<uint8_t> garbage_message(const Schema& schema, long long i, std::mt19937_64& rng) {
  std::vector<const Struct*> types = message_types(schema);
  const Struct* t = types[static_cast<std::size_t>(i / 4) % types.size()];
  std::vector<uint8_t> valid = schema.encode(*t, sample_message(schema, *t, i, now_utime()));
  switch (i % 4) {
    case 0: {  // random bytes; re-drawn in the 1-in-2^60 case of a known fingerprint
      std::vector<uint8_t> b;
      do {
        b.resize(std::uniform_int_distribution<std::size_t>(0, 300)(rng));
        for (auto& x : b) x = static_cast<uint8_t>(rng());
      } while (decode_message(schema, b.data(), b.size(), {}).type);
      return b;
    }
    case 1:  // cut short
      valid.resize(std::uniform_int_distribution<std::size_t>(0, valid.size() - 1)(rng));
      return valid;
    case 2:  // trailing bytes
      for (int k = std::uniform_int_distribution<int>(1, 16)(rng); k > 0; --k)
        valid.push_back(static_cast<uint8_t>(rng()));
      return valid;
    default: {  // header.frame_id length lies (fingerprint 8 + seq 8 + utime 8 = byte 24): huge, negative, zero
      static const uint32_t lies[] = {0x7fffffffu, 0xffffffffu, 0u};
      uint32_t lie = lies[static_cast<std::size_t>(i / 4) % 3];
      for (int k = 0; k < 4; ++k) valid[24 + k] = static_cast<uint8_t>(lie >> (24 - 8 * k));
      return valid;
    }
  }
}

int cmd_garbage(lcm::LCM& lcm, const Schema& schema, const hg::runtime::Params& p) {
  const std::string channel = p.text("channel");
  const long long count = p.integer("count");
  const double rate = p.number("rate");
  const uint64_t seed = static_cast<uint64_t>(p.integer("seed"));
  if (channel.empty()) throw UsageError("garbage: --channel is required");
  for (const Struct* t : message_types(schema))
    if (t->members.empty() || t->members[0].type_name != "hullgrind.header_t")
      throw UsageError("garbage: " + t->full_name() + " does not start with a header_t");
  std::mt19937_64 rng(seed);
  Pacer pacer{rate};
  long long sent = 0;
  for (long long i = 0; i < count && !g_stop; ++i) {
    pacer.wait();
    if (!publish(lcm, channel, garbage_message(schema, i, rng))) return 1;
    ++sent;
  }
  std::fprintf(stderr, "hg-lcm-send: published %lld garbage messages on %s\n", sent, channel.c_str());
  return 0;
}

int cmd_json(lcm::LCM& lcm, const Schema& schema, const hg::runtime::Params& p) {
  const std::string type = p.text("type"), channel = p.text("channel"), text = p.text("json");
  if (type.empty() || channel.empty() || text.empty()) throw UsageError("json: needs --type, --channel and JSON");
  const Struct* t = schema.find(type);
  if (!t) throw UsageError("unknown type '" + type + "'");
  Json value = Json::parse(text, nullptr, false);
  if (value.is_discarded()) throw UsageError("json: the message is not valid JSON");
  std::vector<uint8_t> bytes;
  try {
    bytes = schema.encode(*t, value);
  } catch (const std::invalid_argument& e) {
    throw UsageError(std::string("json: ") + e.what());
  }
  if (!publish(lcm, channel, bytes)) return 1;
  std::fprintf(stderr, "hg-lcm-send: published %s (%zu bytes) on %s\n", t->full_name().c_str(), bytes.size(),
               channel.c_str());
  return 0;
}

// The command's own options (argv from the command word on); -1 to run, else the exit code.
int parse_command(hg::runtime::Params& p, const std::vector<std::string>& rest, const std::string& command) {
  std::vector<const char*> argv;
  for (const std::string& a : rest) argv.push_back(a.c_str());
  const auto help = [&](std::FILE* f, const hg::runtime::Params& params) {
    std::fprintf(f, "usage: hg-lcm-send [--lcm-url URL] %s [options]\n", command.c_str());
    params.print_options(f);
  };
  return hg::runtime::parse_tool(p, int(argv.size()), argv.data(), "hg-lcm-send " + command, help);
}

int run(const std::string& url, const std::string& command, const hg::runtime::Params& p) {
  Schema schema = Schema::embedded();
  check_schema_matches_generated(schema);
  lcm::LCM lcm(url);
  if (!lcm.good()) {
    std::fprintf(stderr, "hg-lcm-send: cannot open LCM at %s\n", url.c_str());
    return 1;
  }
  if (command == "heartbeat") return cmd_heartbeat(lcm, p);
  if (command == "sample") return cmd_sample(lcm, schema, p);
  if (command == "garbage") return cmd_garbage(lcm, schema, p);
  if (command == "json") return cmd_json(lcm, schema, p);
  return cmd_request(lcm, command, p);
}

}  // namespace

int main(int argc, char** argv) {
  struct sigaction sa {};
  sa.sa_handler = on_signal;
  sigaction(SIGINT, &sa, nullptr);
  sigaction(SIGTERM, &sa, nullptr);
  hg::runtime::Params global(global_params());
  global.stop_at_command();
  try {
    using Action = hg::runtime::Params::Action;
    const Action action = global.parse(argc, argv);
    if (action == Action::HelpMarkdown) return std::fputs(markdown(global).c_str(), stdout), 0;
    if (action != Action::Run) return hg::runtime::answer(action, "hg-lcm-send", global, usage);
  } catch (const std::exception& e) {  // runtime::ConfigError: names the option
    std::fprintf(stderr, "hg-lcm-send: %s (see --help)\n", e.what());
    return 2;
  }
  try {
    if (global.positional().empty()) throw UsageError("no command (see --help)");
    const std::string command = global.positional()[0];
    std::vector<Command> all = commands();
    auto c = std::find_if(all.begin(), all.end(), [&](const Command& x) { return x.name == command; });
    if (c == all.end()) throw UsageError("unknown command '" + command + "' (see --help)");
    hg::runtime::Params p(c->params);
    if (const int rc = parse_command(p, global.positional(), command); rc >= 0) return rc;
    if (command != "heartbeat" && command != "sample" && command != "garbage" && command != "json")
      request_of(command, p);  // a missing --job-id or --by is refused before LCM is opened
    return run(global.text("lcm-url"), command, p);
  } catch (const UsageError& e) {
    std::fprintf(stderr, "hg-lcm-send: %s\n", e.what());
    return 2;
  } catch (const SchemaError& e) {
    std::fprintf(stderr, "hg-lcm-send: schema: %s\n", e.what());
    return 1;
  }
}
