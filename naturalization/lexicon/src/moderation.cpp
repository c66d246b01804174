// Moderation of a shared lexicon (docs/naturalization.md §5 "Moderation"): under
// lexicon.moderation = hold_new a definition's rules wait in a table of their own (created with
// the first hold, no schema change; older builds ignore it) and serve no one until a researcher
// approves them, which stores them as a definition made then. Holding, approving and rejecting
// are history entries, written in the transaction of the change.
#include <nlohmann/json.hpp>

#include "flipper/naturalization/lexicon_history.hpp"
#include "flipper/naturalization/lexicon_store.hpp"
#include "flipper/sdk/errors.hpp"
#include "history_store.hpp"
#include "sqlite_handle.hpp"
#include "store_impl.hpp"

namespace flipper::naturalization {
using nlohmann::json;

namespace {

// AUTOINCREMENT: an id once given is never given again (a rejected h3 stays h3 in the history).
constexpr const char* kCreateHeld =
    "CREATE TABLE IF NOT EXISTS lexicon_held("
    "id INTEGER PRIMARY KEY AUTOINCREMENT, time INTEGER NOT NULL, author TEXT NOT NULL, "
    "head TEXT NOT NULL, body TEXT NOT NULL, study TEXT NOT NULL, via TEXT NOT NULL, "
    "rules TEXT NOT NULL)";

bool has_held_table(sqlite::Db& db) {
  sqlite::Stmt s(db, "SELECT 1 FROM sqlite_master WHERE type='table' AND name='lexicon_held'");
  return s.step();
}

json rules_json(const std::vector<StoredRule>& rules) {
  json out = json::array();
  for (const auto& r : rules)
    out.push_back({{"lhs", r.lhs}, {"rhs", r.rhs}, {"template", r.semantics}, {"how", r.how}});
  return out;
}

std::vector<std::string> strings(const json& j) {
  std::vector<std::string> out;
  if (j.is_array())
    for (const auto& s : j)
      if (s.is_string()) out.push_back(s.get<std::string>());
  return out;
}

constexpr const char* kHeldSelect =
    "SELECT id, time, author, head, body, study, via, rules FROM lexicon_held ";

HeldDefinition read_held(const sqlite::Stmt& s) {
  HeldDefinition h;
  h.id = "h" + std::to_string(s.int64(0));
  StoredDefinition& d = h.definition;
  d.time = s.int64(1);
  d.author = s.text(2);
  d.head = s.text(3);
  d.body = strings(json::parse(s.text(4), nullptr, false));
  d.study = s.text(5);
  d.via = s.text(6);
  const json rules = json::parse(s.text(7), nullptr, false);
  if (rules.is_array())
    for (const auto& r : rules) {
      if (!r.is_object()) continue;
      StoredRule rule;
      rule.lhs = r.value("lhs", std::string());
      rule.rhs = strings(r.value("rhs", json::array()));
      rule.semantics = r.value("template", std::string());
      rule.how = r.value("how", std::string());
      rule.author = d.author;
      rule.head = d.head;
      rule.body = d.body;
      h.rules.push_back(std::move(rule));
    }
  return h;
}

/// The row number of "h<N>", or 0 when `id` is not of that form.
std::int64_t held_number(const std::string& id) {
  if (id.size() < 2 || id.size() > 19 || id[0] != 'h') return 0;
  std::int64_t n = 0;
  for (std::size_t i = 1; i < id.size(); ++i) {
    if (id[i] < '0' || id[i] > '9') return 0;
    n = n * 10 + (id[i] - '0');
  }
  return n;
}

/// Reads held definition `id` under the caller's write transaction and removes its row.
HeldDefinition take_held(sqlite::Db& db, const std::string& id) {
  const std::int64_t n = held_number(id);
  if (n > 0 && has_held_table(db)) {
    std::optional<HeldDefinition> found;
    {
      sqlite::Stmt s(db, (std::string(kHeldSelect) + "WHERE id = ?").c_str());
      if (s.bind(1, n).step()) found = read_held(s);
    }
    if (found) {
      sqlite::Stmt del(db, "DELETE FROM lexicon_held WHERE id = ?");
      del.bind(1, n).run();
      return *found;
    }
  }
  throw sdk::Error("not_found", "no held definition '" + id.substr(0, 40) +
                                    "' (approved, rejected, or never held: flipper lexicon "
                                    "pending lists them)");
}

HistoryEntry moderation_entry(const HeldDefinition& h, const char* action,
                              const std::string& author, const std::string& study,
                              std::int64_t time, const std::string& site) {
  HistoryEntry e;
  e.time = time;
  e.author = author;
  e.action = action;
  e.effect = history_effect::kNone;
  e.head = h.definition.head;
  e.body = h.definition.body;
  e.study = study;
  e.site = site;
  e.note = h.id;
  return e;
}

}  // namespace

std::string LexiconStore::hold_definition(const StoredDefinition& d,
                                          const std::vector<StoredRule>& rules) {
  auto& db = *impl_->db;
  sqlite::Transaction tx(db);
  db.exec(kCreateHeld);
  sqlite::Stmt ins(db,
                   "INSERT INTO lexicon_held(time, author, head, body, study, via, rules) "
                   "VALUES (?,?,?,?,?,?,?)");
  ins.bind(1, d.time).bind(2, d.author).bind(3, d.head).bind(4, json(d.body).dump());
  ins.bind(5, d.study).bind(6, d.via).bind(7, rules_json(rules).dump()).run();
  HeldDefinition h;
  h.id = "h" + std::to_string(sqlite3_last_insert_rowid(db.raw()));
  h.definition = d;
  HistoryEntry e =
      moderation_entry(h, history_action::kHold, d.author, d.study, d.time, impl_->site);
  append_history(db, e);
  tx.commit();
  return h.id;
}

std::vector<HeldDefinition> LexiconStore::held() const {
  auto& db = *impl_->db;
  std::vector<HeldDefinition> out;
  if (!has_held_table(db)) return out;
  sqlite::Stmt s(db, (std::string(kHeldSelect) + "ORDER BY id").c_str());
  while (s.step()) out.push_back(read_held(s));
  return out;
}

DefinitionCommit LexiconStore::approve_held(const std::string& id, const HistoryContext& moderator,
                                            std::int64_t time) {
  auto& db = *impl_->db;
  sqlite::Transaction tx(db);
  HeldDefinition h = take_held(db, id);
  append_history(db, moderation_entry(h, history_action::kApprove, moderator.author,
                                      h.definition.study, time, impl_->site));
  StoredDefinition d = h.definition;
  d.time = time;  // it counts from now: its rules come after every rule made while it waited
  DefinitionCommit out = commit_definition_in(db, impl_->site, d, std::move(h.rules));
  tx.commit();
  return out;
}

HeldDefinition LexiconStore::reject_held(const std::string& id, const HistoryContext& moderator,
                                         std::int64_t time) {
  auto& db = *impl_->db;
  sqlite::Transaction tx(db);
  HeldDefinition h = take_held(db, id);
  HistoryEntry e = moderation_entry(h, history_action::kReject, moderator.author,
                                    h.definition.study, time, impl_->site);
  if (!moderator.note.empty()) e.note += ": " + moderator.note;
  append_history(db, e);
  tx.commit();
  return h;
}

}  // namespace flipper::naturalization
