#include "flipper/naturalization/lexicon_store.hpp"

#include <algorithm>
#include <chrono>
#include <ctime>
#include <filesystem>
#include <istream>
#include <nlohmann/json.hpp>
#include <ostream>
#include <thread>

#include "degraded_open.hpp"
#include "flipper/sdk/errors.hpp"
#include "group_sync.hpp"
#include "history_store.hpp"
#include "sqlite_handle.hpp"
#include "store_impl.hpp"

namespace flipper::naturalization {
namespace fs = std::filesystem;
using nlohmann::json;

namespace {

// Version 3, then kUpgradeFrom3 (kSchemaVersion 4). `created` is assigned inside the defining
// transaction (max + 1); `deleted_seq` orders deletions so other processes can pick them up
// incrementally; `scorer_weights` holds an incremental scorer's weights as sums of every
// process's changes (added in place, so concurrent learners never overwrite each other).
constexpr const char* kSchema = R"sql(
CREATE TABLE flipper_schema(version INTEGER NOT NULL);
CREATE TABLE definitions(
  id INTEGER PRIMARY KEY, head TEXT NOT NULL, body TEXT NOT NULL, author TEXT NOT NULL,
  time INTEGER NOT NULL);
CREATE TABLE rules(
  id TEXT PRIMARY KEY, created INTEGER NOT NULL UNIQUE, definition INTEGER NOT NULL,
  lhs TEXT NOT NULL, rhs TEXT NOT NULL, template TEXT NOT NULL, author TEXT NOT NULL,
  head TEXT NOT NULL, body TEXT NOT NULL, how TEXT NOT NULL,
  deleted INTEGER NOT NULL DEFAULT 0, deleted_at INTEGER, deleted_seq INTEGER);
CREATE INDEX rules_deleted_seq ON rules(deleted_seq);
CREATE TABLE rule_uses(
  rule TEXT PRIMARY KEY, by_author INTEGER NOT NULL, by_others INTEGER NOT NULL);
CREATE TABLE scorer_state(key TEXT PRIMARY KEY, state TEXT NOT NULL);
CREATE TABLE scorer_weights(
  key TEXT NOT NULL, model TEXT NOT NULL, feature TEXT NOT NULL, weight REAL NOT NULL,
  aux REAL NOT NULL, PRIMARY KEY(key, model, feature)) WITHOUT ROWID;
INSERT INTO flipper_schema(version) VALUES (3);
)sql";

// Version 2 -> 3: the additive weight table.
constexpr const char* kUpgradeFrom2 = R"sql(
CREATE TABLE scorer_weights(
  key TEXT NOT NULL, model TEXT NOT NULL, feature TEXT NOT NULL, weight REAL NOT NULL,
  aux REAL NOT NULL, PRIMARY KEY(key, model, feature)) WITHOUT ROWID;
UPDATE flipper_schema SET version = 3;
)sql";

// Version 3 -> 4: `seq` orders what accepts teach (counters, weights, whole scorer states), so
// other processes and kernels pick it up incrementally (learned_since, docs/naturalization.md §5).
constexpr const char* kUpgradeFrom3 = R"sql(
ALTER TABLE rule_uses ADD COLUMN seq INTEGER NOT NULL DEFAULT 0;
ALTER TABLE scorer_weights ADD COLUMN seq INTEGER NOT NULL DEFAULT 0;
ALTER TABLE scorer_state ADD COLUMN seq INTEGER NOT NULL DEFAULT 0;
CREATE INDEX rule_uses_seq ON rule_uses(seq);
CREATE INDEX scorer_weights_seq ON scorer_weights(seq);
CREATE INDEX scorer_state_seq ON scorer_state(seq);
UPDATE flipper_schema SET version = 4;
)sql";

// Version 4 -> 5: the append-only history of every change to the live rules, and tags naming
// points of it (docs/naturalization.md §5 "History and governance"). Rules stored before get a
// synthesized `import` entry each (creation order), then a `delete` entry per deletion (deletion
// order), with the times of their rows.
constexpr const char* kUpgradeFrom4 = R"sql(
CREATE TABLE lexicon_history(
  seq INTEGER PRIMARY KEY, time INTEGER NOT NULL, author TEXT NOT NULL, action TEXT NOT NULL,
  effect TEXT NOT NULL, rule TEXT, source_rule TEXT, definition INTEGER,
  head TEXT NOT NULL DEFAULT '', body TEXT NOT NULL DEFAULT '[]', study TEXT NOT NULL DEFAULT '',
  site TEXT NOT NULL DEFAULT '', note TEXT NOT NULL DEFAULT '');
CREATE INDEX lexicon_history_rule ON lexicon_history(rule);
CREATE INDEX lexicon_history_source ON lexicon_history(source_rule);
CREATE TABLE lexicon_tags(
  name TEXT PRIMARY KEY, seq INTEGER NOT NULL, time INTEGER NOT NULL, author TEXT NOT NULL,
  checksum TEXT NOT NULL);
CREATE TRIGGER lexicon_history_append_only_u BEFORE UPDATE ON lexicon_history
  BEGIN SELECT RAISE(ABORT, 'the lexicon history is append-only'); END;
CREATE TRIGGER lexicon_history_append_only_d BEFORE DELETE ON lexicon_history
  BEGIN SELECT RAISE(ABORT, 'the lexicon history is append-only'); END;
CREATE TRIGGER lexicon_tags_fixed_u BEFORE UPDATE ON lexicon_tags
  BEGIN SELECT RAISE(ABORT, 'a lexicon tag is never moved'); END;
CREATE TRIGGER lexicon_tags_fixed_d BEFORE DELETE ON lexicon_tags
  BEGIN SELECT RAISE(ABORT, 'a lexicon tag is never moved'); END;
