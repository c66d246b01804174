// The account store (flipper/studio/accounts.hpp, docs/accounts.md): SQLite + libsodium.
#include "flipper/studio/accounts.hpp"

#include <fcntl.h>
#include <sodium.h>
#include <sqlite3.h>
#include <sys/stat.h>
#include <unistd.h>

#include <cctype>
#include <cerrno>
#include <cstring>
#include <filesystem>
#include <mutex>

#include "flipper/naturalization/config_keys.hpp"
#include "flipper/sdk/errors.hpp"
#include "flipper/studio/config_keys.hpp"
#include "study.hpp"

namespace flipper::studio {
namespace {

namespace fs = std::filesystem;

[[noreturn]] void fail(const char* code, const std::string& message) {
  throw sdk::Error(code, message);
}

// Creates the folders of `dir` that are missing, each private to the user (0700: the data
// folder holds credentials and the lexicon; docs/accounts.md §4). Existing folders keep their
// modes. An error names the folder that could not be made.
void create_private_folders(const fs::path& dir) {
  fs::path at;
  for (const auto& part : dir) {
    at /= part;
    if (::mkdir(at.c_str(), 0700) == 0 || errno == EEXIST) continue;
    fail("bad_accounts", "cannot create the folder '" + at.string() + "': " + std::strerror(errno));
  }
}

std::int64_t unix_now() {
  return std::chrono::duration_cast<std::chrono::seconds>(
             std::chrono::system_clock::now().time_since_epoch())
      .count();
}

std::string to_hex(const unsigned char* bytes, std::size_t n) {
  std::string out(n * 2 + 1, '\0');
  sodium_bin2hex(out.data(), out.size(), bytes, n);
  out.pop_back();
  return out;
}

// 32 random bytes as hex: a login token or a participant code.
std::string random_token(std::size_t bytes) {
  std::vector<unsigned char> b(bytes);
  randombytes_buf(b.data(), b.size());
  return to_hex(b.data(), b.size());
}

// Tokens and codes are stored as BLAKE2b hashes: a copy of the file opens no login.
std::string token_hash(std::string_view token) {
  unsigned char h[crypto_generichash_BYTES];
  crypto_generichash(h, sizeof h, reinterpret_cast<const unsigned char*>(token.data()),
                     token.size(), nullptr, 0);
  return to_hex(h, sizeof h);
}

void check_password(const std::string& password) {
  if (password.size() < kMinPasswordLength)
    fail("weak_password",
         "a password needs at least " + std::to_string(kMinPasswordLength) + " characters");
  if (password.size() > kMaxPasswordLength)
    fail("weak_password",
         "a password has at most " + std::to_string(kMaxPasswordLength) + " characters");
}

std::string hash_password(const std::string& password) {
  char out[crypto_pwhash_STRBYTES];
  if (crypto_pwhash_str(out, password.data(), password.size(), crypto_pwhash_OPSLIMIT_INTERACTIVE,
                        crypto_pwhash_MEMLIMIT_INTERACTIVE) != 0)
    fail("internal", "out of memory while hashing a password");
  return out;
}

class Stmt {
 public:
  Stmt(sqlite3* db, const char* sql) : db_(db) {
    if (sqlite3_prepare_v2(db, sql, -1, &s_, nullptr) != SQLITE_OK)
      fail("bad_accounts", std::string("accounts store: ") + sqlite3_errmsg(db));
  }
  ~Stmt() { sqlite3_finalize(s_); }
  Stmt(const Stmt&) = delete;
  Stmt& operator=(const Stmt&) = delete;
  Stmt& bind(int i, const std::string& v) {
    sqlite3_bind_text(s_, i, v.data(), static_cast<int>(v.size()), SQLITE_TRANSIENT);
    return *this;
  }
  Stmt& bind(int i, std::int64_t v) {
    sqlite3_bind_int64(s_, i, v);
    return *this;
  }
  /// true: a row.
  bool step() {
    const int rc = sqlite3_step(s_);
    if (rc == SQLITE_ROW) return true;
    if (rc == SQLITE_DONE) return false;
    const int primary = rc & 0xff;
    if (primary == SQLITE_READONLY)
      fail("read_only",
           "the accounts store is read-only: existing logins work, nothing new can be stored "
           "(no new logins, codes, accounts or passwords)");
    if (primary == SQLITE_FULL)
      fail(sdk::codes::kWriteFailed,
           "the accounts store's disk is full: nothing new can be stored");
    fail("bad_accounts", std::string("accounts store: ") + sqlite3_errmsg(db_));
  }
  std::string text(int col) const {
    const auto* p = sqlite3_column_text(s_, col);
    return p ? reinterpret_cast<const char*>(p) : std::string();
  }
  std::int64_t integer(int col) const { return sqlite3_column_int64(s_, col); }
  bool null(int col) const { return sqlite3_column_type(s_, col) == SQLITE_NULL; }

