#pragma once
/// @file accounts.hpp
/// The studio's accounts (docs/accounts.md): who may act as a name in `flipper serve`. An account
/// is a name with a role and, optionally, a password (Argon2id through libsodium's
/// crypto_pwhash_str); one-time codes log a participant in without one; a login is a random
/// token that the browser keeps in an HttpOnly cookie and that the server can revoke. Guests get
/// names `guest-N` whose N is never given twice, so no one inherits a guest's rules. Everything
/// is kept in one SQLite file (serve.accounts), apart from the lexicon: the lexicon is community
/// data that is exported, imported and replicated between sites; credentials must never travel
/// with it. Tokens and codes are stored only as hashes. Thread-safe.

#include <chrono>
#include <cstdint>
#include <memory>
#include <optional>
#include <string>
#include <string_view>
#include <vector>

#include "flipper/kernel/config.hpp"

namespace flipper::studio {

enum class Role { user, participant, admin };
const char* to_string(Role role);
/// "user", "participant" or "admin"; throws sdk::Error(bad_request) otherwise.
Role role_from_string(const std::string& text);

struct Account {
  std::string name;
  Role role = Role::user;
  bool has_password = false;
  std::int64_t created = 0;  ///< Unix seconds
  int logins = 0;            ///< live (unexpired, unrevoked) logins
};

/// A login: the token (only ever shown once, to the client that logged in) and whose it is.
struct Login {
  std::string token;
  std::string name;
  Role role = Role::user;
};

/// Why `name` cannot be an account's name, or nullopt when it can: 1 to 32 characters of
/// letters, digits, '.', '_' and '-', starting with a letter or digit, not "guest-..." (guests'
/// names) and not "anonymous" (the local default user).
std::optional<std::string> name_problem(std::string_view name);
inline constexpr std::size_t kMaxNameLength = 32;
inline constexpr std::size_t kMinPasswordLength = 8;
inline constexpr std::size_t kMaxPasswordLength = 1024;

/// The accounts file of a config: serve.accounts; else, with serve.study, accounts.sqlite in the
/// study's recording folder (the study file is read: bad_config when it is bad); else
/// accounts.sqlite beside lexicon.path (":memory:" when the lexicon is in memory).
std::string accounts_path(const kernel::Config& config);
/// The same for a study already loaded: `study_record_dir` is its recording folder (empty: no
/// study), so the study file is read once (the server, docs/studio.md §7 "A study's accounts").
std::string accounts_path(const kernel::Config& config, const std::string& study_record_dir);

class AccountStore {
 public:
  /// Opens (creating, mode 0600, its missing folders 0700) the store. A store that exists but
  /// cannot be written is opened for reading: logins resume, every write throws read_only.
  /// Throws sdk::Error(bad_accounts) naming the file.
  explicit AccountStore(const std::string& path);
  ~AccountStore();
  AccountStore(const AccountStore&) = delete;
  AccountStore& operator=(const AccountStore&) = delete;

  const std::string& path() const;
  /// Opened for reading only (a read-only file, folder or file system, or a full disk).
  bool read_only() const;

  /// Adds an account. An empty password: the account logs in with codes only. Throws
  /// sdk::Error: bad_name, weak_password, account_exists.
  void add(const std::string& name, const std::string& password, Role role);
  /// Sets the password and ends every login of the account (its open sessions need a new
  /// login). The number of logins ended. Throws no_such_account, weak_password.
  int set_password(const std::string& name, const std::string& password);
  /// Sets the role and ends every login of the account, as set_password.
  int set_role(const std::string& name, Role role);
  /// Removes the account, its codes and logins (its rules stay, under its name, which stays
  /// taken: see add). Returns false when there is no such account.
  bool remove(const std::string& name);
  std::vector<Account> list() const;
  std::optional<Account> find(const std::string& name) const;
  /// Whether `name` was ever an account (removed accounts keep their name reserved).
  bool name_taken(const std::string& name) const;

  /// A one-time code that logs in as `name` (a participant account without a password is
  /// created when there is none). Throws bad_name.
  std::string invite(const std::string& name, Role role_if_new, std::chrono::seconds valid_for);

  /// Checks a password (Argon2id; an unknown name costs the same time) and opens a login.
  std::optional<Login> login(const std::string& name, const std::string& password,
                             std::chrono::seconds valid_for);
  /// Redeems a code (once) and opens a login for its account.
  std::optional<Login> redeem(const std::string& code, std::chrono::seconds valid_for);
  /// The live login a token names.
  std::optional<Login> resume(const std::string& token) const;
  void logout(const std::string& token);
  /// Revokes every login of `name`; the number revoked.
  int revoke(const std::string& name);

  /// "guest-N" with an N this store never gave before (kept across restarts); on a read-only
  /// store "guest-r" and 16 random hex digits.
  std::string next_guest();

 private:
  struct Impl;
  std::unique_ptr<Impl> impl_;
};

}  // namespace flipper::studio