INSERT INTO lexicon_history(time, author, action, effect, rule, definition, head, body, note)
  SELECT coalesce(d.time, 0), r.author, 'import', 'add', r.id, r.definition, r.head, r.body,
         'synthesized at the upgrade to schema 5'
  FROM rules r LEFT JOIN definitions d ON d.id = r.definition ORDER BY r.created;
INSERT INTO lexicon_history(time, author, action, effect, rule, definition, head, body, note)
  SELECT coalesce(r.deleted_at, 0), r.author, 'delete', 'remove', r.id, r.definition, r.head,
         r.body, 'synthesized at the upgrade to schema 5'
  FROM rules r WHERE r.deleted = 1 ORDER BY r.deleted_seq;
UPDATE flipper_schema SET version = 5;
)sql";

// Version 1 -> 2, in place: existing deletions get a sequence in `created` order.
constexpr const char* kUpgradeFrom1 = R"sql(
ALTER TABLE rules ADD COLUMN deleted_seq INTEGER;
UPDATE rules SET deleted_seq = created WHERE deleted = 1;
CREATE INDEX rules_deleted_seq ON rules(deleted_seq);
UPDATE flipper_schema SET version = 2;
)sql";

std::string to_json_list(const std::vector<std::string>& v) {
  return json(v).dump();
}

/// A stored list column back to its strings; nullopt when it is not a JSON list of strings.
std::optional<std::vector<std::string>> from_json_list(const std::string& text) {
  // The common case without a JSON tree: ["a","$B",...] with no escapes (start-up reads two
  // lists per rule).
  if (text.size() >= 2 && text.front() == '[' && text.back() == ']' &&
      text.find('\\') == std::string::npos) {
    std::vector<std::string> out;
    std::size_t i = 1;
    bool ok = true;
    while (ok && i < text.size() - 1) {
      if (text[i] != '"') {
        ok = false;
        break;
      }
      const std::size_t end = text.find('"', i + 1);
      if (end == std::string::npos || end >= text.size() - 1) {
        ok = false;
        break;
      }
      out.emplace_back(text, i + 1, end - i - 1);
      i = end + 1;
      if (text[i] == ',') {
        ++i;
        ok = i < text.size() - 1;  // no trailing comma
      } else if (i != text.size() - 1) {
        ok = false;
      }
    }
    if (ok) return out;
  }
  const json j = json::parse(text, nullptr, false);
  if (!j.is_array()) return std::nullopt;
  std::vector<std::string> out;
  for (const auto& e : j) {
    if (!e.is_string()) return std::nullopt;
    out.push_back(e.get<std::string>());
  }
  return out;
}

/// Reads list column `column` of a row into `into`; a value that does not decode leaves `into`
/// empty and says why in `error` (the first such column of the row), so the row is quarantined
/// instead of stopping the store.
void decode_list(const std::string& text, const char* column, std::vector<std::string>& into,
                 std::string& error) {
  if (auto list = from_json_list(text)) {
    into = std::move(*list);
    return;
  }
  into.clear();
  if (!error.empty()) return;
  constexpr std::size_t kShown = 80;
  error = std::string("the row does not decode: column '") + column + "' holds '" +
          text.substr(0, kShown) + (text.size() > kShown ? "...'" : "'") +
          ", not a JSON list of strings";
}

}  // namespace

bool lexicon_codes::is_store_fault(const std::string& code) {
  return code == kBadLexicon || code == kBusy || code == kFull || code == kReadOnly ||
         code == kCorrupt;
}

namespace {

void verify_pages(sqlite::Db& db) {
  sqlite::Stmt check(db, "PRAGMA quick_check");
  if (check.step() && check.text(0) != "ok")
    throw sdk::Error(lexicon_codes::kCorrupt, "lexicon store '" + db.path() +
                                                  "' is corrupt; the file was left as it is (" +
                                                  check.text(0) + ")");
}

/// Refuses anything that is not an empty database or a Flipper lexicon, before any write.
/// Returns the schema version (0: an empty database).
std::int64_t check_existing(sqlite::Db& db, bool quick_check) {
  sqlite::Stmt tables(db, "SELECT name FROM sqlite_master WHERE type='table'");
  bool any = false, ours = false;
  while (tables.step()) {
    any = true;
    if (tables.text(0) == "flipper_schema") ours = true;
  }
  if (any && !ours)
    throw sdk::Error(lexicon_codes::kBadLexicon,
                     "lexicon store '" + db.path() + "': not a Flipper lexicon (foreign tables)");
  std::int64_t version = 0;
  if (ours) {
    sqlite::Stmt v(db, "SELECT max(version) FROM flipper_schema");
    if (v.step()) version = v.int64(0);
    if (version > LexiconStore::kSchemaVersion)
      throw sdk::Error(lexicon_codes::kBadLexicon,
                       "lexicon store '" + db.path() + "': schema version " +
                           std::to_string(version) + " is newer than this build's " +
                           std::to_string(LexiconStore::kSchemaVersion));
  }
  if (quick_check) verify_pages(db);
  return version;
}

/// Creates the schema or upgrades it, in one write transaction (re-checked under the lock:
/// another process may have done it first).
void create_or_upgrade(sqlite::Db& db) {
  sqlite::Transaction tx(db);
  std::int64_t version = 0;
  {
    sqlite::Stmt t(db, "SELECT count(*) FROM sqlite_master WHERE name='flipper_schema'");
    t.step();
    if (t.int64(0) > 0) {
      sqlite::Stmt v(db, "SELECT coalesce(max(version), 0) FROM flipper_schema");
      v.step();
      version = v.int64(0);
    }
  }
  if (version == 0) db.exec(kSchema);
  if (version == 1) db.exec(kUpgradeFrom1);
  if (version == 1 || version == 2) db.exec(kUpgradeFrom2);
  if (version <= 3) db.exec(kUpgradeFrom3);
  if (version <= 4) db.exec(kUpgradeFrom4);
  tx.commit();
}

}  // namespace

