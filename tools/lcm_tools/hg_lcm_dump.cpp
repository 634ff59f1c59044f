// hg-lcm-dump: prints every hullgrind message on the bus as one JSON object per line (docs/monitoring.md).
#include <lcm/lcm-cpp.hpp>

#include <chrono>
#include <csignal>
#include <cstdio>
#include <iostream>
#include <map>
#include <string>
#include <vector>

#include "cli.hpp"
#include "registry.hpp"
#include "runtime/params.hpp"

namespace {

using namespace hg::lcmtools;

volatile std::sig_atomic_t g_stop = 0;
void on_signal(int) { g_stop = 1; }

const char* kUsageHead = R"(usage: hg-lcm-dump [options]
Subscribes to LCM channels and prints each hullgrind message as one JSON line on stdout:
  {"channel": C, "type": "hullgrind.T", "recv_utime": U, "msg": {fields...}}
A message that does not decode (unknown fingerprint, truncated, trailing bytes) prints
  {"channel": C, "recv_utime": U, "size": BYTES, "error": "why"}
and is counted; the dump keeps running. Arrays longer than 8 elements print as
{"length": N, "first": [8 elements]} unless --full.
Exit codes: 0 done, 1 LCM failure, 2 bad usage, 3 timed out before --count.

)";

std::vector<hg::runtime::Param> dump_params() {
  using namespace hg::runtime;
  std::vector<Param> params = {
      text_param("lcm-url", default_lcm_url(), "LCM provider [$LCM_DEFAULT_URL, else udpm://239.255.76.67:7667?ttl=0]"),
      text_param("channels", "HG_.*", "channels to subscribe to (a regular expression)"),
      text_param("type", "", "print only this type (\"heartbeat_t\" or \"hullgrind.heartbeat_t\")"),
      integer_param("count", "", "exit after N printed messages", 0, double(1LL << 62)),
      number_param("timeout", "", "exit after S seconds (exit code 3 if --count was not reached by then)", 0, 1e9),
      flag_param("full", "print arrays in full"),
      flag_param("summary", "at exit, print per-channel counts and decode errors to stderr")};
  set_value_names(params,
                  {{"lcm-url", "URL"}, {"channels", "REGEX"}, {"type", "NAME"}, {"count", "N"}, {"timeout", "S"}});
  return params;
}

struct ChannelStats {
  long long decoded = 0;  // decoded, whether printed or filtered out by --type
  long long errors = 0;
  std::map<std::string, long long> types;
};

struct Dump {
  const Schema& schema;
  DecodeOptions opt;
  std::string type_filter;  // full name, "" for all
  long long count_limit = -1;
  long long printed = 0;
  bool output_closed = false;
  std::map<std::string, ChannelStats> stats;

  void emit(const Json& line) {
    std::string text = line.dump(-1, ' ', false, Json::error_handler_t::replace) + "\n";
    if (std::fwrite(text.data(), 1, text.size(), stdout) != text.size() || std::fflush(stdout) != 0)
      output_closed = true;  // the reader went away: stop quietly
  }

  void on_message(const lcm::ReceiveBuffer* rbuf, const std::string& channel) {
    if (count_limit >= 0 && printed >= count_limit) return;
    ChannelStats& st = stats[channel];
    const auto* data = static_cast<const uint8_t*>(rbuf->data);
    std::size_t size = rbuf->data_size;
    Decoded d = decode_message(schema, data, size, opt);
    if (!d.type) {
      ++st.errors;
      Json line;
      line["channel"] = channel;
      line["recv_utime"] = rbuf->recv_utime;
      line["size"] = size;
      line["error"] = d.error;
      emit(line);
      return;
    }
    ++st.decoded;
    std::string type = d.type->full_name();
    ++st.types[type];
    if (!type_filter.empty() && type != type_filter) return;
    Json line;
    line["channel"] = channel;
    line["type"] = type;
    line["recv_utime"] = rbuf->recv_utime;
    line["msg"] = std::move(d.msg);
    emit(line);
    ++printed;
  }
};

}  // namespace

struct DumpArgs {
  std::string url = default_lcm_url();
  std::string channels = "HG_.*";
  std::string type_name;
  long long count = -1;
  double timeout = -1;
  bool summary = false;
  DecodeOptions opt;
};