 private:
  sqlite3* db_;
  sqlite3_stmt* s_ = nullptr;
};

constexpr const char* kSchema = R"sql(
CREATE TABLE IF NOT EXISTS accounts(
  name TEXT PRIMARY KEY, password TEXT, role TEXT NOT NULL, created INTEGER NOT NULL,
  removed INTEGER NOT NULL DEFAULT 0);
CREATE TABLE IF NOT EXISTS codes(
  hash TEXT PRIMARY KEY, name TEXT NOT NULL, expires INTEGER NOT NULL);
CREATE TABLE IF NOT EXISTS logins(
  hash TEXT PRIMARY KEY, name TEXT NOT NULL, created INTEGER NOT NULL, expires INTEGER NOT NULL);
CREATE INDEX IF NOT EXISTS logins_by_name ON logins(name);
CREATE TABLE IF NOT EXISTS counters(name TEXT PRIMARY KEY, value INTEGER NOT NULL);
)sql";

}  // namespace

const char* to_string(Role role) {
  switch (role) {
    case Role::admin:
      return "admin";
    case Role::participant:
      return "participant";
    case Role::user:
      break;
  }
  return "user";
}

Role role_from_string(const std::string& text) {
  if (text == "user") return Role::user;
  if (text == "participant") return Role::participant;
  if (text == "admin") return Role::admin;
  fail(sdk::codes::kBadRequest, "role '" + text + "' is not user, participant or admin");
}

std::optional<std::string> name_problem(std::string_view name) {
  if (name.empty()) return "a name may not be empty";
  if (name.size() > kMaxNameLength)
    return "a name has at most " + std::to_string(kMaxNameLength) + " characters";
  for (char c : name) {
    const auto u = static_cast<unsigned char>(c);
    if (!std::isalnum(u) && c != '.' && c != '_' && c != '-')
      return "a name may hold only letters, digits, '.', '_' and '-'";
  }
  if (!std::isalnum(static_cast<unsigned char>(name.front())))
    return "a name starts with a letter or a digit";
  if (name.rfind("guest-", 0) == 0) return "names 'guest-...' are given to guests only";
  if (name == "anonymous") return "'anonymous' is the local default user";
  return std::nullopt;
}

std::string accounts_path(const kernel::Config& config) {
  if (!config.text(keys::kServeAccounts).empty() || config.text(keys::kServeStudy).empty())
    return accounts_path(config, std::string());
  return accounts_path(config, Study::load(config.get(keys::kServeStudy))->record_dir());
}

std::string accounts_path(const kernel::Config& config, const std::string& study_record_dir) {
  if (!config.text(keys::kServeAccounts).empty()) return config.get(keys::kServeAccounts);
  // A study owns its accounts (docs/studio.md §7 "A study's accounts"): beside its recording, so a
  // second study starts at P1 and a browser's login of one study is nobody in another.
  if (!study_record_dir.empty()) return (fs::path(study_record_dir) / "accounts.sqlite").string();
  // The raw value decides "in memory": a resolved path would make ":memory:" a file in a folder.
  const std::string given = config.text(naturalization::keys::kLexiconPath);
  if (given.empty() || given == ":memory:") return ":memory:";
  return (fs::path(config.get(naturalization::keys::kLexiconPath)).parent_path() /
          "accounts.sqlite")
      .string();
}

struct AccountStore::Impl {
  std::string path;
  sqlite3* db = nullptr;
  bool read_only = false;  ///< opened for reading only (docs/accounts.md §4 "Degraded")
  mutable std::mutex mutex;
  std::string dummy_hash;  // verified against when a name is unknown (same time either way)