namespace {

std::string journal_mode(sqlite::Db& db) {
  sqlite::Stmt m(db, "PRAGMA journal_mode");
  return m.step() ? m.text(0) : std::string();
}  // finalized: an active statement would hold a read transaction open

/// Switches a store to WAL. Two processes creating one store race here: switching needs the
/// database to itself, and SQLite answers a loser SQLITE_BUSY at once, without its busy handler.
/// The loser looks again (the winner has usually switched it) and retries within the busy timeout.
void use_wal(sqlite::Db& db) {
  const auto deadline =
      std::chrono::steady_clock::now() + std::chrono::milliseconds(db.busy_timeout_ms());
  for (int attempt = 0;; ++attempt) {
    if (journal_mode(db) == "wal") return;
    try {
      db.exec("PRAGMA journal_mode=WAL");
      return;
    } catch (const sdk::Error& e) {
      if (std::string(e.code()) != lexicon_codes::kBusy ||
          std::chrono::steady_clock::now() >= deadline)
        throw;
    }
    std::this_thread::sleep_for(std::chrono::microseconds(500 << std::min(attempt, 5)));
  }
}

}  // namespace

namespace {

/// A store opened for reading only must need no change: it holds a lexicon of this build's
/// schema (version 2 only lacks the weight table, which weight_changes() treats as empty;
/// versions 2 and 3 lack the learning sequence, so learned_since() sees nothing new; versions
/// before 5 have no history, which history() reports).
void check_readable_version(sqlite::Db& db, std::int64_t version) {
  if (version != LexiconStore::kSchemaVersion && version != 2 && version != 3 && version != 4)
    throw sdk::Error(lexicon_codes::kReadOnly,
                     "lexicon store '" + db.path() + "' is read-only and " +
                         (version == 0 ? std::string("holds no lexicon yet")
                                       : "needs an upgrade to schema version " +
                                             std::to_string(LexiconStore::kSchemaVersion)));
}

/// Opens (or creates) the store for reading and writing, in WAL mode with the current schema.
void open_writable(std::unique_ptr<sqlite::Db>& into, const std::string& path, bool existed,
                   const LexiconStoreOptions& options) {
  const bool memory = path == ":memory:";
  into = std::make_unique<sqlite::Db>(path, !existed, options.busy_timeout_ms);
  auto& db = *into;
  if (options.max_page_count > 0)
    db.exec(("PRAGMA max_page_count = " + std::to_string(options.max_page_count)).c_str());
  const std::int64_t version = existed ? check_existing(db, options.check_on_open) : 0;
  if (db.read_only()) {
    // SQLite could only open the file for reading: serve it as it is if it needs no change.
    check_readable_version(db, version);
    db.refuse_writes(lexicon_codes::kReadOnly);
  } else {
    // WAL + FULL: every COMMIT is on disk when it returns, and a kill mid-write never corrupts.
    // WAL + NORMAL (lexicon.durability: normal): a COMMIT is in the WAL file (the OS's page cache)
    // when it returns, so it survives a crash of the process; the WAL is synced at checkpoints.
    // WAL + NORMAL + a shared sync (lexicon.group_commit, group_sync.hpp): a write returns once
    // an fdatasync of the WAL that started after its COMMIT returned — `full`'s promise, with
    // one sync for the commits of every connection of this process that waited meanwhile.
    if (!memory) use_wal(db);
    const bool group = options.sync_every_commit && options.group_commit && !memory;
    db.exec(options.sync_every_commit && !group ? "PRAGMA synchronous=FULL"
                                                : "PRAGMA synchronous=NORMAL");
    if (group) db.commit_in_groups(sqlite::group_sync_for(path));
    if (!memory) db.checkpoint_in_background();
    if (version < LexiconStore::kSchemaVersion) create_or_upgrade(db);
  }
}

}  // namespace

GroupCommitStats group_commit_stats(const std::string& path) {
  const std::shared_ptr<sqlite::GroupSync> sync = sqlite::find_group_sync(path);
  if (!sync) return {};
  return {sync->writes(), sync->syncs()};
}

LexiconStore::LexiconStore(const std::string& path, const LexiconStoreOptions& options)
    : impl_(std::make_unique<Impl>()) {
  impl_->path = path;
  impl_->site = options.site;
  const bool memory = path == ":memory:";
  bool existed = false;
  if (!memory) {
    std::error_code ec;
    existed = fs::exists(path, ec);
    if (existed && !fs::is_regular_file(path, ec))
      throw sdk::Error(lexicon_codes::kBadLexicon,
                       "lexicon store '" + path + "': not a regular file");
    const fs::path parent = fs::path(path).parent_path();
    if (!existed && !parent.empty()) {
      fs::create_directories(parent, ec);
      if (ec)
        throw sdk::Error(
            ec == std::errc::read_only_file_system || ec == std::errc::permission_denied
                ? lexicon_codes::kReadOnly
                : lexicon_codes::kBadLexicon,
            "lexicon store '" + path + "': cannot create directory '" + parent.string() +
                "': " + ec.message());
    }
  }
  try {
    open_writable(impl_->db, path, existed, options);
    impl_->data_version = std::make_unique<sqlite::Stmt>(*impl_->db, "PRAGMA data_version");
  } catch (const sdk::Error& e) {
    // A store that exists but cannot be written (read-only file, folder or file system, or a
    // full device) still serves its rules; only writes fail (docs/naturalization.md §5).
    const char* refusal = existed ? degraded_reason(path, e) : nullptr;
    if (refusal == nullptr) throw;
    impl_->data_version.reset();
    impl_->db.reset();
    impl_->db = open_for_reading(path, options.busy_timeout_ms, e);
    check_readable_version(*impl_->db, check_existing(*impl_->db, options.check_on_open));
    impl_->db->refuse_writes(refusal);
    impl_->data_version = std::make_unique<sqlite::Stmt>(*impl_->db, "PRAGMA data_version");
  }
}

