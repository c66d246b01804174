#include "sqlite_handle.hpp"

#include <cerrno>
#include <chrono>
#include <condition_variable>
#include <mutex>
#include <random>
#include <thread>

#include "flipper/naturalization/lexicon_store.hpp"
#include "flipper/sdk/errors.hpp"
#include "group_sync.hpp"

namespace flipper::naturalization::sqlite {

namespace {

std::int64_t now_us() {
  return std::chrono::duration_cast<std::chrono::microseconds>(
             std::chrono::steady_clock::now().time_since_epoch())
      .count();
}

/// What a person should know about each fault, after "lexicon store 'PATH' ".
std::string explain(const char* code, int busy_timeout_ms) {
  const std::string c = code;
  if (c == lexicon_codes::kBusy)
    return "is busy: other writers held it longer than lexicon.busy_timeout_ms = " +
           std::to_string(busy_timeout_ms) + " ms; nothing was changed, try again";
  if (c == lexicon_codes::kFull)
    return "is full (no space left on the device, or the store's size limit); nothing was changed";
  if (c == lexicon_codes::kReadOnly)
    return "is read-only (file or directory permissions, or a read-only file system); nothing was "
           "changed";
  if (c == lexicon_codes::kCorrupt)
    return "is corrupt or not an SQLite database; the file was left as it is";
  return "failed";
}

}  // namespace

const char* code_for(int rc, int system_errno) {
  switch (rc & 0xff) {
    case SQLITE_BUSY:
    case SQLITE_LOCKED:
      return lexicon_codes::kBusy;
    case SQLITE_FULL:
      return lexicon_codes::kFull;
    case SQLITE_READONLY:
      return lexicon_codes::kReadOnly;
    case SQLITE_CORRUPT:
    case SQLITE_NOTADB:
      return lexicon_codes::kCorrupt;
    case SQLITE_CANTOPEN:
    case SQLITE_IOERR:
    case SQLITE_PERM:
      if (system_errno == ENOSPC || system_errno == EDQUOT) return lexicon_codes::kFull;
      if (system_errno == EROFS || system_errno == EACCES || system_errno == EPERM)
        return lexicon_codes::kReadOnly;
      return lexicon_codes::kBadLexicon;
    default:
      return lexicon_codes::kBadLexicon;
  }
}

/// The background checkpoints of one store (Db::checkpoint_in_background). Its thread starts at
/// the first request and owns its own connection; a failed or busy checkpoint is simply retried at
/// the next request: the frames stay in the WAL, which is as durable as the database file.
class Checkpointer {
 public:
  explicit Checkpointer(std::string path) : path_(std::move(path)) {}
  ~Checkpointer() {
    {
      std::lock_guard<std::mutex> lock(mutex_);
      stop_ = true;
    }
    wake_.notify_one();
    if (thread_.joinable()) thread_.join();
    sqlite3_close_v2(db_);
  }
  Checkpointer(const Checkpointer&) = delete;
  Checkpointer& operator=(const Checkpointer&) = delete;

  void request() {
    {
      std::lock_guard<std::mutex> lock(mutex_);
      pending_ = true;
      if (!thread_.joinable()) thread_ = std::thread([this] { run(); });
    }
    wake_.notify_one();
  }

 private:
  void run() {
    std::unique_lock<std::mutex> lock(mutex_);
    for (;;) {
      wake_.wait(lock, [this] { return stop_ || pending_; });
      if (stop_) return;
      pending_ = false;
      lock.unlock();
      checkpoint();
      lock.lock();
    }
  }

  void checkpoint() {
    if (db_ == nullptr) {
      if (sqlite3_open_v2(path_.c_str(), &db_, SQLITE_OPEN_READWRITE | SQLITE_OPEN_NOMUTEX,
                          nullptr) != SQLITE_OK) {
        sqlite3_close_v2(db_);
        db_ = nullptr;
        return;
      }
      // The WAL is synced before pages are copied, the database file after.
      sqlite3_exec(db_, "PRAGMA synchronous=FULL", nullptr, nullptr, nullptr);
    }
    sqlite3_wal_checkpoint_v2(db_, "main", SQLITE_CHECKPOINT_PASSIVE, nullptr, nullptr);
  }