  void exec(const char* sql) {
    char* err = nullptr;
    if (const int rc = sqlite3_exec(db, sql, nullptr, nullptr, &err); rc != SQLITE_OK) {
      const std::string what = err ? err : "unknown error";
      sqlite3_free(err);
      if ((rc & 0xff) == SQLITE_READONLY) fail("read_only", "accounts store is read-only: " + what);
      fail("bad_accounts", "accounts store '" + path + "': " + what);
    }
  }
  void close() {
    sqlite3_close(db);
    db = nullptr;
  }
  /// Opens `path` writable (creating the schema); false with `why` set when it cannot.
  bool open_writable(std::string& why) {
    if (sqlite3_open_v2(path.c_str(), &db,
                        SQLITE_OPEN_READWRITE | SQLITE_OPEN_CREATE | SQLITE_OPEN_FULLMUTEX,
                        nullptr) != SQLITE_OK) {
      why = db ? sqlite3_errmsg(db) : "cannot open";
      close();
      return false;
    }
    sqlite3_busy_timeout(db, 5000);
    try {
      exec("PRAGMA journal_mode=WAL");
      exec("PRAGMA synchronous=FULL");
      exec(kSchema);
    } catch (const sdk::Error& e) {
      why = e.what();
      close();
      return false;
    }
    return true;
  }
  /// Opens an existing store for reading only: through its write-ahead log when it has one
  /// (mode=ro), else as an immutable file (a read-only folder cannot hold the WAL's index).
  bool open_for_reading() {
    std::error_code ec;
    const auto wal = fs::file_size(path + "-wal", ec);
    const std::string uri = "file:" + path + (ec || wal == 0 ? "?immutable=1" : "?mode=ro");
    if (sqlite3_open_v2(uri.c_str(), &db,
                        SQLITE_OPEN_READONLY | SQLITE_OPEN_URI | SQLITE_OPEN_FULLMUTEX,
                        nullptr) != SQLITE_OK) {
      close();
      return false;
    }
    sqlite3_busy_timeout(db, 5000);
    if (sqlite3_exec(db, "SELECT count(*) FROM accounts", nullptr, nullptr, nullptr) != SQLITE_OK) {
      close();
      return false;
    }
    read_only = true;
    return true;
  }
  /// Runs `update` (binding `value`, then `name`) and ends every login of `name`, at once: a
  /// new password or role takes effect on every browser (docs/accounts.md §2). The number ended.
  int change_and_end_logins(const std::string& name, const char* update, const std::string& value) {
    exec("BEGIN IMMEDIATE");
    try {
      Stmt(db, update).bind(1, value).bind(2, name).step();
      Stmt(db, "DELETE FROM logins WHERE name = ?").bind(1, name).step();
      const int ended = sqlite3_changes(db);
      exec("COMMIT");
      return ended;
    } catch (...) {
      sqlite3_exec(db, "ROLLBACK", nullptr, nullptr, nullptr);
      throw;
    }
  }
  Login open_login(const std::string& name, Role role, std::chrono::seconds valid_for) {
    Login l{random_token(32), name, role};
    const std::int64_t now = unix_now();
    Stmt(db, "INSERT INTO logins(hash, name, created, expires) VALUES(?,?,?,?)")
        .bind(1, token_hash(l.token))
        .bind(2, name)
        .bind(3, now)
        .bind(4, now + valid_for.count())
        .step();
    return l;
  }
  bool taken(const std::string& name) const {
    Stmt s(db, "SELECT 1 FROM accounts WHERE name = ?");
    s.bind(1, name);
    return s.step();
  }
  std::optional<Account> find(const std::string& name) const {
    Stmt s(db,
           "SELECT name, password, role, created, (SELECT count(*) FROM logins l WHERE l.name = "
           "a.name AND l.expires > ?) FROM accounts a WHERE name = ? AND removed = 0");
    s.bind(1, unix_now()).bind(2, name);
    if (!s.step()) return std::nullopt;
    return Account{s.text(0), role_from_string(s.text(2)), !s.null(1), s.integer(3),
                   static_cast<int>(s.integer(4))};
  }
};