LexiconStore::~LexiconStore() = default;

const std::string& LexiconStore::path() const {
  return impl_->path;
}

bool LexiconStore::read_only() const {
  return impl_->db->read_only();
}

const char* LexiconStore::write_refusal() const {
  return impl_->db->write_refusal();
}

namespace {

std::int64_t next_value(sqlite::Db& db, const char* sql) {
  sqlite::Stmt s(db, sql);
  s.step();
  return s.int64(0);
}

/// Inserts a rule (never replacing one: a taken id or `created` fails the transaction), and its
/// counters when it has been used: a rule without a `rule_uses` row has none (every reader joins
/// with `coalesce(..., 0)`), so a definition's new rules write no counter pages (three b-tree
/// pages of a define's eleven, docs/naturalization.md §5).
void insert_rule(sqlite::Db& db, const StoredRule& r, std::int64_t definition) {
  sqlite::Stmt ins(
      db,
      "INSERT INTO rules(id, created, definition, lhs, rhs, template, author, head, "
      "body, how, deleted, deleted_at, deleted_seq) VALUES (?,?,?,?,?,?,?,?,?,?,?,?,?)");
  ins.bind(1, r.id).bind(2, r.created).bind(3, definition).bind(4, r.lhs);
  ins.bind(5, to_json_list(r.rhs)).bind(6, r.semantics).bind(7, r.author).bind(8, r.head);
  ins.bind(9, to_json_list(r.body)).bind(10, r.how).bind(11, std::int64_t{r.deleted ? 1 : 0});
  if (r.deleted) {
    ins.bind(12, r.deleted_at);
    ins.bind(13, next_value(db, "SELECT coalesce(max(deleted_seq), 0) + 1 FROM rules"));
  } else {
    ins.bind_null(12).bind_null(13);
  }
  ins.run();
  if (r.uses_by_author == 0 && r.uses_by_others == 0) return;
  sqlite::Stmt uses(db,
                    "INSERT INTO rule_uses(rule, by_author, by_others) VALUES (?,?,?) "
                    "ON CONFLICT(rule) DO UPDATE SET by_author = excluded.by_author, "
                    "by_others = excluded.by_others");
  uses.bind(1, r.id)
      .bind(2, static_cast<std::int64_t>(r.uses_by_author))
      .bind(3, static_cast<std::int64_t>(r.uses_by_others))
      .run();
}

// One min/max aggregate per subquery: SQLite answers each from its index in O(log n) (two in
// one SELECT would scan the table).
constexpr const char* kMarkAndRows =
    "SELECT (SELECT coalesce(max(created), 0) FROM rules), "
    "(SELECT coalesce(max(deleted_seq), 0) FROM rules), (SELECT count(*) FROM rules)";

constexpr const char* kRuleSelect =
    "SELECT r.id, r.lhs, r.rhs, r.template, r.author, r.head, r.body, r.how, r.created, "
    "r.definition, r.deleted, r.deleted_at, coalesce(u.by_author,0), coalesce(u.by_others,0) "
    "FROM rules r LEFT JOIN rule_uses u ON u.rule = r.id ";

StoredRule read_rule(const sqlite::Stmt& s) {
  StoredRule r;
  r.id = s.text(0);
  r.lhs = s.text(1);
  decode_list(s.text(2), "rhs", r.rhs, r.decode_error);
  r.semantics = s.text(3);
  r.author = s.text(4);
  r.head = s.text(5);
  decode_list(s.text(6), "body", r.body, r.decode_error);
  r.how = s.text(7);
  r.created = s.int64(8);
  r.definition = s.int64(9);
  r.deleted = s.int64(10) != 0;
  r.deleted_at = s.is_null(11) ? 0 : s.int64(11);
  r.uses_by_author = static_cast<std::uint64_t>(s.int64(12));
  r.uses_by_others = static_cast<std::uint64_t>(s.int64(13));
  return r;
}

}  // namespace

const char* const kRuleSelectForHistory = kRuleSelect;
StoredRule read_history_rule(const sqlite::Stmt& s) {
  return read_rule(s);
}

namespace {

HistoryEntry entry_for(const StoredRule& r, const char* action, const char* effect,
                       const std::string& author, std::int64_t time, const std::string& site) {
  HistoryEntry e;
  e.time = time;
  e.author = author;
  e.action = action;
  e.effect = effect;
  e.rule = r.id;
  e.definition = r.definition;
  e.head = r.head;
  e.body = r.body;
  e.site = site;
  return e;
}

}  // namespace

DefinitionCommit commit_definition_in(sqlite::Db& db, const std::string& site,
                                      const StoredDefinition& d, std::vector<StoredRule> rules) {
  sqlite::Stmt ins(db, "INSERT INTO definitions(head, body, author, time) VALUES (?,?,?,?)");
  ins.bind(1, d.head).bind(2, to_json_list(d.body)).bind(3, d.author).bind(4, d.time).run();
  DefinitionCommit out;
  out.definition = sqlite3_last_insert_rowid(db.raw());
  HistoryEntry def;
  def.time = d.time;
  def.author = d.author;
  def.action = d.via.empty() ? history_action::kDefine : d.via;
  def.effect = history_effect::kNone;
  def.definition = out.definition;
  def.head = d.head;
  def.body = d.body;
  def.study = d.study;
  def.site = site;
  append_history(db, def);
  // Under the write lock: no other process can take these numbers before the commit.
  std::int64_t created = next_value(db, "SELECT coalesce(max(created), 0) + 1 FROM rules");
  for (auto& r : rules) {
    r.created = created++;
    r.id = "r" + std::to_string(r.created);
    r.definition = out.definition;
    r.deleted = false;
    insert_rule(db, r, out.definition);
    HistoryEntry e =
        entry_for(r, history_action::kInduce, history_effect::kAdd, d.author, d.time, site);
    e.study = d.study;
    append_history(db, e);
  }
  out.rules = std::move(rules);
  return out;
}

