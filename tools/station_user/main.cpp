// hg-station-user: manages hg-station's users file (station/auth.hpp: NAME ROLE ARGON2ID-HASH, mode 0600).
//   hg-station-user add NAME --role operator|viewer [--file F] [--password-stdin]   (else a password is generated)
//   hg-station-user passwd NAME [--file F] [--password-stdin]
//   hg-station-user remove NAME [--file F]
//   hg-station-user list [--file F]
#include <cstdio>
#include <filesystem>
#include <iostream>
#include <string>

#include "runtime/params.hpp"
#include "station/auth.hpp"

namespace {

using hg::station::User;

struct UsageError : std::runtime_error {
  using std::runtime_error::runtime_error;
};

std::vector<hg::runtime::Param> params() {
  return {hg::runtime::text_param("file", "out/station/users", "the users file (made if missing, mode 0600)"),
          hg::runtime::text_param("role", "", "add: operator (may act) or viewer (reads)", {"", "operator", "viewer"}),
          hg::runtime::flag_param("password-stdin",
                                  "read the password from the first line of standard input "
                                  "(else a random one is generated and printed once)")};
}

void usage(std::FILE* f, const hg::runtime::Params& p) {
  std::fprintf(f,
               "usage: hg-station-user add NAME --role operator|viewer [options]\n"
               "       hg-station-user passwd NAME | remove NAME | list [options]\n"
               "Manages hg-station's users: passwords stored as libsodium argon2id hashes (crypto_pwhash_str).\n\n");
  p.print_options(f);
}

std::string new_password(const hg::runtime::Params& p) {
  if (!p.flag("password-stdin")) {
    const std::string pw = hg::station::random_password();
    std::printf("password: %s\n", pw.c_str());
    return pw;
  }
  std::string pw;
  std::getline(std::cin, pw);
  if (pw.size() < 8) throw UsageError("the password must have at least 8 characters");
  return pw;
}

std::vector<User>::iterator find_user(std::vector<User>& users, const std::string& name) {
  return std::find_if(users.begin(), users.end(), [&](const User& u) { return u.name == name; });
}

int command(const hg::runtime::Params& p) {
  const auto& args = p.positional();
  if (args.empty()) throw UsageError("a command: add, passwd, remove or list");
  const std::string file = p.text("file"), cmd = args[0];
  std::vector<User> users;
  if (std::filesystem::exists(file)) users = hg::station::read_users(file);
  if (cmd == "list") {
    for (const User& u : users) std::printf("%s %s\n", u.name.c_str(), hg::station::role_name(u.role).c_str());
    return 0;
  }
  if (args.size() != 2) throw UsageError(cmd + ": one user NAME");
  const std::string name = args[1];
  if (!hg::station::valid_user_name(name)) throw UsageError("bad user name '" + name + "' (1-32 of A-Z a-z 0-9 _ . -)");
  auto it = find_user(users, name);
  if (cmd == "add") {
    if (it != users.end()) throw UsageError("user " + name + " exists (passwd to change the password)");
    auto role = hg::station::parse_role(p.text("role"));
    if (!role) throw UsageError("add: --role operator or --role viewer");
    users.push_back({name, *role, hg::station::hash_password(new_password(p))});
  } else if (cmd == "passwd" || cmd == "remove") {
    if (it == users.end()) throw UsageError("no user " + name + " in " + file);
    if (cmd == "remove") users.erase(it);
    else
      it->hash = hg::station::hash_password(new_password(p));
  } else {
    throw UsageError("unknown command '" + cmd + "' (add, passwd, remove, list)");
  }
  const auto parent = std::filesystem::path(file).parent_path();
  if (!parent.empty()) std::filesystem::create_directories(parent);
  hg::station::write_users(file, users);
  std::printf("%s: %s %s\n", file.c_str(), cmd.c_str(), name.c_str());
  return 0;
}

}  // namespace

int main(int argc, char** argv) {
  hg::runtime::Params p(params());
  try {
    const auto action = p.parse(argc, argv);
    if (action != hg::runtime::Params::Action::Run) return hg::runtime::answer(action, "hg-station-user", p, usage);
    return command(p);
  } catch (const UsageError& e) {
    std::fprintf(stderr, "hg-station-user: %s\n", e.what());
    return 2;
  } catch (const std::exception& e) {  // ConfigError (command line), UsersError (file and line)
    std::fprintf(stderr, "hg-station-user: %s\n", e.what());
    return e.what()[0] && dynamic_cast<const hg::runtime::ConfigError*>(&e) ? 2 : 1;
  }
}
