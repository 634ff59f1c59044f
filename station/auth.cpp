#include "station/auth.hpp"

#include <sodium.h>
#include <sys/stat.h>

#include <cerrno>
#include <cstdio>
#include <cstring>
#include <fstream>
#include <iterator>
#include <sstream>
#include <stdexcept>

namespace hg::station {

namespace {

void sodium_ready() {
  if (sodium_init() < 0) throw std::runtime_error("libsodium could not start");
}

}  // namespace

std::string role_name(Role role) { return role == Role::Operator ? "operator" : "viewer"; }

std::optional<Role> parse_role(const std::string& text) {
  if (text == "operator") return Role::Operator;
  if (text == "viewer") return Role::Viewer;
  return std::nullopt;
}

bool valid_user_name(const std::string& name) {
  if (name.empty() || name.size() > 32) return false;
  for (char c : name)
    if (!(std::isalnum(static_cast<unsigned char>(c)) || c == '_' || c == '.' || c == '-')) return false;
  return true;
}

std::string hash_password(const std::string& password) {
  sodium_ready();
  char out[crypto_pwhash_STRBYTES];
  if (crypto_pwhash_str(out, password.data(), password.size(), crypto_pwhash_OPSLIMIT_INTERACTIVE,
                        crypto_pwhash_MEMLIMIT_INTERACTIVE) != 0)
    throw std::runtime_error("crypto_pwhash_str: out of memory");
  return out;
}

bool verify_password(const std::string& hash, const std::string& password) {
  sodium_ready();
  if (hash.empty() || hash.size() >= crypto_pwhash_STRBYTES) return false;
  return crypto_pwhash_str_verify(hash.c_str(), password.data(), password.size()) == 0;
}

std::string random_password(std::size_t length) {
  sodium_ready();
  static const char alphabet[] = "abcdefghijkmnpqrstuvwxyzABCDEFGHJKLMNPQRSTUVWXYZ23456789";
  std::string out;
  for (std::size_t i = 0; i < length; ++i) out += alphabet[randombytes_uniform(sizeof(alphabet) - 1)];
  return out;
}

std::string random_token(std::size_t bytes) {
  sodium_ready();
  std::string raw(bytes, '\0');
  randombytes_buf(raw.data(), raw.size());
  std::string hex(bytes * 2 + 1, '\0');
  sodium_bin2hex(hex.data(), hex.size(), reinterpret_cast<const unsigned char*>(raw.data()), raw.size());
  hex.pop_back();
  return hex;
}

std::vector<User> parse_users(const std::string& text, const std::string& where) {
  std::vector<User> users;
  std::istringstream in(text);
  std::string line;
  for (int number = 1; std::getline(in, line); ++number) {
    const std::string at = where + " line " + std::to_string(number) + ": ";
    if (line.empty() || line[0] == '#') continue;
    std::istringstream fields(line);
    User u;
    std::string role, extra;
    if (!(fields >> u.name >> role >> u.hash) || (fields >> extra)) throw UsersError(at + "expected NAME ROLE HASH");
    if (!valid_user_name(u.name)) throw UsersError(at + "bad user name '" + u.name + "' (1-32 of A-Z a-z 0-9 _ . -)");
    auto r = parse_role(role);
    if (!r) throw UsersError(at + "role must be operator or viewer, not '" + role + "'");
    u.role = *r;
    if (u.hash.rfind("$argon2id$", 0) != 0) throw UsersError(at + "the hash is not an argon2id crypto_pwhash_str");
    for (const User& other : users)
      if (other.name == u.name) throw UsersError(at + "user '" + u.name + "' twice");
    users.push_back(std::move(u));
  }
  return users;
}

std::vector<User> read_users(const std::string& path) {
  std::ifstream in(path, std::ios::binary);
  if (!in) throw UsersError(path + ": cannot read: " + std::strerror(errno));
  std::ostringstream text;
  text << in.rdbuf();
  return parse_users(text.str(), path);
}

void write_users(const std::string& path, const std::vector<User>& users) {
  const std::string tmp = path + ".tmp";
  const mode_t old = ::umask(077);
  {
    std::ofstream out(tmp, std::ios::binary | std::ios::trunc);
    ::umask(old);
    if (!out) throw UsersError(tmp + ": cannot write: " + std::strerror(errno));
    out << "# hg-station users: NAME ROLE ARGON2ID-HASH (tools/hg-station-user)\n";
    for (const User& u : users) out << u.name << ' ' << role_name(u.role) << ' ' << u.hash << '\n';
    if (!out.flush()) throw UsersError(tmp + ": write failed");
  }
  ::chmod(tmp.c_str(), 0600);
  if (std::rename(tmp.c_str(), path.c_str()) != 0) throw UsersError(path + ": cannot replace: " + std::strerror(errno));
}

Session Sessions::create(const std::string& user, Role role, std::chrono::steady_clock::time_point now) {
  Session s{random_token(), random_token(), user, role, now};
  std::lock_guard lock(mutex_);
  while (sessions_.size() >= capacity_) {
    auto oldest = sessions_.begin();
    for (auto it = sessions_.begin(); it != sessions_.end(); ++it)
      if (it->second.last_used < oldest->second.last_used) oldest = it;
    sessions_.erase(oldest);
  }
  sessions_[s.id] = s;
  return s;
}

std::optional<Session> Sessions::find(const std::string& id, std::chrono::steady_clock::time_point now) {
  std::lock_guard lock(mutex_);
  auto it = sessions_.find(id);
  if (it == sessions_.end()) return std::nullopt;
  if (now - it->second.last_used > idle_timeout_) {
    sessions_.erase(it);
    return std::nullopt;
  }
  it->second.last_used = now;
  return it->second;
}

void Sessions::remove(const std::string& id) {
  std::lock_guard lock(mutex_);
  sessions_.erase(id);
}

std::size_t Sessions::size() const {
  std::lock_guard lock(mutex_);
  return sessions_.size();
}

void LoginLimiter::prune(std::deque<std::chrono::steady_clock::time_point>& times,
                         std::chrono::steady_clock::time_point now) {
  while (!times.empty() && now - times.front() >= window_) times.pop_front();
}

int LoginLimiter::wait_seconds(const std::string& key, std::chrono::steady_clock::time_point now) {
  std::lock_guard lock(mutex_);
  auto it = failed_.find(key);
  if (it == failed_.end()) return 0;
  prune(it->second, now);
  if (static_cast<int>(it->second.size()) < failures_) return 0;
  auto left = window_ - (now - it->second.front());
  return static_cast<int>(std::chrono::duration_cast<std::chrono::seconds>(left).count()) + 1;
}

void LoginLimiter::failed(const std::string& key, std::chrono::steady_clock::time_point now) {
  std::lock_guard lock(mutex_);
  if (failed_.size() > 10000) {  // a flood of names: forget the keys whose window has passed
    for (auto it = failed_.begin(); it != failed_.end();) {
      prune(it->second, now);
      it = it->second.empty() ? failed_.erase(it) : std::next(it);
    }
    if (failed_.size() > 10000) failed_.erase(failed_.begin());
  }
  auto& times = failed_[key];
  prune(times, now);
  times.push_back(now);
}

void LoginLimiter::succeeded(const std::string& key) {
  std::lock_guard lock(mutex_);
  failed_.erase(key);
}

}  // namespace hg::station