// The command line into `a`; -1 to go on, else the exit code (0 after --help, 2 on a usage error).
int parse_args(int argc, char** argv, DumpArgs& a) {
  hg::runtime::Params p(dump_params());
  if (const int rc = hg::runtime::parse_tool(p, argc, argv, "hg-lcm-dump", hg::runtime::usage_with(kUsageHead));
      rc >= 0)
    return rc;
  if (!p.positional().empty()) {
    std::fprintf(stderr, "hg-lcm-dump: command line: unexpected argument '%s' (see --help)\n",
                 p.positional()[0].c_str());
    return 2;
  }
  a.url = p.text("lcm-url");
  a.channels = p.text("channels");
  a.type_name = p.text("type");
  if (p.given("count")) a.count = p.integer("count");
  if (p.given("timeout")) a.timeout = p.number("timeout");
  a.opt.full = p.flag("full");
  a.summary = p.flag("summary");
  return -1;
}

// Handles messages until a signal, the count, closed output or the timeout; 1 if LCM failed, 3 if the
// timeout came before the count, else 0.
int receive(lcm::LCM& lcm, const Dump& dump, long long count, double timeout) {
  using clock = std::chrono::steady_clock;
  const auto deadline =
      clock::now() + std::chrono::duration_cast<clock::duration>(std::chrono::duration<double>(timeout));
  while (!g_stop && !dump.output_closed && !(count >= 0 && dump.printed >= count)) {
    int wait_ms = 100;  // short, so a signal is noticed quickly
    if (timeout >= 0) {
      auto left = std::chrono::duration_cast<std::chrono::milliseconds>(deadline - clock::now()).count();
      if (left <= 0) return count >= 0 && dump.printed < count ? 3 : 0;
      wait_ms = static_cast<int>(std::min<long long>(left, wait_ms));
    }
    if (lcm.handleTimeout(wait_ms) < 0 && !g_stop) {
      std::fprintf(stderr, "hg-lcm-dump: LCM receive failed\n");
      return 1;
    }
  }
  return 0;
}

void print_summary(const Dump& dump) {
  long long decoded = 0, errors = 0;
  for (const auto& [channel, st] : dump.stats) {
    std::string types;
    for (const auto& [t, n] : st.types) types += " " + t + "=" + std::to_string(n);
    std::fprintf(stderr, "hg-lcm-dump: summary %s decoded %lld errors %lld%s\n", channel.c_str(), st.decoded, st.errors,
                 types.c_str());
    decoded += st.decoded;
    errors += st.errors;
  }
  std::fprintf(stderr, "hg-lcm-dump: summary total decoded %lld printed %lld errors %lld\n", decoded, dump.printed,
               errors);
}

int main(int argc, char** argv) {
  DumpArgs a;
  if (const int rc = parse_args(argc, argv, a); rc >= 0) return rc;

  Schema schema;
  try {
    schema = Schema::embedded();
    check_schema_matches_generated(schema);
  } catch (const SchemaError& e) {
    std::fprintf(stderr, "hg-lcm-dump: schema: %s\n", e.what());
    return 1;
  }
  Dump dump{schema, a.opt, "", a.count, 0, false, {}};
  if (!a.type_name.empty()) {
    const Struct* t = schema.find(a.type_name);
    if (!t) {
      std::fprintf(stderr, "hg-lcm-dump: unknown type '%s'\n", a.type_name.c_str());
      return 2;
    }
    dump.type_filter = t->full_name();
  }

  struct sigaction sa {};
  sa.sa_handler = on_signal;
  sigaction(SIGINT, &sa, nullptr);
  sigaction(SIGTERM, &sa, nullptr);
  std::signal(SIGPIPE, SIG_IGN);

  lcm::LCM lcm(with_receive_buffer(a.url));  // big clouds: see runtime/lcm_url.hpp
  if (!lcm.good()) {
    std::fprintf(stderr, "hg-lcm-dump: cannot open LCM at %s\n", a.url.c_str());
    return 1;
  }
  lcm.subscribe(a.channels, &Dump::on_message, &dump);
  // Tests and the supervisor wait for this line before publishing.
  std::fprintf(stderr, "hg-lcm-dump: listening on %s channels %s\n", a.url.c_str(), a.channels.c_str());
  std::fflush(stderr);

  const int rc = receive(lcm, dump, a.count, a.timeout);
  if (rc == 1) return 1;
  if (a.summary) print_summary(dump);
  return rc;
}
