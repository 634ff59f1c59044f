// hg-lcm-send: publishes hullgrind messages from the command line, for demos and tests (docs/monitoring.md).
#include <lcm/lcm-cpp.hpp>

#include <chrono>
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
#include "sample.hpp"
#include "runtime/version.hpp"

namespace {

using namespace hg::lcmtools;

volatile std::sig_atomic_t g_stop = 0;
void on_signal(int) { g_stop = 1; }

const char* kUsage = R"(usage: hg-lcm-send [--lcm-url URL] COMMAND [options]
Publishes hullgrind messages. --lcm-url default: $LCM_DEFAULT_URL, else udpm://239.255.76.67:7667?ttl=0.

  job --job-id J [--part-id P] [--action start|abort|reset] [--tool-radius R] [--chamfer-angle RAD]
      [--grind-speed M/S] [--travel-speed M/S] [--step M] [--safe-height M]
      [--direction climb|conventional] [--flipped] [--seq N] [--channel C]
      one job_request_t on HG_JOB_REQUEST (zero parameters mean "configured default").

  approve --job-id J --by NAME [--exclude-loops 3,5] [--revision N]
      APPROVE the plan the robot bridge holds AWAITING_APPROVAL (revision N, default 0: the latest), without
      the loops listed (their edge is recorded as excluded by "operator NAME").
  reject --job-id J --by NAME
      REJECT the plan held: the job ends REJECTED, nothing moves.
  replan --job-id J [--by NAME] [job parameters as for job]
      REPLAN a job awaiting approval on its outline with these parameters: the next plan revision.
  query [--job-id J]
      QUERY: every process answers its last status of job J (of every job it holds without --job-id).

  sample --type T[,T...]|all [--count N] [--rate HZ] [--start-seq S] [--channel C]
      N rounds (default 10; 0: until SIGINT/SIGTERM) of well-formed messages of each type, seq S..S+N-1,
      every field a function of seq (see docs/monitoring.md), header.utime the time of sending.
      "all" is every type that has a channel; default channel: the type's (runtime/channels.hpp).
      --rate is rounds per second (default 100; 0: as fast as possible).

  garbage --channel C [--count N] [--rate HZ] [--seed S]
      N messages (default 20) that must not decode, in turn: random bytes, a valid message cut short,
      a valid message with trailing bytes, a valid message whose header string length lies.

  heartbeat --process NAME [--pid PID] [--rate HZ] [--state-text TEXT]
      heartbeat_t on HG_HEARTBEAT at HZ (default 1) until SIGINT/SIGTERM, state OK, for a process that
      has no LCM library of its own (tools/supervisor announces itself so); --pid default: the parent's.

  json --type T --channel C JSON
      one message of type T given as JSON in hg-lcm-dump's --full form (its "msg" object).
)";

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

// The job parameters (START, REPLAN); false when `a` is none of them.
bool job_option(const std::string& a, Args& args, hullgrind::job_request_t& m) {
  if (a == "--part-id") m.part_id = args.value();
  else if (a == "--tool-radius")
    m.tool_radius = args.number(0, 1);
  else if (a == "--chamfer-angle")
    m.chamfer_angle = args.number(-1.6, 1.6);
  else if (a == "--grind-speed")
    m.grind_speed = args.number(0, 10);
  else if (a == "--travel-speed")
    m.travel_speed = args.number(0, 10);
  else if (a == "--step")
    m.step = args.number(0, 1);
  else if (a == "--safe-height")
    m.safe_height = args.number(0, 2);
  else if (a == "--direction") {
    std::string v = args.value();
    if (v == "climb") m.direction = hullgrind::job_request_t::DIRECTION_CLIMB;
    else if (v == "conventional")
      m.direction = hullgrind::job_request_t::DIRECTION_CONVENTIONAL;
    else
      throw UsageError("--direction: '" + v + "' is not climb or conventional");
  } else if (a == "--flipped")
    m.flipped = args.flag();
  else
    return false;
  return true;
}

std::int8_t action_of(const std::string& v) {
  using R = hullgrind::job_request_t;
  if (v == "start") return R::ACTION_START;
  if (v == "abort") return R::ACTION_ABORT;
  if (v == "reset") return R::ACTION_RESET;
  throw UsageError("--action: '" + v + "' is not start, abort or reset");
}

