#pragma once
/// @file replication_log.hpp
/// The replication log: every lexicon event this site knows (its own and other sites'), keyed
/// by (site, version), with what it became here: the local definition id and rule ids, and a
/// status. Kept in its own table (`dds_replication`) of the lexicon's SQLite file, next to the
/// store's tables but never touching them; ":memory:" stores get an in-memory log.
///
/// status: applying (written before the definition is committed: recovery after a kill),
/// applied, pending (waits for a definition it needs), superseded (lost a cross-site conflict),
/// refused (not allowed, e.g. a deletion from another site than the author's), held (another
/// site's definition waiting for this site's moderator, lexicon.moderation = hold_new), rejected
/// (this site's moderator rejected it; it never serves here).
///
/// Held definitions (docs/ros2.md "Moderation across sites") are kept in a second table,
/// `dds_held`, by the store's held id ("h3"): this site's own (not yet an event: no version,
/// never published; the event it becomes on approval) and other sites' (the log row's key).

#include <cstdint>
#include <map>
#include <memory>
#include <string>
#include <utility>
#include <vector>

#include "flipper/dds/lexicon_event.hpp"

namespace flipper::dds {

struct LogRow {
  LexiconEvent event;
  std::string status;
  std::int64_t definition = 0;           ///< local store id of the definition (define, applied)
  std::vector<std::string> local_rules;  ///< local rule ids induced from it
};

/// A definition held by this site's store (LexiconStore::held) that replication follows.
struct HeldRow {
  std::string held;    ///< the store's held id, "h<N>"
  LexiconEvent event;  ///< own: the event to publish on approval (version 0); other site's: its
                       ///< event (the key of its log row)
  bool own = false;    ///< made at this site
};

class ReplicationLog {
 public:
  using Key = std::pair<std::string, std::uint64_t>;  ///< (site, version)

  explicit ReplicationLog(const std::string& path);
  ~ReplicationLog();
  ReplicationLog(const ReplicationLog&) = delete;
  ReplicationLog& operator=(const ReplicationLog&) = delete;

  /// Inserts or replaces a row (durable on return).
  void put(const LogRow& row);
  const LogRow* find(const Key& key) const;
  const std::map<Key, LogRow>& rows() const { return rows_; }
  std::uint64_t max_version(const std::string& site) const;
  std::uint64_t max_lamport() const;

  /// The held definitions replication follows (by held id), and their changes (durable).
  const std::map<std::string, HeldRow>& held() const { return held_; }
  void put_held(const HeldRow& row);
  void drop_held(const std::string& held);

 private:
  struct Db;
  std::unique_ptr<Db> db_;
  std::map<Key, LogRow> rows_;           // mirror of the table
  std::map<std::string, HeldRow> held_;  // mirror of dds_held
};

}  // namespace flipper::dds
