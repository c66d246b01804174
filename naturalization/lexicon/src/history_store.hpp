#pragma once
// What the store's files share to keep the history (history.cpp) in step with every change
// (lexicon_store.cpp): an entry is appended inside the transaction of the change it records.
#include <cstdint>
#include <string>
#include <vector>

#include "flipper/naturalization/lexicon_history.hpp"
#include "flipper/naturalization/lexicon_store.hpp"
#include "sqlite_handle.hpp"

namespace flipper::naturalization {

/// The rule columns read_history_rule() reads: "SELECT ... FROM rules r LEFT JOIN rule_uses u ".
extern const char* const kRuleSelectForHistory;
StoredRule read_history_rule(const sqlite::Stmt& s);
/// Flags `id` deleted with the next deletion sequence number (inside the caller's transaction).
void flag_rule_deleted(sqlite::Db& db, const std::string& id, std::int64_t time);
/// Whether the store has its history table (schema 5; a read-only older store has none).
bool has_history_table(sqlite::Db& db);
/// Appends `e` (its seq assigned by SQLite, its time raised to the last entry's when earlier),
/// inside the caller's write transaction.
void append_history(sqlite::Db& db, const HistoryEntry& e);
/// Stores a definition and its rules (ids and `created` assigned), with their history entries,
/// inside the caller's write transaction (LexiconStore::commit_definition, an approval).
DefinitionCommit commit_definition_in(sqlite::Db& db, const std::string& site,
                                      const StoredDefinition& d, std::vector<StoredRule> rules);

}  // namespace flipper::naturalization
