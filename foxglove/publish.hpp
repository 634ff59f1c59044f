// Client publishing on hg-foxglove (--client-publish): who may publish and what. Only HG_JOB_REQUEST, only
// by an operator of the operator station's users file (station/auth.hpp: the same names, roles and argon2id
// hashes, the same login rate limit), who logs in with HTTP Basic on the WebSocket upgrade
// (ws://USER:PASSWORD@127.0.0.1:8765). A client without credentials connects read-only; wrong credentials
// are refused (HTTP 401). A published message is the job_request_t's JSON (the fields it leaves out are
// zero); its actor is always "operator USER" of the login, whatever the client wrote.
#pragma once

#include <string>
#include <string_view>

#include "foxglove/ws_server.hpp"
#include "runtime/node.hpp"
#include "station/auth.hpp"
#include "tools/lcm_tools/lcm_schema.hpp"

namespace hg::foxglove {

class JobRequestGate {
 public:
  // Reads the users file (station::UsersError naming the file and line when it is bad).
  JobRequestGate(runtime::Node& node, const std::string& users_file);

  WsIdentity identify(const std::string& authorization, const std::string& peer);
  // Publishes the JSON payload as job_request_t on HG_JOB_REQUEST; why not, if it does not.
  std::string publish(const WsClientChannel& channel, const std::string& user, std::string_view payload);

 private:
  runtime::Node& node_;
  std::vector<station::User> users_;
  station::LoginLimiter limiter_;
  lcmtools::Schema schema_;
};

// The job_request_t of a client's JSON text: its fields over a zero message. Throws std::invalid_argument
// saying what is wrong (not JSON, not an object, a field the type does not have, a wrong value).
std::vector<std::uint8_t> job_request_bytes(const lcmtools::Schema& schema, std::string_view json_text);

}  // namespace hg::foxglove
