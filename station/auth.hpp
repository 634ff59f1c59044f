// Who may use the station: the users file (name, role, argon2id hash from libsodium's crypto_pwhash_str),
// the sessions (an HttpOnly cookie and a CSRF token per login) and the login rate limit. No sockets: the
// HTTP layer (server.cpp) and the request handling (api.cpp) call in; the tests and the fuzz target too.
#pragma once

#include <chrono>
#include <cstdint>
#include <deque>
#include <map>
#include <mutex>
#include <optional>
#include <string>
#include <vector>

namespace hg::station {

enum class Role { Viewer, Operator };
std::string role_name(Role role);
std::optional<Role> parse_role(const std::string& text);

struct User {
  std::string name;
  Role role = Role::Viewer;
  std::string hash;  // crypto_pwhash_str output ("$argon2id$v=19$...")
};

// A user name: 1..32 characters of [A-Za-z0-9_.-] (it goes into job_request_t.actor and the logs).
bool valid_user_name(const std::string& name);

// libsodium's argon2id with its "interactive" limits: slow and salted. Throws std::runtime_error when
// libsodium cannot start or runs out of memory.
std::string hash_password(const std::string& password);
bool verify_password(const std::string& hash, const std::string& password);
// A random password of `length` characters from an alphabet without look-alikes (the first user's).
std::string random_password(std::size_t length = 20);
// `bytes` random bytes as lowercase hex (session ids, CSRF tokens).
std::string random_token(std::size_t bytes = 32);

// The users file: a line per user "NAME ROLE HASH"; '#' starts a comment line. Every error names the file
// and the line.
struct UsersError : std::runtime_error {
  using std::runtime_error::runtime_error;
};
std::vector<User> read_users(const std::string& path);
std::vector<User> parse_users(const std::string& text, const std::string& where);
// Written atomically (temporary file + rename), mode 0600.
void write_users(const std::string& path, const std::vector<User>& users);

struct Session {
  std::string id;    // the cookie's value
  std::string csrf;  // X-CSRF-Token of every POST
  std::string user;
  Role role = Role::Viewer;
  std::chrono::steady_clock::time_point last_used;
};

// Sessions in memory (a restart logs everyone out). Bounded: past `capacity` the least recently used one
// goes. Thread-safe.
class Sessions {
 public:
  Sessions(std::chrono::seconds idle_timeout, std::size_t capacity = 1000)
      : idle_timeout_(idle_timeout), capacity_(capacity) {}
  Session create(const std::string& user, Role role, std::chrono::steady_clock::time_point now);
  // The session of a cookie value, refreshed; nullopt when unknown or idle too long.
  std::optional<Session> find(const std::string& id, std::chrono::steady_clock::time_point now);
  void remove(const std::string& id);
  std::size_t size() const;

 private:
  std::chrono::seconds idle_timeout_;
  std::size_t capacity_;
  mutable std::mutex mutex_;
  std::map<std::string, Session> sessions_;
};

// Failed logins per key (the user name, and the client's address): at most `failures` within `window`;
// then refused until the window has passed. Bounded in keys. Thread-safe.
class LoginLimiter {
 public:
  LoginLimiter(int failures = 5, std::chrono::seconds window = std::chrono::seconds(60))
      : failures_(failures), window_(window) {}
  // Seconds to wait before the next attempt for this key (0: may try now).
  int wait_seconds(const std::string& key, std::chrono::steady_clock::time_point now);
  void failed(const std::string& key, std::chrono::steady_clock::time_point now);
  void succeeded(const std::string& key);

 private:
  void prune(std::deque<std::chrono::steady_clock::time_point>& times, std::chrono::steady_clock::time_point now);
  int failures_;
  std::chrono::seconds window_;
  std::mutex mutex_;
  std::map<std::string, std::deque<std::chrono::steady_clock::time_point>> failed_;
};

}  // namespace hg::station
