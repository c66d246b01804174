// Folding an older store's per-user weight keys into the one weights key (docs/naturalization.md
// §5 "Learned state"): lexicon.weights = per_user used to keep each user's weights under
// "user:NAME", the scorer swapped per user; the scorer now keeps a partition per user itself, so
// NAME's weights become partition NAME of the one key. No schema change: the rows move.
#include "flipper/naturalization/lexicon_store.hpp"
#include "sqlite_handle.hpp"
#include "store_impl.hpp"

namespace flipper::naturalization {

namespace {

constexpr std::string_view kUserPrefix = "user:";

bool has_weight_tables(sqlite::Db& db) {
  sqlite::Stmt s(db,
                 "SELECT count(*) FROM sqlite_master WHERE type = 'table' AND name IN "
                 "('scorer_weights', 'scorer_state')");
  s.step();
  return s.int64(0) == 2;
}

// The legacy keys, each once, in order: a range of the primary keys ("user;" follows every
// "user:..."), so a store without any costs two index seeks at start-up.
std::vector<std::string> legacy_keys(sqlite::Db& db) {
  std::vector<std::string> keys;
  if (!has_weight_tables(db)) return keys;
  sqlite::Stmt s(
      db,
      "SELECT key FROM scorer_weights WHERE key >= 'user:' AND key < 'user;' UNION "
      "SELECT key FROM scorer_state WHERE key >= 'user:' AND key < 'user;' ORDER BY key");
  while (s.step()) keys.push_back(s.text(0));
  return keys;
}

// The partition a legacy row lands in: the scorer's own one when it had per-user partitions
// already, else the user of the key.
std::string partition_of(const std::string& model, const std::string& user) {
  return model.empty() ? user : model;
}

}  // namespace

std::size_t LexiconStore::legacy_user_weight_keys() const {
  return legacy_keys(*impl_->db).size();
}

std::vector<std::string> LexiconStore::fold_user_weights(const std::string& key,
                                                         const StateWeights& state_weights) {
  auto& db = *impl_->db;
  std::vector<std::string> kept;
  sqlite::Transaction tx(db);
  const std::vector<std::string> keys = legacy_keys(db);
  if (keys.empty()) return kept;
  sqlite::Stmt seq_of(db,
                      "SELECT max((SELECT coalesce(max(seq), 0) FROM rule_uses), "
                      "(SELECT coalesce(max(seq), 0) FROM scorer_weights), "
                      "(SELECT coalesce(max(seq), 0) FROM scorer_state)) + 1");
  seq_of.step();
  const std::int64_t seq = seq_of.int64(0);
  sqlite::Stmt add(db,
                   "INSERT INTO scorer_weights(key, model, feature, weight, aux, seq) "
                   "VALUES (?,?,?,?,?,?) ON CONFLICT(key, model, feature) DO UPDATE SET "
                   "weight = weight + excluded.weight, aux = aux + excluded.aux, "
                   "seq = excluded.seq");
  const auto add_row = [&](const std::string& model, const std::string& feature, double weight,
                           double aux) {
    add.bind(1, key).bind(2, model).bind(3, feature).bind_real(4, weight).bind_real(5, aux);
    add.bind(6, seq).run();
    add.reset();
  };
  for (const auto& legacy : keys) {
    const std::string user = legacy.substr(kUserPrefix.size());
    if (auto state = load_weights(legacy)) {
      auto weights = state_weights ? state_weights(legacy, *state) : std::nullopt;
      if (!weights) {
        kept.push_back(legacy);
        continue;
      }
      for (const auto& w : *weights)
        add_row(partition_of(w.model, user), w.feature, w.weight, w.aux);
      sqlite::Stmt drop(db, "DELETE FROM scorer_state WHERE key = ?");
      drop.bind(1, legacy).run();
    }
    for (const auto& w : weight_changes(legacy))
      add_row(partition_of(w.model, user), w.feature, w.weight, w.aux);
    sqlite::Stmt drop(db, "DELETE FROM scorer_weights WHERE key = ?");
    drop.bind(1, legacy).run();
  }
  tx.commit();
  return kept;
}

}  // namespace flipper::naturalization
