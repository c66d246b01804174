#include "flipper/kernel/lexicon_store.hpp"

#include <filesystem>
#include <istream>
#include <nlohmann/json.hpp>
#include <ostream>

#include "flipper/sdk/errors.hpp"
#include "sqlite_handle.hpp"

namespace flipper::kernel {
namespace fs = std::filesystem;
using nlohmann::json;

namespace {

constexpr const char* kSchema = R"sql(
CREATE TABLE IF NOT EXISTS flipper_schema(version INTEGER NOT NULL);
CREATE TABLE IF NOT EXISTS definitions(
  id INTEGER PRIMARY KEY, head TEXT NOT NULL, body TEXT NOT NULL, author TEXT NOT NULL,
  time INTEGER NOT NULL);
CREATE TABLE IF NOT EXISTS rules(
  id TEXT PRIMARY KEY, created INTEGER NOT NULL UNIQUE, definition INTEGER NOT NULL,
  lhs TEXT NOT NULL, rhs TEXT NOT NULL, template TEXT NOT NULL, author TEXT NOT NULL,
  head TEXT NOT NULL, body TEXT NOT NULL, how TEXT NOT NULL,
  deleted INTEGER NOT NULL DEFAULT 0, deleted_at INTEGER);
CREATE TABLE IF NOT EXISTS rule_uses(
  rule TEXT PRIMARY KEY, by_author INTEGER NOT NULL, by_others INTEGER NOT NULL);
CREATE TABLE IF NOT EXISTS scorer_state(key TEXT PRIMARY KEY, state TEXT NOT NULL);
)sql";

std::string to_json_list(const std::vector<std::string>& v) {
  return json(v).dump();
}

std::vector<std::string> from_json_list(const std::string& text, const std::string& path) {
  try {
    return json::parse(text).get<std::vector<std::string>>();
  } catch (const std::exception&) {
    throw sdk::Error(lexicon_codes::kBadLexicon,
                     "lexicon store '" + path + "': malformed list column: " + text);
  }
}

}  // namespace

struct LexiconStore::Impl {
  std::unique_ptr<sqlite::Db> db;
  std::string path;
};

namespace {

/// Refuses anything that is not an empty database or a Flipper lexicon, before any write.
void check_existing(sqlite::Db& db) {
  sqlite::Stmt tables(db, "SELECT name FROM sqlite_master WHERE type='table'");
  bool any = false, ours = false;
  while (tables.step()) {
    any = true;
    if (tables.text(0) == "flipper_schema") ours = true;
  }
  if (any && !ours)
    throw sdk::Error(lexicon_codes::kBadLexicon,
                     "lexicon store '" + db.path() + "': not a Flipper lexicon (foreign tables)");
  if (ours) {
    sqlite::Stmt v(db, "SELECT max(version) FROM flipper_schema");
    if (v.step() && v.int64(0) > LexiconStore::kSchemaVersion)
      throw sdk::Error(lexicon_codes::kBadLexicon,
                       "lexicon store '" + db.path() + "': schema version " +
                           std::to_string(v.int64(0)) + " is newer than this build's " +
                           std::to_string(LexiconStore::kSchemaVersion));
  }
  sqlite::Stmt check(db, "PRAGMA quick_check");
  if (check.step() && check.text(0) != "ok")
    throw sdk::Error(lexicon_codes::kBadLexicon,
                     "lexicon store '" + db.path() + "': corrupt: " + check.text(0));
}

}  // namespace

LexiconStore::LexiconStore(const std::string& path) : impl_(std::make_unique<Impl>()) {
  impl_->path = path;
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
        throw sdk::Error(lexicon_codes::kBadLexicon, "lexicon store '" + path +
                                                         "': cannot create directory '" +
                                                         parent.string() + "': " + ec.message());
    }
  }
  impl_->db = std::make_unique<sqlite::Db>(path, !existed);
  auto& db = *impl_->db;
  if (existed) check_existing(db);
  // WAL + FULL: every COMMIT is on disk when it returns, and a kill mid-write never corrupts.
  db.exec("PRAGMA journal_mode=WAL; PRAGMA synchronous=FULL;");
  {
    sqlite::Transaction tx(db);
    db.exec(kSchema);
    sqlite::Stmt count(db, "SELECT count(*) FROM flipper_schema");
    count.step();
    if (count.int64(0) == 0) {
      sqlite::Stmt ins(db, "INSERT INTO flipper_schema(version) VALUES (?)");
      ins.bind(1, std::int64_t{kSchemaVersion}).run();
    }
    tx.commit();
  }
}