DefinitionCommit LexiconStore::commit_definition(const StoredDefinition& d,
                                                 std::vector<StoredRule> rules) {
  auto& db = *impl_->db;
  sqlite::Transaction tx(db);
  DefinitionCommit out = commit_definition_in(db, impl_->site, d, std::move(rules));
  tx.commit();
  return out;
}

std::int64_t LexiconStore::add_definition(const StoredDefinition& d,
                                          const std::vector<StoredRule>& rules) {
  return commit_definition(d, rules).definition;
}

std::vector<StoredDefinition> LexiconStore::definitions() const {
  sqlite::Stmt s(*impl_->db, "SELECT id, head, body, author, time FROM definitions ORDER BY id");
  std::vector<StoredDefinition> out;
  while (s.step()) {
    StoredDefinition d{s.int64(0), s.text(1), {}, s.text(3), s.int64(4), {}};
    decode_list(s.text(2), "body", d.body, d.decode_error);
    out.push_back(std::move(d));
  }
  return out;
}

std::vector<StoredRule> LexiconStore::rules(bool include_deleted) const {
  std::string sql = kRuleSelect;
  if (!include_deleted) sql += "WHERE r.deleted = 0 ";
  sql += "ORDER BY r.created";
  sqlite::Stmt s(*impl_->db, sql.c_str());
  std::vector<StoredRule> out;
  while (s.step()) out.push_back(read_rule(s));
  return out;
}

std::optional<StoredRule> LexiconStore::rule(const std::string& id) const {
  const std::string sql = std::string(kRuleSelect) + "WHERE r.id = ?";
  sqlite::Stmt s(*impl_->db, sql.c_str());
  s.bind(1, id);
  if (!s.step()) return std::nullopt;
  return read_rule(s);
}

std::int64_t LexiconStore::max_created() const {
  sqlite::Stmt s(*impl_->db, "SELECT coalesce(max(created), 0) FROM rules");
  s.step();
  return s.int64(0);
}

/// Flags `id` deleted with the next deletion sequence number (inside the caller's transaction).
void flag_rule_deleted(sqlite::Db& db, const std::string& id, std::int64_t time) {
  const std::int64_t seq = next_value(db, "SELECT coalesce(max(deleted_seq), 0) + 1 FROM rules");
  sqlite::Stmt s(db,
                 "UPDATE rules SET deleted = 1, deleted_at = ?, deleted_seq = ? "
                 "WHERE id = ? AND deleted = 0");
  s.bind(1, time).bind(2, seq).bind(3, id).run();
}

bool LexiconStore::mark_deleted(const std::string& id, std::int64_t time) {
  auto& db = *impl_->db;
  sqlite::Transaction tx(db);
  flag_rule_deleted(db, id, time);
  const bool changed = sqlite3_changes(db.raw()) > 0;
  if (changed) {
    const auto r = rule(id);
    append_history(db, entry_for(*r, history_action::kDelete, history_effect::kRemove, r->author,
                                 time, impl_->site));
  }
  tx.commit();
  return changed;
}

DeleteResult LexiconStore::delete_rule(
    const std::string& id, const std::string& user, std::int64_t time,
    const std::function<bool(const std::string& author)>& visible_to_user) {
  auto& db = *impl_->db;
  sqlite::Transaction tx(db);  // the check and the delete see the same, locked, state
  DeleteResult out;
  {
    sqlite::Stmt s(db, "SELECT author FROM rules WHERE id = ? AND deleted = 0");
    s.bind(1, id);
    if (!s.step()) return out;  // not_found (rolled back: nothing written)
    const std::string author = s.text(0);
    if (author != user) {
      if (visible_to_user && visible_to_user(author)) {
        out.status = DeleteStatus::forbidden;
        out.author = author;
      }
      return out;
    }
    out.author = author;
  }
  flag_rule_deleted(db, id, time);
  const auto r = rule(id);
  append_history(
      db, entry_for(*r, history_action::kDelete, history_effect::kRemove, user, time, impl_->site));
  tx.commit();
  out.status = DeleteStatus::deleted;
  return out;
}

LexiconChanges LexiconStore::changes_since(const ChangeMark& since) const {
  auto& db = *impl_->db;
  sqlite::ReadTransaction snapshot(db);
  LexiconChanges out;
  {
    const std::string sql =
        std::string(kRuleSelect) + "WHERE r.created > ? AND r.deleted = 0 ORDER BY r.created";
    sqlite::Stmt s(db, sql.c_str());
    s.bind(1, since.created);
    while (s.step()) out.added.push_back(read_rule(s));
  }
  {
    sqlite::Stmt s(db, "SELECT id FROM rules WHERE deleted_seq > ? ORDER BY deleted_seq");
    s.bind(1, since.deleted);
    while (s.step()) out.deleted.push_back(s.text(0));
  }
  sqlite::Stmt m(db, kMarkAndRows);
  m.step();
  out.mark = {std::max(since.created, m.int64(0)), std::max(since.deleted, m.int64(1))};
  return out;
}

