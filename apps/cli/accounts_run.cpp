// flipper accounts (commands.hpp, docs/accounts.md), in the serve front-end module
// (frontend_module.hpp): the accounts store of the config (serve.accounts, or accounts.sqlite
// beside lexicon.path).
#include <termios.h>
#include <unistd.h>

#include <iostream>
#include <nlohmann/json.hpp>
#include <string>

#include "commands.hpp"
#include "common.hpp"
#include "flipper/sdk/errors.hpp"
#include "flipper/studio/accounts.hpp"

namespace flipper::cli {
namespace {

// One line of standard input; on a terminal, prompted and not echoed.
std::string read_password() {
  const bool tty = isatty(STDIN_FILENO) != 0;
  termios saved{};
  if (tty) {
    std::cerr << "password: " << std::flush;
    tcgetattr(STDIN_FILENO, &saved);
    termios quiet = saved;
    quiet.c_lflag &= ~static_cast<tcflag_t>(ECHO);
    tcsetattr(STDIN_FILENO, TCSANOW, &quiet);
  }
  std::string line;
  std::getline(std::cin, line);
  if (tty) {
    tcsetattr(STDIN_FILENO, TCSANOW, &saved);
    std::cerr << "\n";
  }
  if (!line.empty() && line.back() == '\r') line.pop_back();
  return line;
}

}  // namespace

int accounts_action(studio::AccountStore&& store, const std::string& cmd, const AccountsArgs& args);

int accounts_main(const CommonOptions& opts, const AccountsArgs& args) {
  const kernel::Config config = load_config(opts);
  const std::string cmd = "accounts " + args.action;
  try {
    return accounts_action(studio::AccountStore(studio::accounts_path(config)), cmd, args);
  } catch (const sdk::Error& e) {
    // A name or password that cannot be used is the caller's misuse (2).
    const bool misuse = e.code() == "bad_name" || e.code() == "weak_password";
    return report_error(cmd, e.code(), e.what(), misuse ? kExitUsage : status_for(e.code()));
  }
}

int accounts_action(studio::AccountStore&& store, const std::string& cmd,
                    const AccountsArgs& args) {
  if (args.action == "add") {
    store.add(args.name, read_password(),
              studio::role_from_string(args.role.empty() ? "user" : args.role));
    std::cout << "added " << args.name << "\n";
  } else if (args.action == "passwd") {
    const int ended = store.set_password(args.name, read_password());
    std::cout << "password of " << args.name << " set; " << ended << " logins ended\n";
  } else if (args.action == "role") {
    const int ended = store.set_role(args.name, studio::role_from_string(args.role));
    std::cout << args.name << " is now " << args.role << "; " << ended << " logins ended\n";
  } else if (args.action == "list") {
    for (const auto& a : store.list()) {
      if (args.json)
        std::cout << nlohmann::json{{"name", a.name},
                                    {"role", studio::to_string(a.role)},
                                    {"password", a.has_password},
                                    {"created", a.created},
                                    {"logins", a.logins}}
                         .dump()
                  << "\n";
      else
        std::cout << a.name << "  " << studio::to_string(a.role)
                  << (a.has_password ? "" : "  (codes only)") << "  logins: " << a.logins << "\n";
    }
  } else if (args.action == "remove") {
    if (!store.remove(args.name))
      return report_error(cmd, "no_such_account", "there is no account '" + args.name + "'",
                          kExitFailed);
    std::cout << "removed " << args.name << "\n";
  } else if (args.action == "invite") {
    const std::string code = store.invite(
        args.name, studio::role_from_string(args.role.empty() ? "participant" : args.role),
        std::chrono::hours(24) * args.days);
    std::cout << code << "\n";
    if (!args.url.empty()) {
      std::string url = args.url;
      if (url.back() != '/') url += '/';
      std::cout << url << "?code=" << code << "\n";
    }
  } else if (args.action == "revoke") {
    std::cout << "revoked " << store.revoke(args.name) << " logins of " << args.name << "\n";
  }
  return kExitOk;
}

}  // namespace flipper::cli