LexiconStore::~LexiconStore() = default;

const std::string& LexiconStore::path() const {
  return impl_->path;
}

namespace {

void insert_rule(sqlite::Db& db, const StoredRule& r, std::int64_t definition) {
  sqlite::Stmt ins(db,
                   "INSERT OR REPLACE INTO rules(id, created, definition, lhs, rhs, template, "
                   "author, head, body, how, deleted, deleted_at) "
                   "VALUES (?,?,?,?,?,?,?,?,?,?,?,?)");
  ins.bind(1, r.id).bind(2, r.created).bind(3, definition).bind(4, r.lhs);
  ins.bind(5, to_json_list(r.rhs)).bind(6, r.semantics).bind(7, r.author).bind(8, r.head);
  ins.bind(9, to_json_list(r.body)).bind(10, r.how).bind(11, std::int64_t{r.deleted ? 1 : 0});
  if (r.deleted)
    ins.bind(12, r.deleted_at);
  else
    ins.bind_null(12);
  ins.run();
  sqlite::Stmt uses(db,
                    "INSERT OR REPLACE INTO rule_uses(rule, by_author, by_others) VALUES (?,?,?)");
  uses.bind(1, r.id)
      .bind(2, static_cast<std::int64_t>(r.uses_by_author))
      .bind(3, static_cast<std::int64_t>(r.uses_by_others))
      .run();
}

constexpr const char* kRuleSelect =
    "SELECT r.id, r.lhs, r.rhs, r.template, r.author, r.head, r.body, r.how, r.created, "
    "r.definition, r.deleted, r.deleted_at, coalesce(u.by_author,0), coalesce(u.by_others,0) "
    "FROM rules r LEFT JOIN rule_uses u ON u.rule = r.id ";

StoredRule read_rule(const sqlite::Stmt& s, const std::string& path) {
  StoredRule r;
  r.id = s.text(0);
  r.lhs = s.text(1);
  r.rhs = from_json_list(s.text(2), path);
  r.semantics = s.text(3);
  r.author = s.text(4);
  r.head = s.text(5);
  r.body = from_json_list(s.text(6), path);
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

std::int64_t LexiconStore::add_definition(const StoredDefinition& d,
                                          const std::vector<StoredRule>& rules) {
  auto& db = *impl_->db;
  sqlite::Transaction tx(db);
  sqlite::Stmt ins(db, "INSERT INTO definitions(id, head, body, author, time) VALUES (?,?,?,?,?)");
  if (d.id > 0)
    ins.bind(1, d.id);
  else
    ins.bind_null(1);
  ins.bind(2, d.head).bind(3, to_json_list(d.body)).bind(4, d.author).bind(5, d.time).run();
  const std::int64_t id = sqlite3_last_insert_rowid(db.raw());
  for (const auto& r : rules) insert_rule(db, r, id);
  tx.commit();
  return id;
}

std::vector<StoredDefinition> LexiconStore::definitions() const {
  sqlite::Stmt s(*impl_->db, "SELECT id, head, body, author, time FROM definitions ORDER BY id");
  std::vector<StoredDefinition> out;
  while (s.step())
    out.push_back(
        {s.int64(0), s.text(1), from_json_list(s.text(2), impl_->path), s.text(3), s.int64(4)});
  return out;
}

std::vector<StoredRule> LexiconStore::rules(bool include_deleted) const {
  std::string sql = kRuleSelect;
  if (!include_deleted) sql += "WHERE r.deleted = 0 ";
  sql += "ORDER BY r.created";
  sqlite::Stmt s(*impl_->db, sql.c_str());
  std::vector<StoredRule> out;
  while (s.step()) out.push_back(read_rule(s, impl_->path));
  return out;
}

std::optional<StoredRule> LexiconStore::rule(const std::string& id) const {
  const std::string sql = std::string(kRuleSelect) + "WHERE r.id = ?";
  sqlite::Stmt s(*impl_->db, sql.c_str());
  s.bind(1, id);
  if (!s.step()) return std::nullopt;
  return read_rule(s, impl_->path);
}

std::int64_t LexiconStore::max_created() const {
  sqlite::Stmt s(*impl_->db, "SELECT coalesce(max(created), 0) FROM rules");
  s.step();
  return s.int64(0);
}

bool LexiconStore::mark_deleted(const std::string& id, std::int64_t time) {
  auto& db = *impl_->db;
  sqlite::Transaction tx(db);
  sqlite::Stmt s(db, "UPDATE rules SET deleted = 1, deleted_at = ? WHERE id = ? AND deleted = 0");
  s.bind(1, time).bind(2, id).run();
  const bool changed = sqlite3_changes(db.raw()) > 0;
  tx.commit();
  return changed;
}

namespace {
void upsert_weights(sqlite::Db& db, const std::string& key, const std::string& state) {
  sqlite::Stmt s(db, "INSERT OR REPLACE INTO scorer_state(key, state) VALUES (?, ?)");
  s.bind(1, key).bind(2, state).run();
}
}  // namespace

void LexiconStore::record_accept(const std::vector<RuleUses>& uses, const std::string& weights_key,
                                 const std::string& weights_state) {
  auto& db = *impl_->db;
  sqlite::Transaction tx(db);
  sqlite::Stmt s(db, "INSERT OR REPLACE INTO rule_uses(rule, by_author, by_others) VALUES (?,?,?)");
  for (const auto& u : uses) {
    s.bind(1, u.rule)
        .bind(2, static_cast<std::int64_t>(u.by_author))
        .bind(3, static_cast<std::int64_t>(u.by_others))
        .run();
  }
  if (!weights_key.empty()) upsert_weights(db, weights_key, weights_state);
  tx.commit();
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

void LexiconStore::export_jsonl(std::ostream& out) const {
  for (const auto& d : definitions())
    out << json{{"type", "definition"}, {"id", d.id},         {"head", d.head},
                {"body", d.body},       {"author", d.author}, {"time", d.time}}
               .dump()
        << '\n';
  for (const auto& r : rules(true))
    out << json{{"type", "rule"},
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
                {"uses_by_others", r.uses_by_others}}
               .dump()
        << '\n';
  sqlite::Stmt s(*impl_->db, "SELECT key, state FROM scorer_state ORDER BY key");
  while (s.step())
    out << json{{"type", "weights"}, {"key", s.text(0)}, {"state", s.text(1)}}.dump() << '\n';
}

std::size_t LexiconStore::import_jsonl(std::istream& in) {
  auto& db = *impl_->db;
  sqlite::Transaction tx(db);
  std::string line;
  std::size_t n = 0, line_no = 0;
  while (std::getline(in, line)) {
    ++line_no;
    if (line.find_first_not_of(" \t\r") == std::string::npos) continue;
    try {
      const json j = json::parse(line);
      const std::string type = j.at("type").get<std::string>();
      if (type == "definition") {
        sqlite::Stmt ins(db,
                         "INSERT OR REPLACE INTO definitions(id, head, body, author, time) "
                         "VALUES (?,?,?,?,?)");
        ins.bind(1, j.at("id").get<std::int64_t>())
            .bind(2, j.at("head").get<std::string>())
            .bind(3, j.at("body").dump())
            .bind(4, j.at("author").get<std::string>())
            .bind(5, j.value("time", std::int64_t{0}))
            .run();
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
        insert_rule(db, r, j.value("definition", std::int64_t{0}));
      } else if (type == "weights") {
        upsert_weights(db, j.at("key").get<std::string>(), j.at("state").get<std::string>());
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
  tx.commit();
  return n;
}

}  // namespace flipper::kernel