AccountStore::AccountStore(const std::string& path) : impl_(std::make_unique<Impl>()) {
  if (sodium_init() < 0) fail("internal", "libsodium could not start");
  impl_->path = path;
  if (path != ":memory:") {
    std::error_code ec;
    if (!fs::exists(path, ec)) {
      const fs::path parent = fs::path(path).parent_path();
      if (!parent.empty() && !fs::is_directory(parent, ec)) create_private_folders(parent);
      const int fd = ::open(path.c_str(), O_CREAT | O_RDWR | O_CLOEXEC, 0600);
      const int err = errno;
      if (fd < 0 && (err == EROFS || err == EACCES || err == EPERM || err == ENOSPC)) {
        // A folder that cannot be written holds no accounts: guests only, nothing stored
        // (docs/accounts.md §4 "Degraded").
        std::string why;
        impl_->path = ":memory:";
        if (!impl_->open_writable(why)) fail("bad_accounts", "accounts store in memory: " + why);
        impl_->path = path;
        impl_->read_only = true;
        impl_->dummy_hash = hash_password("not a password of anyone");
        return;
      }
      if (fd < 0)
        fail("bad_accounts",
             "cannot create the accounts store '" + path + "': " + std::strerror(err));
      ::close(fd);
    }
  }
  std::string why;
  // A store that exists but cannot be written (a read-only file, folder or file system, a full
  // disk) still serves its logins; only writes are refused (docs/accounts.md §4 "Degraded").
  if (!impl_->open_writable(why) &&
      !(path != ":memory:" && fs::exists(path) && impl_->open_for_reading()))
    fail("bad_accounts", "cannot open the accounts store '" + path + "': " + why);
  impl_->dummy_hash = hash_password("not a password of anyone");
}

AccountStore::~AccountStore() {
  sqlite3_close(impl_->db);
}

const std::string& AccountStore::path() const {
  return impl_->path;
}

bool AccountStore::read_only() const {
  return impl_->read_only;
}

void AccountStore::add(const std::string& name, const std::string& password, Role role) {
  if (auto why = name_problem(name)) fail("bad_name", "'" + name + "': " + *why);
  if (!password.empty()) check_password(password);
  const std::string hash = password.empty() ? std::string() : hash_password(password);
  std::lock_guard lock(impl_->mutex);
  if (impl_->taken(name))
    fail("account_exists", "the name '" + name +
                               "' is taken (an account has or had it; the "
                               "rules of a removed account keep its name)");
  Stmt s(impl_->db, "INSERT INTO accounts(name, password, role, created) VALUES(?,?,?,?)");
  s.bind(1, name).bind(3, std::string(to_string(role))).bind(4, unix_now());
  if (!hash.empty()) s.bind(2, hash);
  s.step();
}

int AccountStore::set_password(const std::string& name, const std::string& password) {
  check_password(password);
  const std::string hash = hash_password(password);
  std::lock_guard lock(impl_->mutex);
  if (!impl_->find(name)) fail("no_such_account", "there is no account '" + name + "'");
  return impl_->change_and_end_logins(name, "UPDATE accounts SET password = ? WHERE name = ?",
                                      hash);
}

int AccountStore::set_role(const std::string& name, Role role) {
  std::lock_guard lock(impl_->mutex);
  if (!impl_->find(name)) fail("no_such_account", "there is no account '" + name + "'");
  return impl_->change_and_end_logins(name, "UPDATE accounts SET role = ? WHERE name = ?",
                                      to_string(role));
}

bool AccountStore::remove(const std::string& name) {
  std::lock_guard lock(impl_->mutex);
  if (!impl_->find(name)) return false;
  impl_->exec("BEGIN IMMEDIATE");
  Stmt(impl_->db, "UPDATE accounts SET removed = 1, password = NULL WHERE name = ?")
      .bind(1, name)
      .step();
  Stmt(impl_->db, "DELETE FROM logins WHERE name = ?").bind(1, name).step();
  Stmt(impl_->db, "DELETE FROM codes WHERE name = ?").bind(1, name).step();
  impl_->exec("COMMIT");
  return true;
}

std::vector<Account> AccountStore::list() const {
  std::lock_guard lock(impl_->mutex);
  std::vector<Account> out;
  Stmt s(impl_->db, "SELECT name FROM accounts WHERE removed = 0 ORDER BY name");
  while (s.step())
    if (auto a = impl_->find(s.text(0))) out.push_back(*a);
  return out;
}

std::optional<Account> AccountStore::find(const std::string& name) const {
  std::lock_guard lock(impl_->mutex);
  return impl_->find(name);
}

bool AccountStore::name_taken(const std::string& name) const {
  std::lock_guard lock(impl_->mutex);
  return impl_->taken(name);
}