LiveRulesRead LexiconStore::read_live_rules(const std::function<void(StoredRule&&)>& each) const {
  auto& db = *impl_->db;
  sqlite::ReadTransaction snapshot(db);
  LiveRulesRead out;
  {
    sqlite::Stmt s(db,
                   "SELECT id, lhs, rhs, template, author, head, body, how, created, definition "
                   "FROM rules WHERE deleted = 0 ORDER BY created");
    while (s.step()) {
      StoredRule r;
      r.id = s.text(0);
      r.lhs = s.text(1);
      decode_list(s.text(2), "rhs", r.rhs, r.decode_error);
      r.semantics = s.text(3);
      r.author = s.text(4);
      r.head = s.text(5);
      decode_list(s.text(6), "body", r.body, r.decode_error);
      r.how = s.text(7);
      r.created = s.int64(8);
      r.definition = s.int64(9);
      each(std::move(r));
    }
  }
  sqlite::Stmt m(db, kMarkAndRows);
  m.step();
  out.mark = {m.int64(0), m.int64(1)};
  out.rows = m.int64(2);
  return out;
}

std::vector<RuleUses> LexiconStore::nonzero_uses() const {
  sqlite::Stmt s(*impl_->db,
                 "SELECT rule, by_author, by_others FROM rule_uses "
                 "WHERE by_author <> 0 OR by_others <> 0");
  std::vector<RuleUses> out;
  while (s.step())
    out.push_back({s.text(0), static_cast<std::uint64_t>(s.int64(1)),
                   static_cast<std::uint64_t>(s.int64(2))});
  return out;
}

void LexiconStore::verify() {
  verify_pages(*impl_->db);
}

bool LexiconStore::changed_elsewhere() {
  Impl& m = *impl_;
  // The header is read before the pragma, so a commit racing with both shows next time.
  std::optional<WalIndexWatch::Header> header = m.wal_index.read();
  if (header && m.last_data_version && header == m.header_at_last_read) return false;
  auto& s = *m.data_version;
  s.step();
  const std::int64_t v = s.int64(0);
  s.reset();
  ++m.data_version_reads;
  const bool changed = !m.last_data_version || *m.last_data_version != v;
  m.last_data_version = v;
  // Only a header read before the pragma may stand for it: one read after could already show a
  // commit the pragma did not see. So the call that maps the index records none.
  m.header_at_last_read = header;
  if (!m.wal_index_tried) {  // SQLite mapped the index for the read above
    m.wal_index_tried = true;
    // A store open for writing is in WAL mode (open_writable); a read-only one may keep its
    // index in private memory, which only its own reads refresh: it always asks SQLite.
    if (!m.db->read_only() && m.db->write_refusal() == nullptr && journal_mode(*m.db) == "wal")
      m.wal_index.map(m.db->raw());
  }
  return changed;
}

std::uint64_t LexiconStore::data_version_reads() const {
  return impl_->data_version_reads;
}

namespace {
// The learning sequence of a write transaction: one more than any stored (indexed maxima).
std::int64_t next_learned(sqlite::Db& db) {
  sqlite::Stmt s(db,
                 "SELECT max((SELECT coalesce(max(seq), 0) FROM rule_uses), "
                 "(SELECT coalesce(max(seq), 0) FROM scorer_weights), "
                 "(SELECT coalesce(max(seq), 0) FROM scorer_state)) + 1");
  s.step();
  return s.int64(0);
}

}  // namespace

namespace {
bool has_learned_seq(sqlite::Db& db) {
  sqlite::Stmt has(db, "SELECT 1 FROM pragma_table_info('rule_uses') WHERE name = 'seq'");
  return has.step();  // not in a read-only store of version 2 or 3
}
}  // namespace

std::int64_t LexiconStore::learned_mark() const {
  auto& db = *impl_->db;
  if (!has_learned_seq(db)) return 0;
  return next_learned(db) - 1;
}

LearnedChanges LexiconStore::learned_since(std::int64_t since) const {
  auto& db = *impl_->db;
  LearnedChanges out;
  out.mark = since;
  if (!has_learned_seq(db)) return out;
  sqlite::ReadTransaction snapshot(db);
  {
    sqlite::Stmt s(db, "SELECT rule, by_author, by_others, seq FROM rule_uses WHERE seq > ?");
    s.bind(1, since);
    while (s.step()) {
      out.uses.push_back({s.text(0), static_cast<std::uint64_t>(s.int64(1)),
                          static_cast<std::uint64_t>(s.int64(2))});
      out.mark = std::max(out.mark, s.int64(3));
    }
  }
  for (const char* sql : {"SELECT key, max(seq) FROM scorer_weights WHERE seq > ? GROUP BY key",
                          "SELECT key, seq FROM scorer_state WHERE seq > ?"}) {
    sqlite::Stmt s(db, sql);
    s.bind(1, since);
    while (s.step()) {
      if (std::find(out.weight_keys.begin(), out.weight_keys.end(), s.text(0)) ==
          out.weight_keys.end())
        out.weight_keys.push_back(s.text(0));
      out.mark = std::max(out.mark, s.int64(1));
    }
  }
  return out;
}

namespace {
void upsert_weights(sqlite::Db& db, const std::string& key, const std::string& state) {
  sqlite::Stmt s(db,
                 "INSERT INTO scorer_state(key, state, seq) VALUES (?, ?, ?) "
                 "ON CONFLICT(key) DO UPDATE SET state = excluded.state, seq = excluded.seq");
  s.bind(1, key).bind(2, state).bind(3, next_learned(db)).run();
}
}  // namespace

