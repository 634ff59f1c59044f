#include "foxglove/publish.hpp"

#include <sodium.h>

#include <algorithm>
#include <chrono>
#include <stdexcept>

#include "hullgrind/job_request_t.hpp"
#include "runtime/channels.hpp"
#include "runtime/log.hpp"

namespace hg::foxglove {

namespace {

// Standard base64 (RFC 4648), padded as RFC 7617 sends it or not; false on anything else (libsodium's decoder).
bool decode_base64(const std::string& coded, std::string& out) {
  for (const int variant : {sodium_base64_VARIANT_ORIGINAL, sodium_base64_VARIANT_ORIGINAL_NO_PADDING}) {
    out.assign(coded.size() / 4 * 3 + 3, '\0');
    std::size_t length = 0;
    const char* end = nullptr;
    if (sodium_base642bin(reinterpret_cast<unsigned char*>(out.data()), out.size(), coded.data(), coded.size(), nullptr,
                          &length, &end, variant) == 0 &&
        end == coded.data() + coded.size()) {
      out.resize(length);
      return true;
    }
  }
  out.clear();
  return false;
}

// "Basic base64(user:password)" -> {user, password}; false if it is not that.
bool basic_credentials(const std::string& header, std::string& user, std::string& password) {
  const std::string prefix = "Basic ";
  if (header.size() <= prefix.size() || header.size() > 4096 || header.compare(0, prefix.size(), prefix) != 0)
    return false;
  std::string text;
  if (!decode_base64(header.substr(prefix.size()), text)) return false;
  const auto colon = text.find(':');
  if (colon == std::string::npos) return false;
  user = text.substr(0, colon);
  password = text.substr(colon + 1);
  return true;
}

}  // namespace

std::vector<std::uint8_t> job_request_bytes(const lcmtools::Schema& schema, std::string_view json_text) {
  const lcmtools::Struct* type = schema.find("hullgrind.job_request_t");
  if (!type) throw std::logic_error("no job_request_t in the schema");
  lcmtools::Json given = lcmtools::Json::parse(json_text, nullptr, false);
  if (given.is_discarded() || !given.is_object()) throw std::invalid_argument("HG_JOB_REQUEST: not a JSON object");
  hullgrind::job_request_t zero{};
  std::vector<std::uint8_t> bytes(std::size_t(zero.getEncodedSize()));
  zero.encode(bytes.data(), 0, int(bytes.size()));
  std::size_t used = 0;
  lcmtools::Json msg = schema.decode(*type, bytes.data(), bytes.size(), used, lcmtools::DecodeOptions{true});
  for (auto& [key, value] : given.items()) {
    if (!msg.contains(key)) throw std::invalid_argument("HG_JOB_REQUEST: job_request_t has no field '" + key + "'");
    msg[key] = value;
  }
  try {
    return schema.encode(*type, msg);
  } catch (const std::exception& e) {
    throw std::invalid_argument(std::string("HG_JOB_REQUEST: ") + e.what());
  }
}

JobRequestGate::JobRequestGate(runtime::Node& node, const std::string& users_file)
    : node_(node), users_(station::read_users(users_file)), schema_(lcmtools::Schema::embedded()) {}

WsIdentity JobRequestGate::identify(const std::string& authorization, const std::string& peer) {
  WsIdentity who;
  if (authorization.empty()) return who;  // anonymous: read-only
  std::string user, password;
  if (!basic_credentials(authorization, user, password)) {
    who.refusal = "Authorization: only Basic with a user of the station's users file";
    return who;
  }
  const auto now = std::chrono::steady_clock::now();
  const std::string user_key = "user " + user.substr(0, 64), peer_key = "peer " + peer;
  if (std::max(limiter_.wait_seconds(user_key, now), limiter_.wait_seconds(peer_key, now)) > 0) {
    who.refusal = "too many failed logins: try again later";
    return who;
  }
  for (const station::User& u : users_)
    if (u.name == user && password.size() <= 1024 && station::verify_password(u.hash, password)) {
      limiter_.succeeded(user_key);
      who.user = u.name;
      who.may_publish = u.role == station::Role::Operator;
      return who;
    }
  limiter_.failed(user_key, now);
  limiter_.failed(peer_key, now);
  who.refusal = "wrong user or password";
  return who;
}

std::string JobRequestGate::publish(const WsClientChannel& channel, const std::string& user, std::string_view payload) {
  if (channel.topic != channels::kJobRequest) return "only HG_JOB_REQUEST may be published";
  hullgrind::job_request_t req;
  try {
    std::vector<std::uint8_t> bytes = job_request_bytes(schema_, payload);
    if (req.decode(bytes.data(), 0, int(bytes.size())) != int(bytes.size()))
      return "HG_JOB_REQUEST: not a job_request_t";
  } catch (const std::invalid_argument& e) {
    return e.what();
  }
  req.actor = "operator " + user;
  req.header.utime = 0;  // now
  if (!node_.publish(channels::kJobRequest, req)) return "HG_JOB_REQUEST: LCM refused it";
  runtime::logf(runtime::Level::Info, "published HG_JOB_REQUEST from the Foxglove client of %s: job '%s' action %d",
                user.c_str(), req.job_id.c_str(), int(req.action));
  return "";
}

}  // namespace hg::foxglove
