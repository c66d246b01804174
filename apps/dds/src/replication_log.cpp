#include "flipper/dds/replication_log.hpp"

#include <sqlite3.h>

#include <nlohmann/json.hpp>

#include "flipper/sdk/errors.hpp"

namespace flipper::dds {
namespace {

using nlohmann::json;

[[noreturn]] void fail(sqlite3* db, const std::string& what) {
  throw sdk::Error("bad_lexicon", "replication log: " + what + ": " +
                                      (db != nullptr ? sqlite3_errmsg(db) : "out of memory"));
}

const char* kSchema =
    "CREATE TABLE IF NOT EXISTS dds_replication("
    " site TEXT NOT NULL, version INTEGER NOT NULL, status TEXT NOT NULL,"
    " definition INTEGER NOT NULL DEFAULT 0, local_rules TEXT NOT NULL DEFAULT '[]',"
    " event TEXT NOT NULL, PRIMARY KEY(site, version))";

const char* kHeldSchema =
    "CREATE TABLE IF NOT EXISTS dds_held("
    " held TEXT PRIMARY KEY, own INTEGER NOT NULL, event TEXT NOT NULL)";

}  // namespace

struct ReplicationLog::Db {
  sqlite3* db = nullptr;
  ~Db() { sqlite3_close(db); }
};

ReplicationLog::ReplicationLog(const std::string& path) : db_(std::make_unique<Db>()) {
  if (sqlite3_open_v2(path.c_str(), &db_->db, SQLITE_OPEN_READWRITE | SQLITE_OPEN_CREATE,
                      nullptr) != SQLITE_OK)
    fail(db_->db, "cannot open '" + path + "'");
  sqlite3_busy_timeout(db_->db, 10000);  // the store's connection writes to the same file
  for (const char* sql :
       {"PRAGMA journal_mode=WAL", "PRAGMA synchronous=FULL", kSchema, kHeldSchema})
    if (sqlite3_exec(db_->db, sql, nullptr, nullptr, nullptr) != SQLITE_OK)
      fail(db_->db, std::string("setting up (") + sql + ")");
  sqlite3_stmt* st = nullptr;
  if (sqlite3_prepare_v2(db_->db,
                         "SELECT status, definition, local_rules, event FROM dds_replication", -1,
                         &st, nullptr) != SQLITE_OK)
    fail(db_->db, "reading");
  while (sqlite3_step(st) == SQLITE_ROW) {
    LogRow row;
    row.status = reinterpret_cast<const char*>(sqlite3_column_text(st, 0));
    row.definition = sqlite3_column_int64(st, 1);
    row.local_rules = json::parse(reinterpret_cast<const char*>(sqlite3_column_text(st, 2)))
                          .get<std::vector<std::string>>();
    row.event =
        event_from_json(json::parse(reinterpret_cast<const char*>(sqlite3_column_text(st, 3))));
    rows_[{row.event.site, row.event.version}] = std::move(row);
  }
  sqlite3_finalize(st);
  if (sqlite3_prepare_v2(db_->db, "SELECT held, own, event FROM dds_held", -1, &st, nullptr) !=
      SQLITE_OK)
    fail(db_->db, "reading the held definitions");
  while (sqlite3_step(st) == SQLITE_ROW) {
    HeldRow row;
    row.held = reinterpret_cast<const char*>(sqlite3_column_text(st, 0));
    row.own = sqlite3_column_int(st, 1) != 0;
    row.event =
        event_from_json(json::parse(reinterpret_cast<const char*>(sqlite3_column_text(st, 2))));
    held_[row.held] = std::move(row);
  }
  sqlite3_finalize(st);
}

ReplicationLog::~ReplicationLog() = default;

void ReplicationLog::put_held(const HeldRow& row) {
  sqlite3_stmt* st = nullptr;
  if (sqlite3_prepare_v2(db_->db, "INSERT OR REPLACE INTO dds_held(held, own, event) VALUES(?,?,?)",
                         -1, &st, nullptr) != SQLITE_OK)
    fail(db_->db, "preparing a write");
  const std::string event = to_json(row.event).dump(-1, ' ', false, json::error_handler_t::replace);
  sqlite3_bind_text(st, 1, row.held.c_str(), -1, SQLITE_TRANSIENT);
  sqlite3_bind_int(st, 2, row.own ? 1 : 0);
  sqlite3_bind_text(st, 3, event.c_str(), -1, SQLITE_TRANSIENT);
  const int rc = sqlite3_step(st);
  sqlite3_finalize(st);
  if (rc != SQLITE_DONE) fail(db_->db, "writing held definition " + row.held);
  held_[row.held] = row;
}

void ReplicationLog::drop_held(const std::string& held) {
  sqlite3_stmt* st = nullptr;
  if (sqlite3_prepare_v2(db_->db, "DELETE FROM dds_held WHERE held = ?", -1, &st, nullptr) !=
      SQLITE_OK)
    fail(db_->db, "preparing a write");
  sqlite3_bind_text(st, 1, held.c_str(), -1, SQLITE_TRANSIENT);
  const int rc = sqlite3_step(st);
  sqlite3_finalize(st);
  if (rc != SQLITE_DONE) fail(db_->db, "dropping held definition " + held);
  held_.erase(held);
}

void ReplicationLog::put(const LogRow& row) {
  sqlite3_stmt* st = nullptr;
  if (sqlite3_prepare_v2(db_->db,
                         "INSERT OR REPLACE INTO dds_replication(site, version, status, "
                         "definition, local_rules, event) VALUES(?,?,?,?,?,?)",
                         -1, &st, nullptr) != SQLITE_OK)
    fail(db_->db, "preparing a write");
  const std::string rules = json(row.local_rules).dump();
  const std::string event = to_json(row.event).dump(-1, ' ', false, json::error_handler_t::replace);
  sqlite3_bind_text(st, 1, row.event.site.c_str(), -1, SQLITE_TRANSIENT);
  sqlite3_bind_int64(st, 2, static_cast<sqlite3_int64>(row.event.version));
  sqlite3_bind_text(st, 3, row.status.c_str(), -1, SQLITE_TRANSIENT);
  sqlite3_bind_int64(st, 4, row.definition);
  sqlite3_bind_text(st, 5, rules.c_str(), -1, SQLITE_TRANSIENT);
  sqlite3_bind_text(st, 6, event.c_str(), -1, SQLITE_TRANSIENT);
  const int rc = sqlite3_step(st);
  sqlite3_finalize(st);
  if (rc != SQLITE_DONE) fail(db_->db, "writing " + row.event.identity());
  rows_[{row.event.site, row.event.version}] = row;
}

const LogRow* ReplicationLog::find(const Key& key) const {
  auto it = rows_.find(key);
  return it == rows_.end() ? nullptr : &it->second;
}

std::uint64_t ReplicationLog::max_version(const std::string& site) const {
  std::uint64_t v = 0;
  for (auto it = rows_.lower_bound({site, 0}); it != rows_.end() && it->first.first == site; ++it)
    v = std::max(v, it->first.second);
  return v;
}

std::uint64_t ReplicationLog::max_lamport() const {
  std::uint64_t v = 0;
  for (const auto& [k, row] : rows_) v = std::max(v, row.event.lamport);
  return v;
}

}  // namespace flipper::dds