namespace {
// Adds `deltas` to the rules' counters; returns the totals after (other processes' included).
std::vector<RuleUses> add_uses(sqlite::Db& db, const std::vector<RuleUses>& deltas,
                               std::int64_t seq) {
  sqlite::Stmt add(db,
                   "INSERT INTO rule_uses(rule, by_author, by_others, seq) VALUES (?,?,?,?) "
                   "ON CONFLICT(rule) DO UPDATE SET by_author = by_author + excluded.by_author, "
                   "by_others = by_others + excluded.by_others, seq = excluded.seq");
  sqlite::Stmt total(db, "SELECT by_author, by_others FROM rule_uses WHERE rule = ?");
  std::vector<RuleUses> totals;
  for (const auto& u : deltas) {
    add.bind(1, u.rule)
        .bind(2, static_cast<std::int64_t>(u.by_author))
        .bind(3, static_cast<std::int64_t>(u.by_others))
        .bind(4, seq)
        .run();
    total.bind(1, u.rule);
    total.step();
    totals.push_back({u.rule, static_cast<std::uint64_t>(total.int64(0)),
                      static_cast<std::uint64_t>(total.int64(1))});
    total.reset();
  }
  return totals;
}
}  // namespace

std::vector<RuleUses> LexiconStore::record_accept(const std::vector<RuleUses>& deltas,
                                                  const std::string& weights_key,
                                                  const std::string& weights_state) {
  auto& db = *impl_->db;
  sqlite::Transaction tx(db);
  std::vector<RuleUses> totals = add_uses(db, deltas, next_learned(db));
  if (!weights_key.empty()) upsert_weights(db, weights_key, weights_state);
  tx.commit();
  return totals;
}

namespace {
void add_weight_changes(sqlite::Db& db, const std::string& key,
                        const std::vector<StoredWeightChange>& changes,
                        LexiconStore::WeightSums* sums = nullptr) {
  std::unique_ptr<sqlite::Stmt> sum;
  if (sums)
    sum = std::make_unique<sqlite::Stmt>(
        db, "SELECT weight, aux FROM scorer_weights WHERE key = ? AND model = ? AND feature = ?");
  const auto read = [&](const StoredWeightChange& c, std::vector<StoredWeightChange>& into) {
    sum->bind(1, key).bind(2, c.model).bind(3, c.feature);
    const bool found = sum->step();
    into.push_back({c.model, c.feature, found ? sum->real(0) : 0.0, found ? sum->real(1) : 0.0});
    sum->reset();
  };
  const std::int64_t seq = next_learned(db);
  sqlite::Stmt add(db,
                   "INSERT INTO scorer_weights(key, model, feature, weight, aux, seq) "
                   "VALUES (?,?,?,?,?,?) ON CONFLICT(key, model, feature) DO UPDATE SET "
                   "weight = weight + excluded.weight, aux = aux + excluded.aux, "
                   "seq = excluded.seq");
  for (const auto& c : changes) {
    if (sums) read(c, sums->before);
    add.bind(1, key).bind(2, c.model).bind(3, c.feature).bind_real(4, c.weight).bind_real(5, c.aux);
    add.bind(6, seq);
    add.run();
    add.reset();
    if (sums) read(c, sums->after);
  }
}
}  // namespace

std::vector<RuleUses> LexiconStore::record_accept(const std::vector<RuleUses>& deltas,
                                                  const std::string& weights_key,
                                                  const std::vector<StoredWeightChange>& changes,
                                                  WeightSums* sums) {
  auto& db = *impl_->db;
  sqlite::Transaction tx(db);
  std::vector<RuleUses> totals = add_uses(db, deltas, next_learned(db));
  add_weight_changes(db, weights_key, changes, sums);
  tx.commit();
  return totals;
}

std::vector<StoredWeightChange> LexiconStore::weight_changes(const std::string& key) const {
  std::vector<StoredWeightChange> out;
  sqlite::Stmt has(*impl_->db, "SELECT 1 FROM sqlite_master WHERE name = 'scorer_weights'");
  if (!has.step()) return out;  // a read-only version-2 store
  sqlite::Stmt s(*impl_->db,
                 "SELECT model, feature, weight, aux FROM scorer_weights WHERE key = ? "
                 "ORDER BY model, feature");
  s.bind(1, key);
  while (s.step()) out.push_back({s.text(0), s.text(1), s.real(2), s.real(3)});
  return out;
}

void LexiconStore::save_weights(const std::string& key, const std::string& state) {
  auto& db = *impl_->db;
  sqlite::Transaction tx(db);
  upsert_weights(db, key, state);
  tx.commit();
}

std::optional<std::string> LexiconStore::load_weights(const std::string& key) const {
  sqlite::Stmt s(*impl_->db, "SELECT state FROM scorer_state WHERE key = ?");
  s.bind(1, key);
  if (!s.step()) return std::nullopt;
  return s.text(0);
}

// ---- JSON Lines export/import (a portable, diffable copy of the whole store) ----

void LexiconStore::export_jsonl(
    std::ostream& out,
    const std::function<std::optional<std::string>(const StoredRule&)>& quarantine_reason) const {
  for (const auto& d : definitions()) {
    json line{{"type", "definition"}, {"id", d.id},         {"head", d.head},
              {"body", d.body},       {"author", d.author}, {"time", d.time}};
    if (!d.decode_error.empty()) line["quarantined"] = d.decode_error;
    out << line.dump() << '\n';
  }
  for (const auto& r : rules(true)) {
    json line{{"type", "rule"},
              {"id", r.id},
              {"lhs", r.lhs},
              {"rhs", r.rhs},
              {"semantics", r.semantics},
              {"author", r.author},
              {"head", r.head},
              {"body", r.body},
              {"how", r.how},
              {"created", r.created},
              {"definition", r.definition},
              {"deleted", r.deleted},
              {"deleted_at", r.deleted_at},
              {"uses_by_author", r.uses_by_author},
              {"uses_by_others", r.uses_by_others}};
    if (quarantine_reason)
      if (auto why = quarantine_reason(r)) line["quarantined"] = *why;
    out << line.dump() << '\n';
  }
  sqlite::Stmt s(*impl_->db, "SELECT key, state FROM scorer_state ORDER BY key");
  while (s.step())
    out << json{{"type", "weights"}, {"key", s.text(0)}, {"state", s.text(1)}}.dump() << '\n';
  sqlite::Stmt keys(*impl_->db, "SELECT DISTINCT key FROM scorer_weights ORDER BY key");
  while (keys.step())
    for (const auto& c : weight_changes(keys.text(0)))
      out << json{{"type", "weight"},     {"key", keys.text(0)}, {"model", c.model},
                  {"feature", c.feature}, {"weight", c.weight},  {"aux", c.aux}}
                 .dump()
          << '\n';
  for (const auto& f : preload_failures())
    out << json{{"type", "preload_failure"},
                {"file", f.file},
                {"line", f.line},
                {"head", f.head},
                {"author", f.author},
                {"code", f.code},
                {"message", f.message},
                {"time", f.time}}
               .dump()
        << '\n';
}