std::string AccountStore::invite(const std::string& name, Role role_if_new,
                                 std::chrono::seconds valid_for) {
  if (auto why = name_problem(name)) fail("bad_name", "'" + name + "': " + *why);
  std::string code = random_token(16);
  std::lock_guard lock(impl_->mutex);
  if (!impl_->find(name)) {
    if (impl_->taken(name))
      fail("account_exists", "the name '" + name + "' belonged to a removed account");
    Stmt(impl_->db, "INSERT INTO accounts(name, role, created) VALUES(?,?,?)")
        .bind(1, name)
        .bind(2, std::string(to_string(role_if_new)))
        .bind(3, unix_now())
        .step();
  }
  Stmt(impl_->db, "INSERT INTO codes(hash, name, expires) VALUES(?,?,?)")
      .bind(1, token_hash(code))
      .bind(2, name)
      .bind(3, unix_now() + valid_for.count())
      .step();
  return code;
}

std::optional<Login> AccountStore::login(const std::string& name, const std::string& password,
                                         std::chrono::seconds valid_for) {
  std::string stored;
  std::optional<Account> account;
  {
    std::lock_guard lock(impl_->mutex);
    account = impl_->find(name);
    if (account) {
      Stmt s(impl_->db, "SELECT password FROM accounts WHERE name = ?");
      s.bind(1, name);
      if (s.step() && !s.null(0)) stored = s.text(0);
    }
  }
  // The hash is checked outside the lock (tens of milliseconds); an unknown name or an account
  // without a password costs the same check, against a hash no password matches.
  const std::string& against = stored.empty() ? impl_->dummy_hash : stored;
  const bool ok = password.size() <= kMaxPasswordLength &&
                  crypto_pwhash_str_verify(against.c_str(), password.data(), password.size()) == 0;
  if (!ok || stored.empty() || !account) return std::nullopt;
  std::lock_guard lock(impl_->mutex);
  return impl_->open_login(account->name, account->role, valid_for);
}

std::optional<Login> AccountStore::redeem(const std::string& code, std::chrono::seconds valid_for) {
  std::lock_guard lock(impl_->mutex);
  const std::string hash = token_hash(code);
  Stmt s(impl_->db, "SELECT name, expires FROM codes WHERE hash = ?");
  s.bind(1, hash);
  if (!s.step()) return std::nullopt;
  const std::string name = s.text(0);
  const bool live = s.integer(1) > unix_now();
  // Used or expired, the code is gone.
  Stmt(impl_->db, "DELETE FROM codes WHERE hash = ?").bind(1, hash).step();
  const auto account = impl_->find(name);
  if (!live || !account) return std::nullopt;
  return impl_->open_login(account->name, account->role, valid_for);
}

std::optional<Login> AccountStore::resume(const std::string& token) const {
  if (token.empty() || token.size() > 128) return std::nullopt;
  std::lock_guard lock(impl_->mutex);
  Stmt s(impl_->db,
         "SELECT l.name, a.role FROM logins l JOIN accounts a ON a.name = l.name "
         "WHERE l.hash = ? AND l.expires > ? AND a.removed = 0");
  s.bind(1, token_hash(token)).bind(2, unix_now());
  if (!s.step()) return std::nullopt;
  return Login{token, s.text(0), role_from_string(s.text(1))};
}

void AccountStore::logout(const std::string& token) {
  std::lock_guard lock(impl_->mutex);
  Stmt(impl_->db, "DELETE FROM logins WHERE hash = ?").bind(1, token_hash(token)).step();
}

int AccountStore::revoke(const std::string& name) {
  std::lock_guard lock(impl_->mutex);
  Stmt(impl_->db, "DELETE FROM logins WHERE name = ?").bind(1, name).step();
  return sqlite3_changes(impl_->db);
}

std::string AccountStore::next_guest() {
  // A read-only store cannot count: a random name no counter gives (guest-r…) is never given
  // twice either.
  if (impl_->read_only) return "guest-r" + random_token(8);
  std::lock_guard lock(impl_->mutex);
  Stmt(impl_->db,
       "INSERT INTO counters(name, value) VALUES('guest', 1) "
       "ON CONFLICT(name) DO UPDATE SET value = value + 1")
      .step();
  Stmt s(impl_->db, "SELECT value FROM counters WHERE name = 'guest'");
  s.step();
  return "guest-" + std::to_string(s.integer(0));
}

}  // namespace flipper::studio