  std::string path_;
  sqlite3* db_ = nullptr;  // used by the thread only
  std::mutex mutex_;
  std::condition_variable wake_;
  bool pending_ = false;
  bool stop_ = false;
  std::thread thread_;
};

Db::Db(const std::string& path, bool create, int busy_timeout_ms)
    : path_(path), busy_timeout_ms_(busy_timeout_ms), jitter_(std::random_device{}()) {
  int flags = SQLITE_OPEN_READWRITE | SQLITE_OPEN_NOMUTEX;
  if (create) flags |= SQLITE_OPEN_CREATE;
  const int rc = sqlite3_open_v2(path.c_str(), &db_, flags, nullptr);
  if (rc != SQLITE_OK) fail("cannot open", rc);
  sqlite3_extended_result_codes(db_, 1);
  // Many writers: wait for the write lock with bounded, jittered retries instead of failing.
  sqlite3_busy_handler(db_, &Db::on_busy, this);
}

namespace {
/// `path` as the path of a `file:` URI (RFC 3986 percent-encoding of what SQLite reads specially).
std::string uri_path(const std::string& path) {
  static const char* kHex = "0123456789ABCDEF";
  std::string out;
  for (const char c : path) {
    const auto u = static_cast<unsigned char>(c);
    if (c == '%' || c == '?' || c == '#' || u < 0x20 || u >= 0x7f) {
      out += '%';
      out += kHex[u >> 4];
      out += kHex[u & 15];
    } else {
      out += c;
    }
  }
  return out;
}
}  // namespace

Db::Db(const std::string& path, const ReadOnly& how, int busy_timeout_ms)
    : path_(path), busy_timeout_ms_(busy_timeout_ms), jitter_(std::random_device{}()) {
  const std::string uri = "file:" + uri_path(path) + "?" + how.uri_query;
  const int rc = sqlite3_open_v2(
      uri.c_str(), &db_, SQLITE_OPEN_READONLY | SQLITE_OPEN_URI | SQLITE_OPEN_NOMUTEX, nullptr);
  if (rc != SQLITE_OK) fail("cannot open read-only", rc);
  sqlite3_extended_result_codes(db_, 1);
  sqlite3_busy_handler(db_, &Db::on_busy, this);
}

Db::~Db() {
  checkpointer_.reset();
  for (auto& [sql, stmts] : idle_)
    for (sqlite3_stmt* stmt : stmts) sqlite3_finalize(stmt);
  sqlite3_close_v2(db_);  // the last connection to close checkpoints and removes the WAL
}

void Db::checkpoint_in_background() {
  checkpointer_ = std::make_unique<Checkpointer>(path_);
  // Replaces the auto-checkpoint hook (sqlite3_wal_autocheckpoint installs one).
  sqlite3_wal_hook(db_, &Db::on_wal_commit, this);
}

// Called by SQLite after each commit, once the commit is durable, with the WAL's frame count.
int Db::on_wal_commit(void* self, sqlite3* db, const char* name, int pages) {
  auto& d = *static_cast<Db*>(self);
  if (pages >= kMaxWalPages) {
    sqlite3_wal_checkpoint_v2(db, name, SQLITE_CHECKPOINT_PASSIVE, nullptr, nullptr);
  } else if (pages >= kCheckpointPages &&
             (pages < d.requested_at_pages_ || pages >= d.requested_at_pages_ + kRequestEvery)) {
    // Once per kRequestEvery frames (and again once the log restarted): a request per commit
    // would keep the thread checkpointing (two syncs each) while commits arrive faster than one
    // checkpoint, for a few frames each time.
    d.requested_at_pages_ = pages;
    ++d.checkpoint_requests_;
    d.checkpointer_->request();
  }
  return SQLITE_OK;
}

// Called by SQLite while a lock is held elsewhere; `attempts` is 0 on the first call of a wait.
// Sleeps 0.5..16 ms (doubling, randomised so waiting writers do not retry in lock-step) until the
// timeout; returning 0 makes the statement fail with SQLITE_BUSY (-> lexicon_busy).
int Db::on_busy(void* self, int attempts) {
  auto& db = *static_cast<Db*>(self);
  const std::int64_t now = now_us();
  if (attempts == 0) db.busy_since_us_ = now;
  if (now - db.busy_since_us_ >= std::int64_t{db.busy_timeout_ms_} * 1000) return 0;
  const std::int64_t cap_us = 500LL << std::min(attempts, 5);
  db.jitter_ = db.jitter_ * 6364136223846793005ULL + 1442695040888963407ULL;
  const std::int64_t sleep_us =
      cap_us / 2 +
      static_cast<std::int64_t>((db.jitter_ >> 33) % static_cast<std::uint64_t>(cap_us / 2 + 1));
  std::this_thread::sleep_for(std::chrono::microseconds(sleep_us));
  return 1;
}

bool Db::read_only() const {
  return sqlite3_db_readonly(db_, "main") == 1;
}

void Db::exec(const char* sql) {
  char* err = nullptr;
  const int rc = sqlite3_exec(db_, sql, nullptr, nullptr, &err);
  if (rc != SQLITE_OK) {
    const std::string msg = err ? err : sqlite3_errstr(rc);
    sqlite3_free(err);
    fail_statement(sql, rc, msg, sqlite3_extended_errcode(db_), sqlite3_system_errno(db_));
  }
}

void Db::fail_statement(const char* sql, int rc, const std::string& msg, int extended,
                        int system_errno) const {
  const char* code = code_for(rc, system_errno);
  throw sdk::Error(code, "lexicon store '" + path_ + "' " + explain(code, busy_timeout_ms_) + " (" +
                             sql + ": " + msg + ", sqlite code " + std::to_string(extended) + ")");
}

void Db::run(const char* sql) {
  Idle* home = nullptr;
  sqlite3_stmt* stmt = take(sql, home);
  int rc = SQLITE_ROW;
  while (rc == SQLITE_ROW) rc = sqlite3_step(stmt);
  if (rc == SQLITE_DONE) {
    give_back(stmt, home);
    return;
  }
  // The message and codes are read before the reset that gives the statement back.
  const std::string msg = sqlite3_errmsg(db_);
  const int extended = sqlite3_extended_errcode(db_);
  const int system_errno = sqlite3_system_errno(db_);
  give_back(stmt, home);
  fail_statement(sql, rc, msg, extended, system_errno);
}

sqlite3_stmt* Db::take(const char* sql, Idle*& home) {
  auto it = idle_.find(std::string_view(sql));
  if (it == idle_.end() && idle_.size() < kStatementTexts) it = idle_.emplace(sql, Idle()).first;
  home = it == idle_.end() ? nullptr : &it->second;
  if (home != nullptr && !home->empty()) {
    sqlite3_stmt* stmt = home->back();
    home->pop_back();
    --idle_count_;
    return stmt;
  }
  sqlite3_stmt* stmt = nullptr;
  const int rc = sqlite3_prepare_v3(db_, sql, -1, SQLITE_PREPARE_PERSISTENT, &stmt, nullptr);
  if (rc != SQLITE_OK) {
    sqlite3_finalize(stmt);
    fail("cannot prepare statement", rc);
  }
  return stmt;
}

void Db::give_back(sqlite3_stmt* stmt, Idle* home) {
  if (stmt == nullptr) return;
  sqlite3_reset(stmt);
  sqlite3_clear_bindings(stmt);
  if (home == nullptr || idle_count_ >= kIdleStatements) {
    sqlite3_finalize(stmt);
    return;
  }
  home->push_back(stmt);
  ++idle_count_;
}

void Db::fail(const std::string& what, int rc) const {
  const std::string detail = db_ ? sqlite3_errmsg(db_) : sqlite3_errstr(rc);
  const char* code = code_for(rc, db_ ? sqlite3_system_errno(db_) : 0);
  throw sdk::Error(code, "lexicon store '" + path_ + "' " + explain(code, busy_timeout_ms_) + " (" +
                             what + ": " + detail + ")");
}

Stmt::Stmt(Db& db, const char* sql) : db_(db), stmt_(db.take(sql, home_)) {}

Stmt::~Stmt() {
  db_.give_back(stmt_, home_);
}

Stmt& Stmt::bind(int i, std::string_view text) {
  const int rc =
      sqlite3_bind_text(stmt_, i, text.data(), static_cast<int>(text.size()), SQLITE_TRANSIENT);
  if (rc != SQLITE_OK) db_.fail("bind", rc);
  return *this;
}

Stmt& Stmt::bind(int i, std::int64_t value) {
  const int rc = sqlite3_bind_int64(stmt_, i, value);
  if (rc != SQLITE_OK) db_.fail("bind", rc);
  return *this;
}

Stmt& Stmt::bind_real(int i, double value) {
  const int rc = sqlite3_bind_double(stmt_, i, value);
  if (rc != SQLITE_OK) db_.fail("bind", rc);
  return *this;
}

Stmt& Stmt::bind_blob(int i, std::string_view bytes) {
  // Not copied (a snapshot is megabytes): the caller keeps `bytes` alive until the statement ran.
  const int rc = sqlite3_bind_blob64(stmt_, i, bytes.data(), bytes.size(), SQLITE_STATIC);
  if (rc != SQLITE_OK) db_.fail("bind", rc);
  return *this;
}

Stmt& Stmt::bind_null(int i) {
  const int rc = sqlite3_bind_null(stmt_, i);
  if (rc != SQLITE_OK) db_.fail("bind", rc);
  return *this;
}

bool Stmt::step() {
  const int rc = sqlite3_step(stmt_);
  if (rc == SQLITE_ROW) return true;
  if (rc == SQLITE_DONE) return false;
  db_.fail("query failed", rc);
}

void Stmt::run() {
  while (step()) {
  }
  reset();
}

void Stmt::reset() {
  sqlite3_reset(stmt_);
  sqlite3_clear_bindings(stmt_);
}

std::int64_t Stmt::int64(int col) const {
  return sqlite3_column_int64(stmt_, col);
}

double Stmt::real(int col) const {
  return sqlite3_column_double(stmt_, col);
}

std::string Stmt::text(int col) const {
  const auto* p = reinterpret_cast<const char*>(sqlite3_column_text(stmt_, col));
  return p ? std::string(p, static_cast<std::size_t>(sqlite3_column_bytes(stmt_, col)))
           : std::string();
}

std::string Stmt::blob(int col) const {
  const auto* p = static_cast<const char*>(sqlite3_column_blob(stmt_, col));
  return p ? std::string(p, static_cast<std::size_t>(sqlite3_column_bytes(stmt_, col)))
           : std::string();
}

bool Stmt::is_null(int col) const {
  return sqlite3_column_type(stmt_, col) == SQLITE_NULL;
}

Transaction::Transaction(Db& db) : db_(db) {
  if (const char* code = db_.write_refusal())
    throw sdk::Error(code, "lexicon store '" + db_.path() + "' " + explain(code, 0) +
                               " (it was so when this process opened it: it serves its rules, "
                               "and every write is refused until the store is reopened)");
  db_.run("BEGIN IMMEDIATE");
}

Transaction::~Transaction() {
  if (!done_) sqlite3_exec(db_.raw(), "ROLLBACK", nullptr, nullptr, nullptr);
}

void Transaction::commit() {
  db_.run("COMMIT");
  done_ = true;
  if (GroupSync* group = db_.group_sync()) {
    group->wait_durable([this]() -> GroupSync::Failure {
      try {
        db_.sync_wal();
        return {};
      } catch (const sdk::Error& e) {
        return {e.code(), e.what()};
      }
    });
  }
}

void Db::commit_in_groups(std::shared_ptr<GroupSync> sync) {
  group_sync_ = std::move(sync);
}

void Db::sync_wal() {
  sqlite3_file* wal = nullptr;
  int rc = sqlite3_file_control(db_, "main", SQLITE_FCNTL_JOURNAL_POINTER, &wal);
  if (rc == SQLITE_OK && (wal == nullptr || wal->pMethods == nullptr)) rc = SQLITE_IOERR_FSYNC;
  if (rc == SQLITE_OK) rc = wal->pMethods->xSync(wal, SQLITE_SYNC_NORMAL);
  if (rc != SQLITE_OK) {
    const int system_errno = errno;
    const char* code = code_for(rc, system_errno);
    throw sdk::Error(code, "lexicon store '" + path_ + "' " + explain(code, busy_timeout_ms_) +
                               " (cannot sync the write-ahead log: " + sqlite3_errstr(rc) +
                               "; the writes of this batch may not be on the disk, and this " +
                               "process refuses every later write until it restarts)");
  }
}

ReadTransaction::ReadTransaction(Db& db) : db_(db) {
  db_.run("BEGIN");
}

ReadTransaction::~ReadTransaction() {
  try {
    db_.run("COMMIT");  // ends a read: fails only if there was none to end
  } catch (...) {       // a destructor: nothing may leave it (not even a failed allocation)
  }
}

}  // namespace flipper::naturalization::sqlite