std::size_t LexiconStore::import_jsonl(std::istream& in) {
  auto& db = *impl_->db;
  sqlite::Transaction tx(db);
  std::string line;
  std::size_t n = 0, line_no = 0;
  std::vector<PreloadFailure> failures;  // the report of the exporting store, copied as it was
  const auto import_time = static_cast<std::int64_t>(std::time(nullptr));
  while (std::getline(in, line)) {
    ++line_no;
    if (line.find_first_not_of(" \t\r") == std::string::npos) continue;
    try {
      const json j = json::parse(line);
      const std::string type = j.at("type").get<std::string>();
      if (type == "definition") {
        const auto id = j.at("id").get<std::int64_t>();
        sqlite::Stmt taken(db, "SELECT 1 FROM definitions WHERE id = ?");
        if (taken.bind(1, id).step())
          throw std::runtime_error("definition " + std::to_string(id) + " is already stored");
        sqlite::Stmt ins(
            db, "INSERT INTO definitions(id, head, body, author, time) VALUES (?,?,?,?,?)");
        ins.bind(1, id)
            .bind(2, j.at("head").get<std::string>())
            .bind(3, j.at("body").dump())
            .bind(4, j.at("author").get<std::string>())
            .bind(5, j.value("time", std::int64_t{0}))
            .run();
        HistoryEntry e;
        e.time = import_time;
        e.author = j.at("author").get<std::string>();
        e.action = history_action::kImport;
        e.effect = history_effect::kNone;
        e.definition = id;
        e.head = j.at("head").get<std::string>();
        if (j.at("body").is_array())
          for (const auto& body_line : j.at("body"))
            if (body_line.is_string()) e.body.push_back(body_line.get<std::string>());
        e.site = impl_->site;
        e.note = "lexicon import --restore";
        append_history(db, e);
      } else if (type == "rule") {
        StoredRule r;
        r.id = j.at("id").get<std::string>();
        r.lhs = j.at("lhs").get<std::string>();
        r.rhs = j.at("rhs").get<std::vector<std::string>>();
        r.semantics = j.at("semantics").get<std::string>();
        r.author = j.at("author").get<std::string>();
        r.head = j.value("head", std::string());
        r.body = j.value("body", std::vector<std::string>());
        r.how = j.at("how").get<std::string>();
        r.created = j.at("created").get<std::int64_t>();
        r.deleted = j.value("deleted", false);
        r.deleted_at = j.value("deleted_at", std::int64_t{0});
        r.uses_by_author = j.value("uses_by_author", std::uint64_t{0});
        r.uses_by_others = j.value("uses_by_others", std::uint64_t{0});
        sqlite::Stmt taken(db, "SELECT 1 FROM rules WHERE id = ? OR created = ?");
        if (taken.bind(1, r.id).bind(2, r.created).step())
          throw std::runtime_error("rule " + r.id + " (created " + std::to_string(r.created) +
                                   ") is already stored");
        r.definition = j.value("definition", std::int64_t{0});
        insert_rule(db, r, r.definition);
        // A verbatim copy keeps ids and `created`: its history says so, and what it deleted.
        HistoryEntry e = entry_for(r, history_action::kImport, history_effect::kAdd, r.author,
                                   import_time, impl_->site);
        e.note = "lexicon import --restore";
        append_history(db, e);
        if (r.deleted) {
          HistoryEntry gone = entry_for(r, history_action::kImport, history_effect::kRemove,
                                        r.author, import_time, impl_->site);
          gone.note = "deleted in the imported store";
          append_history(db, gone);
        }
      } else if (type == "weight") {
        add_weight_changes(db, j.at("key").get<std::string>(),
                           {{j.at("model").get<std::string>(), j.at("feature").get<std::string>(),
                             j.at("weight").get<double>(), j.value("aux", 0.0)}});
      } else if (type == "weights") {
        upsert_weights(db, j.at("key").get<std::string>(), j.at("state").get<std::string>());
      } else if (type == "preload_failure") {
        failures.push_back({j.at("file").get<std::string>(), j.at("line").get<std::int64_t>(),
                            j.at("head").get<std::string>(), j.at("author").get<std::string>(),
                            j.at("code").get<std::string>(), j.at("message").get<std::string>(),
                            j.value("time", std::int64_t{0})});
      } else {
        throw std::runtime_error("unknown type '" + type + "'");
      }
      ++n;
    } catch (const sdk::Error&) {
      throw;
    } catch (const std::exception& e) {
      throw sdk::Error(sdk::codes::kBadRequest,
                       "lexicon import line " + std::to_string(line_no) + ": " + e.what());
    }
  }
  insert_preload_failures(db, failures);
  tx.commit();
  return n;
}

}  // namespace flipper::naturalization
