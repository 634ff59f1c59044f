// libFuzzer target: hg-station's request handling without sockets (target parsing, routing, login, session
// and CSRF checks, JSON bodies, option validation, static-file and record paths). The input is split into
// method, target, cookie, CSRF token and body at the first four newlines. One operator session exists, so
// inputs that carry its cookie and token reach the POST handlers too.
#include <cstdint>
#include <filesystem>
#include <string>

#include "station/api.hpp"

namespace {

using namespace hg::station;

struct World {
  Sessions sessions{std::chrono::seconds(3600)};
  LoginLimiter limiter;
  LiveState live{LiveOptions{}};
  History history{std::filesystem::temp_directory_path() / "hg-station-fuzz-jobs"};
  Session op;
  std::unique_ptr<Api> api;
  World() {
    ApiConfig c;
    c.web_root = std::filesystem::temp_directory_path() / "hg-station-fuzz-web";
    // A cheap fake hash: the fuzzer must not spend its time in argon2id; verify_password rejects it.
    api = std::make_unique<Api>(c, std::vector<User>{{"op", Role::Operator, "$argon2id$fake"}}, sessions, limiter, live,
                                history, [](auto&) { return true; });
    op = sessions.create("op", Role::Operator, std::chrono::steady_clock::now());
  }
};

}  // namespace

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  static World world;
  std::string in(reinterpret_cast<const char*>(data), size);
  std::string part[5];
  for (int i = 0; i < 4; ++i) {
    const std::size_t nl = in.find('\n');
    part[i] = in.substr(0, nl);
    in = nl == std::string::npos ? "" : in.substr(nl + 1);
  }
  part[4] = in;
  HttpRequest r;
  r.method = part[0] == "P" ? "POST" : part[0] == "G" ? "GET" : part[0];
  r.target = part[1];
  r.cookie = part[2] == "S" ? std::string(Api::kCookie) + "=" + world.op.id : part[2];
  r.csrf = part[3] == "T" ? world.op.csrf : part[3];
  r.content_type = "application/json";
  r.body = part[4];
  r.peer = "fuzz";
  HttpResponse res = world.api->handle(r);
  if (res.status < 200 || res.status > 599) __builtin_trap();
  return 0;
}
