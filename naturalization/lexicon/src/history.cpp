// The lexicon's history, tags and reverts (docs/naturalization.md §5 "History and governance").
// Entries are appended inside the transaction of the change they record (history_store.hpp), so
// the live rules at any point of the history are the rules its `add` entries made live minus
// those its `remove` entries took out.
#include <algorithm>
#include <cctype>
#include <ctime>
#include <functional>
#include <nlohmann/json.hpp>

#include "flipper/naturalization/lexicon_history.hpp"
#include "flipper/naturalization/lexicon_store.hpp"
#include "flipper/naturalization/rule_snapshot.hpp"
#include "flipper/sdk/errors.hpp"
#include "history_store.hpp"
#include "sqlite_handle.hpp"
#include "store_impl.hpp"

namespace flipper::naturalization {
using nlohmann::json;

bool valid_tag_name(const std::string& name) {
  constexpr std::size_t kMaxTag = 64;
  if (name.empty() || name.size() > kMaxTag ||
      std::isalpha(static_cast<unsigned char>(name[0])) == 0)
    return false;
  return std::all_of(name.begin(), name.end(), [](char c) {
    return std::isalnum(static_cast<unsigned char>(c)) != 0 || c == '.' || c == '_' || c == '-';
  });
}

bool has_history_table(sqlite::Db& db) {
  sqlite::Stmt s(db, "SELECT 1 FROM sqlite_master WHERE type='table' AND name='lexicon_history'");
  return s.step();
}

void append_history(sqlite::Db& db, const HistoryEntry& e) {
  // Times never go backwards along `seq`, so "the history at time T" is a prefix of it.
  std::int64_t time = e.time;
  {
    sqlite::Stmt last(db, "SELECT time FROM lexicon_history ORDER BY seq DESC LIMIT 1");
    if (last.step()) time = std::max(time, last.int64(0));
  }
  sqlite::Stmt ins(db,
                   "INSERT INTO lexicon_history(time, author, action, effect, rule, source_rule, "
                   "definition, head, body, study, site, note) VALUES (?,?,?,?,?,?,?,?,?,?,?,?)");
  ins.bind(1, time).bind(2, e.author).bind(3, e.action).bind(4, e.effect);
  if (e.rule.empty())
    ins.bind_null(5);
  else
    ins.bind(5, e.rule);
  if (e.source_rule.empty())
    ins.bind_null(6);
  else
    ins.bind(6, e.source_rule);
  if (e.definition == 0)
    ins.bind_null(7);
  else
    ins.bind(7, e.definition);
  ins.bind(8, e.head).bind(9, json(e.body).dump()).bind(10, e.study).bind(11, e.site);
  ins.bind(12, e.note).run();
}

namespace {

constexpr const char* kEntrySelect =
    "SELECT seq, time, author, action, effect, coalesce(rule, ''), coalesce(source_rule, ''), "
    "coalesce(definition, 0), head, body, study, site, note FROM lexicon_history ";

HistoryEntry read_entry(const sqlite::Stmt& s) {
  HistoryEntry e;
  e.seq = s.int64(0);
  e.time = s.int64(1);
  e.author = s.text(2);
  e.action = s.text(3);
  e.effect = s.text(4);
  e.rule = s.text(5);
  e.source_rule = s.text(6);
  e.definition = s.int64(7);
  e.head = s.text(8);
  const json body = json::parse(s.text(9), nullptr, false);
  if (body.is_array())
    for (const auto& line : body)
      if (line.is_string()) e.body.push_back(line.get<std::string>());
  e.study = s.text(10);
  e.site = s.text(11);
  e.note = s.text(12);
  return e;
}

std::int64_t last_seq(sqlite::Db& db) {
  sqlite::Stmt s(db, "SELECT coalesce(max(seq), 0) FROM lexicon_history");
  s.step();
  return s.int64(0);
}

void require_history(sqlite::Db& db) {
  if (!has_history_table(db))
    throw sdk::Error(lexicon_codes::kReadOnly,
                     "lexicon store '" + db.path() +
                         "' has no history yet (schema version before 5, opened read-only); open "
                         "it writable once to upgrade it");
}

/// The rules live after entry `seq` (creation order), read inside the caller's transaction.
std::vector<StoredRule> live_at(sqlite::Db& db, std::int64_t seq,
                                const std::function<StoredRule(const sqlite::Stmt&)>& read) {
  const std::string sql =
      std::string(kRuleSelectForHistory) +
      "WHERE r.id IN (SELECT rule FROM lexicon_history WHERE seq <= ?1 AND effect = 'add') "
      "AND r.id NOT IN (SELECT rule FROM lexicon_history WHERE seq <= ?1 AND effect = 'remove' "
      "AND rule IS NOT NULL) ORDER BY r.created";
  sqlite::Stmt s(db, sql.c_str());
  s.bind(1, seq);
  std::vector<StoredRule> out;
  while (s.step()) out.push_back(read(s));
  return out;
}

/// The same rule, or a copy of it (a revert's): everything but id, `created` and counters.
bool same_content(const StoredRule& a, const StoredRule& b) {
  return a.lhs == b.lhs && a.rhs == b.rhs && a.semantics == b.semantics && a.author == b.author &&
         a.how == b.how && a.head == b.head && a.body == b.body && a.definition == b.definition &&
         a.decode_error == b.decode_error;
}

// One entry of a revert (docs/naturalization.md §5 "History"): `rule` removed or added, as `from`
// was written; an added copy names the rule it restores.
HistoryEntry revert_entry(std::int64_t time, const HistoryContext& who, const std::string& site,
                          const char* effect, const std::string& rule, const StoredRule& from) {
  HistoryEntry e;
  e.time = time;
  e.author = who.author;
  e.action = history_action::kRevert;
  e.effect = effect;
  e.rule = rule;
  if (rule != from.id) e.source_rule = from.id;
  e.definition = from.definition;
  e.head = from.head;
  e.body = from.body;
  e.study = who.study;
  e.site = site;
  e.note = who.note;
  return e;
}

}  // namespace

std::string lexicon_checksum(const std::vector<StoredRule>& live) {
  // What decides parses: each rule's category, right-hand side, template and author, in creation
  // order (docs/naturalization.md §2 "Order"); ids and times do not.
  std::string text;
  for (const auto& r : live) {
    text += r.lhs;
    text += '\x1f';
    for (const auto& s : r.rhs) (text += s) += '\x1e';
    text += '\x1f';
    text += r.semantics;
    text += '\x1f';
    text += r.author;
    text += '\n';
  }
  static constexpr char kHex[] = "0123456789abcdef";
  std::uint64_t sum = snapshot_checksum(text);
  std::string hex(16, '0');
  for (int i = 15; i >= 0; --i, sum >>= 4U) hex[static_cast<std::size_t>(i)] = kHex[sum & 15U];
  return hex;
}

bool LexiconStore::has_history() const {
  return has_history_table(*impl_->db);
}

std::vector<HistoryEntry> LexiconStore::history(const HistoryFilter& filter) const {
  auto& db = *impl_->db;
  require_history(db);
  std::string sql = kEntrySelect;
  sql +=
      "WHERE (?1 IS NULL OR rule = ?1 OR source_rule = ?1) AND (?2 IS NULL OR author = ?2) "
      "ORDER BY seq";
  sqlite::Stmt s(db, sql.c_str());
  if (filter.rule)
    s.bind(1, *filter.rule);
  else
    s.bind_null(1);
  if (filter.author)
    s.bind(2, *filter.author);
  else
    s.bind_null(2);
  std::vector<HistoryEntry> out;
  while (s.step()) out.push_back(read_entry(s));
  return out;
}

std::int64_t LexiconStore::history_head() const {
  auto& db = *impl_->db;
  require_history(db);
  return last_seq(db);
}

std::int64_t LexiconStore::history_at_time(std::int64_t time) const {
  auto& db = *impl_->db;
  require_history(db);
  sqlite::Stmt s(db, "SELECT coalesce(max(seq), 0) FROM lexicon_history WHERE time <= ?");
  s.bind(1, time);
  s.step();
  return s.int64(0);
}

std::vector<StoredRule> LexiconStore::rules_at(std::int64_t seq) const {
  auto& db = *impl_->db;
  require_history(db);
  sqlite::ReadTransaction snapshot(db);
  return live_at(db, seq, read_history_rule);
}

std::vector<LexiconTag> LexiconStore::tags() const {
  auto& db = *impl_->db;
  require_history(db);
  sqlite::Stmt s(db,
                 "SELECT name, seq, time, author, checksum FROM lexicon_tags ORDER BY seq, name");
  std::vector<LexiconTag> out;
  while (s.step()) out.push_back({s.text(0), s.int64(1), s.int64(2), s.text(3), s.text(4)});
  return out;
}

std::optional<LexiconTag> LexiconStore::find_tag(const std::string& name) const {
  for (auto& t : tags())
    if (t.name == name) return t;
  return std::nullopt;
}

LexiconTag LexiconStore::tag(const std::string& name, const std::string& author,
                             std::int64_t time) {
  if (!valid_tag_name(name))
    throw sdk::Error(
        sdk::codes::kBadRequest,
        "tag name '" + name + "': a letter, then letters, digits, '.', '_' or '-' (at most 64)");
  auto& db = *impl_->db;
  require_history(db);
  sqlite::Transaction tx(db);
  {
    sqlite::Stmt taken(db, "SELECT seq FROM lexicon_tags WHERE name = ?");
    if (taken.bind(1, name).step())
      throw sdk::Error(sdk::codes::kBadRequest, "tag '" + name + "' already names entry " +
                                                    std::to_string(taken.int64(0)) +
                                                    "; a tag is never moved, choose another name");
  }
  LexiconTag out{name, last_seq(db), time, author, {}};
  out.checksum = lexicon_checksum(live_at(db, out.seq, read_history_rule));
  sqlite::Stmt ins(
      db, "INSERT INTO lexicon_tags(name, seq, time, author, checksum) VALUES (?,?,?,?,?)");
  ins.bind(1, out.name).bind(2, out.seq).bind(3, out.time).bind(4, out.author);
  ins.bind(5, out.checksum).run();
  tx.commit();
  return out;
}

RevertOutcome LexiconStore::revert_to(std::int64_t seq, const HistoryContext& who,
                                      std::int64_t time) {
  auto& db = *impl_->db;
  require_history(db);
  sqlite::Transaction tx(db);  // the target and the live set are read under the write lock
  if (seq < 0 || seq > last_seq(db))
    throw sdk::Error(sdk::codes::kBadRequest,
                     "no history entry " + std::to_string(seq) + " in '" + db.path() + "'");
  RevertOutcome out;
  out.seq = seq;
  const std::vector<StoredRule> target = live_at(db, seq, read_history_rule);
  std::vector<StoredRule> live;
  {
    const std::string sql =
        std::string(kRuleSelectForHistory) + "WHERE r.deleted = 0 ORDER BY r.created";
    sqlite::Stmt s(db, sql.c_str());
    while (s.step()) live.push_back(read_history_rule(s));
  }
  // Parses depend on the rules' creation order (ties): keep the longest prefix the two share
  // (the same rule, or a copy of it), delete every live rule after it, and re-create the
  // target's rules after it in their order.
  std::size_t keep = 0;
  while (keep < target.size() && keep < live.size() && same_content(target[keep], live[keep]))
    ++keep;
  for (std::size_t i = keep; i < live.size(); ++i) {
    flag_rule_deleted(db, live[i].id, time);
    append_history(
        db, revert_entry(time, who, impl_->site, history_effect::kRemove, live[i].id, live[i]));
    out.removed.push_back(live[i].id);
  }
  std::int64_t created = 0;
  {
    sqlite::Stmt s(db, "SELECT coalesce(max(created), 0) + 1 FROM rules");
    s.step();
    created = s.int64(0);
  }
  for (std::size_t i = keep; i < target.size(); ++i, ++created) {
    const std::string id = "r" + std::to_string(created);
    // A verbatim copy of the row (a row that does not decode stays as it was, and quarantined).
    sqlite::Stmt copy(
        db,
        "INSERT INTO rules(id, created, definition, lhs, rhs, template, author, head, "
        "body, how, deleted) SELECT ?, ?, definition, lhs, rhs, template, author, "
        "head, body, how, 0 FROM rules WHERE id = ?");
    copy.bind(1, id).bind(2, created).bind(3, target[i].id).run();
    sqlite::Stmt uses(db,
                      "INSERT INTO rule_uses(rule, by_author, by_others) SELECT ?, by_author, "
                      "by_others FROM rule_uses WHERE rule = ?");
    uses.bind(1, id).bind(2, target[i].id).run();
    append_history(db, revert_entry(time, who, impl_->site, history_effect::kAdd, id, target[i]));
    out.restored.emplace_back(id, target[i].id);
  }
  tx.commit();
  return out;
}

bool LexiconStore::record_quarantine(const StoredRule& rule, const std::string& reason) {
  auto& db = *impl_->db;
  if (db.write_refusal() != nullptr || db.read_only() || !has_history_table(db)) return false;
  try {
    {
      sqlite::Stmt seen(db,
                        "SELECT 1 FROM lexicon_history WHERE rule = ? AND action = 'quarantine' "
                        "AND note = ?");
      if (seen.bind(1, rule.id).bind(2, reason).step()) return false;
    }
    sqlite::Transaction tx(db);
    {
      sqlite::Stmt seen(db,
                        "SELECT 1 FROM lexicon_history WHERE rule = ? AND action = 'quarantine' "
                        "AND note = ?");
      if (seen.bind(1, rule.id).bind(2, reason).step()) return false;
    }
    HistoryEntry e;
    e.time = static_cast<std::int64_t>(std::time(nullptr));
    e.author = rule.author;
    e.action = history_action::kQuarantine;
    e.effect = history_effect::kNone;
    e.rule = rule.id;
    e.definition = rule.definition;
    e.head = rule.head;
    e.body = rule.body;
    e.site = impl_->site;
    e.note = reason;
    append_history(db, e);
    tx.commit();
    return true;
  } catch (const sdk::Error&) {
    return false;  // a report, not the lexicon: a busy or full store keeps only the warning
  }
}

}  // namespace flipper::naturalization
