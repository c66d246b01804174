#pragma once
// Minimal RAII over the SQLite3 C API: a connection, prepared statements, and transaction guards.
// Every failure throws sdk::Error with a lexicon code chosen from SQLite's result code
// (lexicon_busy, lexicon_full, lexicon_read_only, lexicon_corrupt, else bad_lexicon), naming the
// store file.
#include <sqlite3.h>

#include <cstdint>
#include <optional>
#include <string>
#include <string_view>

namespace flipper::kernel::sqlite {

/// The lexicon error code for an SQLite result code (and the OS errno behind it).
const char* code_for(int rc, int system_errno);

class Db {
 public:
  /// Opens `path`; `create` allows creating a missing file. Waits for other writers up to
  /// `busy_timeout_ms` (jittered backoff), then reports lexicon_busy.
  Db(const std::string& path, bool create, int busy_timeout_ms);
  ~Db();
  Db(const Db&) = delete;
  Db& operator=(const Db&) = delete;

  sqlite3* raw() const { return db_; }
  const std::string& path() const { return path_; }
  int busy_timeout_ms() const { return busy_timeout_ms_; }
  void set_busy_timeout_ms(int ms) { busy_timeout_ms_ = ms; }
  /// The file could only be opened for reading (permissions, read-only file system).
  bool read_only() const;
  /// Runs one or more statements without results.
  void exec(const char* sql);
  /// Throws the lexicon error for `rc` with `what` and SQLite's message.
  [[noreturn]] void fail(const std::string& what, int rc) const;

 private:
  static int on_busy(void* self, int attempts);

  sqlite3* db_ = nullptr;
  std::string path_;
  int busy_timeout_ms_ = 0;
  std::int64_t busy_since_us_ = 0;
  std::uint64_t jitter_ = 0;
};

class Stmt {
 public:
  Stmt(Db& db, const char* sql);
  ~Stmt();
  Stmt(const Stmt&) = delete;
  Stmt& operator=(const Stmt&) = delete;

  Stmt& bind(int i, std::string_view text);
  Stmt& bind(int i, std::int64_t value);
  Stmt& bind_real(int i, double value);
  Stmt& bind_null(int i);
  /// Binds without copying: `bytes` must stay alive until the statement has run.
  Stmt& bind_blob(int i, std::string_view bytes);
  /// Steps once: true when a row is available, false when done.
  bool step();
  /// Steps to completion (statements without rows).
  void run();
  void reset();

  std::int64_t int64(int col) const;
  double real(int col) const;
  std::string text(int col) const;
  std::string blob(int col) const;
  bool is_null(int col) const;

 private:
  Db& db_;
  sqlite3_stmt* stmt_ = nullptr;
};

/// BEGIN IMMEDIATE ... COMMIT: the write lock is taken at BEGIN (waiting through the busy
/// handler), so a transaction never fails half-way for a lock; rolls back when destroyed
/// uncommitted (an exception).
class Transaction {
 public:
  explicit Transaction(Db& db);
  ~Transaction();
  void commit();

 private:
  Db& db_;
  bool done_ = false;
};

/// BEGIN (deferred) ... COMMIT around several reads: one consistent snapshot.
class ReadTransaction {
 public:
  explicit ReadTransaction(Db& db);
  ~ReadTransaction();

 private:
  Db& db_;
};

}  // namespace flipper::kernel::sqlite