// job, approve, reject, replan, query: one job_request_t on HG_JOB_REQUEST.
int cmd_request(lcm::LCM& lcm, const std::string& command, Args& args) {
  using R = hullgrind::job_request_t;
  R m{};
  std::string channel = hg::channels::kJobRequest, by;
  m.action = command == "approve"  ? R::ACTION_APPROVE
             : command == "reject" ? R::ACTION_REJECT
             : command == "replan" ? R::ACTION_REPLAN
             : command == "query"  ? R::ACTION_QUERY
                                   : R::ACTION_START;
  bool have_id = false;
  while (!args.done()) {
    const std::string a = args.next();
    const bool job_like = command == "job" || command == "replan";
    if (a == "--job-id") m.job_id = args.value(), have_id = true;
    else if (job_like && job_option(a, args, m))
      continue;
    else if (a == "--action" && command == "job")
      m.action = action_of(args.value());
    else if (a == "--by" && command != "query")
      by = args.value();
    else if (a == "--exclude-loops" && command == "approve")
      m.excluded_loops = loop_list(args.value());
    else if (a == "--revision" && command == "approve")
      m.plan_revision = std::int32_t(args.integer(0, INT32_MAX));
    else if (a == "--seq")
      m.header.seq = args.integer(0, INT64_MAX);
    else if (a == "--channel")
      channel = args.value();
    else
      throw UsageError(command + ": unknown option '" + a + "'");
  }
  if (command != "query" && (!have_id || m.job_id.empty())) throw UsageError(command + ": --job-id is required");
  if ((command == "approve" || command == "reject") && by.empty())
    throw UsageError(command + ": --by NAME is required (the record keeps who decided)");
  if (!by.empty()) m.actor = "operator " + by;
  m.num_excluded = std::int32_t(m.excluded_loops.size());
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
int cmd_heartbeat(lcm::LCM& lcm, Args& args) {
  hullgrind::heartbeat_t m{};
  m.state = hullgrind::heartbeat_t::STATE_OK;
  m.last_latency = -1;
  double rate = 1;
  while (!args.done()) {
    std::string a = args.next();
    if (a == "--process") m.process = args.value();
    else if (a == "--pid")
      m.pid = static_cast<int32_t>(args.integer(0, INT32_MAX));
    else if (a == "--rate")
      rate = args.number(0.01, 1000);
    else if (a == "--state-text")
      m.state_text = args.value();
    else
      throw UsageError("heartbeat: unknown option '" + a + "'");
  }
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

int cmd_sample(lcm::LCM& lcm, const Schema& schema, Args& args) {
  std::string type_list, channel;
  long long count = 10, start_seq = 0;
  double rate = 100;
  while (!args.done()) {
    std::string a = args.next();
    if (a == "--type") type_list = args.value();
    else if (a == "--count")
      count = args.integer(0, 1LL << 40);
    else if (a == "--rate")
      rate = args.number(0, 1e6);
    else if (a == "--start-seq")
      start_seq = args.integer(0, 1LL << 40);
    else if (a == "--channel")
      channel = args.value();
    else
      throw UsageError("sample: unknown option '" + a + "'");
  }
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

int cmd_garbage(lcm::LCM& lcm, const Schema& schema, Args& args) {
  std::string channel;
  long long count = 20;
  double rate = 100;
  uint64_t seed = 1;
  while (!args.done()) {
    std::string a = args.next();
    if (a == "--channel") channel = args.value();
    else if (a == "--count")
      count = args.integer(0, 1LL << 40);
    else if (a == "--rate")
      rate = args.number(0, 1e6);
    else if (a == "--seed")
      seed = static_cast<uint64_t>(args.integer(0, INT64_MAX));
    else
      throw UsageError("garbage: unknown option '" + a + "'");
  }
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

int cmd_json(lcm::LCM& lcm, const Schema& schema, Args& args) {
  std::string type, channel, text;
  while (!args.done()) {
    std::string a = args.next();
    if (a == "--type") type = args.value();
    else if (a == "--channel")
      channel = args.value();
    else if (a.rfind("--", 0) != 0 && text.empty())
      text = a;
    else
      throw UsageError("json: unexpected argument '" + a + "'");
  }
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

}  // namespace

int main(int argc, char** argv) {
  if (hg::runtime::answer_version(argc, argv, "hg-lcm-send")) return 0;
  struct sigaction sa {};
  sa.sa_handler = on_signal;
  sigaction(SIGINT, &sa, nullptr);
  sigaction(SIGTERM, &sa, nullptr);
  try {
    std::string url = default_lcm_url();
    int first = 1;
    while (first < argc && std::string(argv[first]).rfind("--", 0) == 0) {
      std::string a = argv[first];
      if (a == "--help") {
        std::fputs(kUsage, stdout);
        return 0;
      } else if (a == "--lcm-url" && first + 1 < argc) {
        url = argv[first + 1];
        first += 2;
      } else if (a.rfind("--lcm-url=", 0) == 0) {
        url = a.substr(10);
        first += 1;
      } else {
        throw UsageError("unknown option '" + a + "' (see --help)");
      }
    }
    if (first >= argc) throw UsageError("no command (see --help)");
    std::string command = argv[first];
    Args args(argc, argv, first + 1);
    Schema schema = Schema::embedded();
    check_schema_matches_generated(schema);
    const bool request =
        command == "job" || command == "approve" || command == "reject" || command == "replan" || command == "query";
    if (!request && command != "sample" && command != "garbage" && command != "json" && command != "heartbeat")
      throw UsageError("unknown command '" + command + "' (see --help)");
    lcm::LCM lcm(url);
    if (!lcm.good()) {
      std::fprintf(stderr, "hg-lcm-send: cannot open LCM at %s\n", url.c_str());
      return 1;
    }
    if (request) return cmd_request(lcm, command, args);
    if (command == "heartbeat") return cmd_heartbeat(lcm, args);
    if (command == "sample") return cmd_sample(lcm, schema, args);
    if (command == "garbage") return cmd_garbage(lcm, schema, args);
    return cmd_json(lcm, schema, args);
  } catch (const UsageError& e) {
    std::fprintf(stderr, "hg-lcm-send: %s\n", e.what());
    return 2;
  } catch (const SchemaError& e) {
    std::fprintf(stderr, "hg-lcm-send: schema: %s\n", e.what());
    return 1;
  }
}
