#pragma once
// Minimal RAII over the SQLite3 C API: a connection, prepared statements, and transaction guards.
// Every failure throws sdk::Error with a lexicon code chosen from SQLite's result code
// (lexicon_busy, lexicon_full, lexicon_read_only, lexicon_corrupt, else bad_lexicon), naming the
// store file.
#include <sqlite3.h>

#include <cstdint>
#include <functional>
#include <memory>
#include <optional>
#include <string>
#include <string_view>
#include <unordered_map>
#include <vector>

namespace flipper::naturalization::sqlite {

/// The lexicon error code for an SQLite result code (and the OS errno behind it).
const char* code_for(int rc, int system_errno);

class Checkpointer;
class GroupSync;

class Db {
 public:
  /// Opens `path`; `create` allows creating a missing file. Waits for other writers up to
  /// `busy_timeout_ms` (jittered backoff), then reports lexicon_busy.
  Db(const std::string& path, bool create, int busy_timeout_ms);
  /// How a read-only connection opens (the query of its `file:` URI).
  struct ReadOnly {
    std::string
        uri_query;  ///< `mode=ro`, or `immutable=1` when not even the WAL's index can be made
  };
  /// Opens `path` for reading only, through the URI `file:PATH?<query>`. `path` names the store in
  /// messages.
  Db(const std::string& path, const ReadOnly& how, int busy_timeout_ms);
  ~Db();
  Db(const Db&) = delete;
  Db& operator=(const Db&) = delete;

  sqlite3* raw() const { return db_; }
  const std::string& path() const { return path_; }
  int busy_timeout_ms() const { return busy_timeout_ms_; }
  void set_busy_timeout_ms(int ms) { busy_timeout_ms_ = ms; }
  /// The file could only be opened for reading (permissions, read-only file system).
  bool read_only() const;
  /// The store serves reads only, degraded at open (docs/naturalization.md §5 "Store faults"):
  /// every write transaction is refused with `code` (lexicon_read_only or lexicon_full).
  void refuse_writes(const char* code) { write_refusal_ = code; }
  /// The code writes are refused with, or null.
  const char* write_refusal() const { return write_refusal_; }
  /// Runs one or more statements without results.
  void exec(const char* sql);
  /// Runs one statement without results through the statement cache (below): BEGIN, COMMIT.
  void run(const char* sql);
  /// Throws the lexicon error for `rc` with `what` and SQLite's message.
  [[noreturn]] void fail(const std::string& what, int rc) const;
  /// WAL checkpoints off the committing path (docs/naturalization.md §5): no auto-checkpoint in
  /// COMMIT; once the WAL holds kCheckpointPages frames, a thread with its own connection
  /// checkpoints (PASSIVE: it never blocks a writer or reader). Only a WAL past kMaxWalPages (the
  /// thread cannot keep up) is checkpointed by the commit that grows it. A COMMIT still returns
  /// only after its frames are synced to the WAL (synchronous=FULL).
  void checkpoint_in_background();

  /// Group commit (docs/naturalization.md §5, group_sync.hpp): the caller has set
  /// synchronous=NORMAL; every write transaction's COMMIT then waits on `sync` for one shared
  /// fdatasync of the WAL before it returns.
  void commit_in_groups(std::shared_ptr<GroupSync> sync);
  GroupSync* group_sync() const { return group_sync_.get(); }
  /// Syncs this connection's WAL file (one fdatasync); throws the lexicon error on failure.
  void sync_wal();

  static constexpr int kCheckpointPages = 1000;  // SQLite's own auto-checkpoint size
  static constexpr int kMaxWalPages = 16000;     // ~64 MiB with 4 KiB pages
  /// Past kCheckpointPages, a checkpoint is requested again only after this many more frames.
  static constexpr int kRequestEvery = kCheckpointPages / 4;
  /// Checkpoints requested of the thread so far (for the tests).
  std::uint64_t checkpoint_requests() const { return checkpoint_requests_; }

  /// The statement cache (docs/naturalization.md §5 "Durability and latency"): compiling a
  /// statement costs more than running most of the lexicon's, so a connection keeps its idle
  /// prepared statements by SQL text, up to kIdleStatements of them for up to kStatementTexts
  /// texts. `take` hands out an idle statement for `sql` (or prepares one; Error as Stmt's) and
  /// sets `home` to where it goes back (null: a text past the cap, finalized when given back);
  /// `give_back` resets it (no lock or snapshot survives it, no binding points at the caller's
  /// memory) and keeps it. A statement in use is out of the cache: Stmts of one text may nest.
  using Idle = std::vector<sqlite3_stmt*>;
  sqlite3_stmt* take(const char* sql, Idle*& home);
  void give_back(sqlite3_stmt* stmt, Idle* home);
  static constexpr std::size_t kIdleStatements = 64;
  static constexpr std::size_t kStatementTexts = 256;
  /// The texts the cache has a place for (at most kStatementTexts).
  std::size_t statement_texts() const { return idle_.size(); }

 private:
  struct TextHash {
    using is_transparent = void;
    std::size_t operator()(std::string_view s) const { return std::hash<std::string_view>{}(s); }
  };
  /// Throws the lexicon error of statement `sql` that failed with `rc`: exec's and run's message.
  [[noreturn]] void fail_statement(const char* sql, int rc, const std::string& msg, int extended,
                                   int system_errno) const;
  static int on_busy(void* self, int attempts);
  static int on_wal_commit(void* self, sqlite3* db, const char* name, int pages);

  sqlite3* db_ = nullptr;
  std::string path_;
  int busy_timeout_ms_ = 0;
  std::int64_t busy_since_us_ = 0;
  std::uint64_t jitter_ = 0;
  std::unique_ptr<Checkpointer> checkpointer_;  // stopped before the connection closes
  int requested_at_pages_ = 0;                  // the WAL's frames at the last checkpoint request
  std::uint64_t checkpoint_requests_ = 0;
  const char* write_refusal_ = nullptr;
  std::shared_ptr<GroupSync> group_sync_;
  std::unordered_map<std::string, Idle, TextHash, std::equal_to<>> idle_;  // nodes never erased
  std::size_t idle_count_ = 0;
};

/// A prepared statement, taken from the connection's statement cache (Db::take) and given back
/// reset when destroyed.
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
  Db::Idle* home_ = nullptr;  // declared before stmt_: the constructor's Db::take sets it
  sqlite3_stmt* stmt_ = nullptr;
};

/// BEGIN IMMEDIATE ... COMMIT: the write lock is taken at BEGIN (waiting through the busy
/// handler), so a transaction never fails half-way for a lock; rolls back when destroyed
/// uncommitted (an exception). Under group commit, commit() returns once a shared sync of the WAL
/// covers the COMMIT.
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

}  // namespace flipper::naturalization::sqlite
