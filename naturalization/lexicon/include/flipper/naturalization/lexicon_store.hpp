#pragma once
/// @file lexicon_store.hpp
/// The durable lexicon (docs/naturalization.md §5): one SQLite file holding every definition, the
/// rules induced from it (with their deletion history), the rules' use counters and the scorer
/// state. WAL journal with synchronous=FULL: a call that returned has reached the disk, so a
/// definition acknowledged after add_definition() survives a kill at any moment.
///
/// Many writers (processes) share one file: every write is one BEGIN IMMEDIATE transaction that
/// waits for the write lock through a busy handler (jittered retries, bounded by
/// `busy_timeout_ms`); rule ids and `created` are assigned by SQLite inside the defining
/// transaction (never by a process's memory, never by INSERT OR REPLACE); a delete checks the
/// author in its own transaction; changes_since() lets each process pick up what the others
/// committed, incrementally (new rules by `created`, deletions by `deleted_seq`).
/// Not thread-safe: one owner (the naturalization façade) serialises calls.

#include <cstdint>
#include <functional>
#include <iosfwd>
#include <memory>
#include <optional>
#include <string>
#include <vector>

#include "flipper/naturalization/config_keys.hpp"
#include "flipper/naturalization/lexicon_history.hpp"

namespace flipper::naturalization {

namespace lexicon_codes {
/// Not a Flipper lexicon (foreign tables, newer schema), or another fault of the file.
inline constexpr const char* kBadLexicon = "bad_lexicon";
/// Other writers held the store longer than the busy timeout; nothing changed, retry.
inline constexpr const char* kBusy = "lexicon_busy";
/// No space left on the device (or the store's page limit); nothing changed.
inline constexpr const char* kFull = "lexicon_full";
/// The file or its file system is read-only; nothing changed.
inline constexpr const char* kReadOnly = "lexicon_read_only";
/// Not an SQLite database, or damaged; the file is left untouched.
inline constexpr const char* kCorrupt = "lexicon_corrupt";
/// Whether `code` is one of the store's fault codes above.
bool is_store_fault(const std::string& code);
}  // namespace lexicon_codes

/// How a store is opened.
struct LexiconStoreOptions {
  /// lexicon.busy_timeout_ms: longest wait for other writers
  int busy_timeout_ms = static_cast<int>(keys::kBusyTimeoutMs.def);
  /// SQLite's max_page_count (0: SQLite's default): caps the file size. Tests use it to make a
  /// store "full" without a full device.
  std::int64_t max_page_count = 0;
  /// Runs SQLite's quick_check (every page read) while opening. The naturalizer turns it off and
  /// calls verify() itself when it cannot start from a valid rule snapshot (docs/naturalization.md
  /// §5 "Start-up at scale").
  bool check_on_open = true;
  /// lexicon.durability (docs/naturalization.md §5 "Durability"): true (`full`) syncs the WAL in
  /// every COMMIT (SQLite synchronous=FULL), so an answered accept/define survives a power loss;
  /// false (`normal`, synchronous=NORMAL) syncs it only at checkpoints: every commit survives any
  /// crash of the process, a power loss may drop the last ones.
  bool sync_every_commit = true;
  /// lexicon.group_commit (docs/naturalization.md §5 "Group commit"), with sync_every_commit: the
  /// connections of this process on this file share their WAL syncs. A COMMIT writes its frames
  /// (synchronous=NORMAL) and the call returns once one fdatasync started after it has returned
  /// (one sync for every commit made while the previous one ran).
  bool group_commit = true;
  /// lexicon.site: recorded in every history entry this process writes.
  std::string site{};
};

/// One definition as the user gave it.
struct StoredDefinition {
  std::int64_t id = 0;  ///< assigned by the store
  std::string head;
  std::vector<std::string> body;
  std::string author;
  std::int64_t time = 0;  ///< seconds since the epoch
  /// Set when the stored row does not decode (its body is not a JSON list of strings): the body
  /// is then empty and this says why (docs/naturalization.md §5 "Quarantine").
  std::string decode_error{};
  /// The study the definition was made in (when the front end knows it): kept in the history.
  std::string study{};
  /// The history action of the definition (empty: `define`; e.g. `import`, `preload`).
  std::string via{};
};

/// One induced rule with its provenance; `semantics` is the template's canonical text.
struct StoredRule {
  std::string id;
  std::string lhs;
  std::vector<std::string> rhs;  ///< tokens and "$Category" symbols
  std::string semantics;
  std::string author;
  std::string head;
  std::vector<std::string> body;
  std::string how;           ///< "simple" | "best" | "alignment" | "rewriting"
  std::int64_t created = 0;  ///< creation sequence number, unique and increasing (store-assigned)
  std::int64_t definition = 0;
  bool deleted = false;
  std::int64_t deleted_at = 0;
  std::uint64_t uses_by_author = 0;
  std::uint64_t uses_by_others = 0;
  /// Set when the stored row does not decode (rhs or body is not a JSON list of strings): the
  /// list is then empty and this says why. Such a rule is quarantined, never served, and never
  /// stops the store from opening (docs/naturalization.md §5 "Quarantine").
  std::string decode_error{};
};

/// A 64-bit checksum (16 hex digits) of live rules' content in their order — category,
/// right-hand side, template, author; not ids or times — the same for two stores serving the same
/// rules (not cryptographic).
std::string lexicon_checksum(const std::vector<StoredRule>& live);

/// An incremental scorer's weight (or a change to it): sdk::WeightChange without the SDK type.
struct StoredWeightChange {
  std::string model;
  std::string feature;
  double weight = 0;
  double aux = 0;
};

/// Where a reader is in the store's history: the newest `created` and deletion sequence seen.
struct ChangeMark {
  std::int64_t created = 0;
  std::int64_t deleted = 0;
};

/// What was committed after a mark: new live rules (creation order) and ids deleted since.
struct LexiconChanges {
  std::vector<StoredRule> added;
  std::vector<std::string> deleted;
  ChangeMark mark;  ///< the store's position after these changes
};

/// Where a full read of the live rules ended: the mark, and how many rule rows (deleted included)
/// the store held then (a snapshot taken at that mark is only valid while no row appears below it).
struct LiveRulesRead {
  ChangeMark mark;
  std::int64_t rows = 0;
};

/// A stored rule snapshot (rule_snapshot.hpp) that passed its checks against the store.
struct StoredSnapshot {
  ChangeMark mark;           ///< the rules it holds: every live rule at this mark
  std::int64_t rules = 0;    ///< how many
  std::int64_t changed = 0;  ///< rule rows created or deleted after the mark
  std::string data;          ///< the encoded rules
};

/// Why load_snapshot() gave nothing.
enum class SnapshotMiss { none, absent, other_format, damaged, inconsistent };

/// A definition of a `lexicon.preload` file that did not load at a start (docs/naturalization.md
/// §5): kept in the store, so `flipper lexicon list` and `export` show it.
struct PreloadFailure {
  std::string file;       ///< the preload file, as the config resolved it
  std::int64_t line = 0;  ///< its line in the file (1-based)
  std::string head;
  std::string author;
  std::string code;       ///< why: the error code (head_is_core, body_unparsable, ...)
  std::string message;    ///< and its message
  std::int64_t time = 0;  ///< the start that met it (seconds since the epoch)
};

/// A committed definition: its id and its rules as stored (ids, `created` assigned).
struct DefinitionCommit {
  std::int64_t definition = 0;
  std::vector<StoredRule> rules;
};

enum class DeleteStatus { deleted, not_found, forbidden };
struct DeleteResult {
  DeleteStatus status = DeleteStatus::not_found;
  std::string author;  ///< the rule's author (empty when not found)
};

/// Use counters of one rule, for batched updates after an accept.
struct RuleUses {
  std::string rule;
  std::uint64_t by_author = 0;
  std::uint64_t by_others = 0;
};

/// What accepts committed after a learning mark (any process; docs/naturalization.md §5): the
/// use counters that changed, as their totals, and the weight keys whose weights changed.
struct LearnedChanges {
  std::vector<RuleUses> uses;
  std::vector<std::string> weight_keys;
  std::int64_t mark = 0;  ///< the newest learning sequence read (the argument when none)
};

/// A definition held for moderation (lexicon.moderation = hold_new; docs/naturalization.md §5
/// "Moderation"): stored apart from the rules, so it serves no one until it is approved.
struct HeldDefinition {
  std::string id;  ///< "h<N>", never reused
  StoredDefinition definition;
  std::vector<StoredRule> rules;  ///< as induced when held (no ids yet)
};

/// Group commit's counters for the store file at `path` in this process (zeros when no
/// connection on it commits in groups): writes that waited for a shared sync, and the syncs.
struct GroupCommitStats {
  std::uint64_t writes = 0;
  std::uint64_t syncs = 0;
};
GroupCommitStats group_commit_stats(const std::string& path);

class LexiconStore {
 public:
  /// Opens (or creates, with parent directories) the store at `path`; ":memory:" is a private
  /// in-memory store. A corrupt file throws Error(lexicon_corrupt), a foreign one bad_lexicon,
  /// naming the file, which is left untouched. A store that already holds a lexicon but cannot
  /// be written — a read-only file, folder or file system, or a full device — opens degraded:
  /// reads work, every write throws write_refusal() (lexicon_read_only or lexicon_full).
  explicit LexiconStore(const std::string& path, const LexiconStoreOptions& options = {});
  ~LexiconStore();
  LexiconStore(const LexiconStore&) = delete;
  LexiconStore& operator=(const LexiconStore&) = delete;

  const std::string& path() const;
  /// 2: rules.deleted_seq (deletions in commit order, for changes_since). Version 1 files are
  /// upgraded in place on open.
  /// 5: the history (lexicon_history, lexicon_tags); older files get it on open, their rules
  /// each a synthesized `import` entry (docs/naturalization.md §5 "History and governance").
  static constexpr int kSchemaVersion = 5;
  bool read_only() const;
  /// The code every write is refused with when the store opened degraded (lexicon_read_only,
  /// lexicon_full); null when it opened for writing.
  const char* write_refusal() const;

  /// Commits a definition and its rules in ONE transaction (durable on return). The store
  /// assigns the definition id and each rule's `created` (one past the largest ever stored) and
  /// id ("r<created>") inside that transaction; ids and `created` given by the caller are
  /// ignored. Never replaces a stored row.
  DefinitionCommit commit_definition(const StoredDefinition& definition,
                                     std::vector<StoredRule> rules);
  /// commit_definition() returning only the definition id.
  std::int64_t add_definition(const StoredDefinition& definition,
                              const std::vector<StoredRule>& rules);
  /// Every definition, in commit order.
  std::vector<StoredDefinition> definitions() const;
  /// Rules in creation order; deleted ones only when asked.
  std::vector<StoredRule> rules(bool include_deleted = false) const;
  std::optional<StoredRule> rule(const std::string& id) const;
  /// Largest `created` ever stored (0 when empty); new rules continue after it.
  std::int64_t max_created() const;
  /// Flags a rule deleted (history kept) whoever wrote it. False when unknown or already deleted.
  bool mark_deleted(const std::string& id, std::int64_t time);
  /// Deletes a rule for `user`, checking in the same transaction that it exists, is live and is
  /// theirs: another user's rule is `forbidden` when `visible_to_user(author)`, else
  /// `not_found` (a hidden rule does not reveal its owner).
  DeleteResult delete_rule(const std::string& id, const std::string& user, std::int64_t time,
                           const std::function<bool(const std::string& author)>& visible_to_user);

  /// Every live rule in creation order, handed to `each` as it is read (one read transaction);
  /// use counters are left zero (see nonzero_uses()).
  LiveRulesRead read_live_rules(const std::function<void(StoredRule&&)>& each) const;
  /// The use counters that are not zero (one scan of the counters table).
  std::vector<RuleUses> nonzero_uses() const;
  /// SQLite's quick_check; throws lexicon_corrupt naming the file when it fails.
  void verify();

  /// The stored rule snapshot, when it exists, has this build's format, matches its checksum and
  /// fits the store (no rule row appeared below its mark, the mark is not past the store's).
  /// Otherwise nullopt, with the reason in `miss`.
  std::optional<StoredSnapshot> load_snapshot(SnapshotMiss* miss = nullptr) const;
  /// Stores a snapshot of `rules` live rules at `read` (best effort: a cache). Never waits long for
  /// the write lock and never replaces a snapshot with a newer mark; false when it did not store
  /// (busy, read-only, full, in-memory store).
  bool save_snapshot(const LiveRulesRead& read, std::int64_t rules, const std::string& data);

  /// Rules added and deleted after `since` (any process), read in one snapshot.
  LexiconChanges changes_since(const ChangeMark& since) const;
  /// True when another connection committed since the previous call (PRAGMA data_version; a
  /// cheap check before changes_since). The first call is true. While the WAL index's header is
  /// the one seen at the last pragma, nothing was committed and it answers false without asking
  /// SQLite (docs/naturalization.md §5).
  bool changed_elsewhere();
  /// How many times changed_elsewhere() asked SQLite (tests, benchmarks).
  std::uint64_t data_version_reads() const;
  /// Counters and weight keys changed after learning mark `since` (0: everything ever learned),
  /// read in one snapshot. Marks only grow; a store without the sequence (read-only, schema 2 or
  /// 3) has nothing new.
  LearnedChanges learned_since(std::int64_t since) const;
  /// The newest learning sequence stored (0 when none, or without the sequence).
  std::int64_t learned_mark() const;

  /// Persists an accept in one transaction: adds `deltas` to the used rules' counters and, when
  /// `weights_key` is set, stores the scorer state (last writer wins). Returns the counters'
  /// totals after the commit (other processes' uses included), in the order of `deltas`.
  std::vector<RuleUses> record_accept(const std::vector<RuleUses>& deltas,
                                      const std::string& weights_key,
                                      const std::string& weights_state);
  /// The same for an incremental scorer: adds `changes` to the stored weights under
  /// `weights_key` (sums, so two processes learning at once both count), in the same transaction.
  /// `sums` (when given) gets each changed weight's stored sum before and after, in the order of
  /// `changes`.
  struct WeightSums {
    std::vector<StoredWeightChange> before, after;
  };
  std::vector<RuleUses> record_accept(const std::vector<RuleUses>& deltas,
                                      const std::string& weights_key,
                                      const std::vector<StoredWeightChange>& changes,
                                      WeightSums* sums = nullptr);
  /// Every stored weight under `key` (the sums of all changes recorded).
  std::vector<StoredWeightChange> weight_changes(const std::string& key) const;
  void save_weights(const std::string& key, const std::string& state);
  std::optional<std::string> load_weights(const std::string& key) const;
  /// Older builds' per-user weights (lexicon.weights = per_user stored each user's under
  /// "user:NAME"): how many such keys the store holds (weight rows and saved states).
  std::size_t legacy_user_weight_keys() const;
  /// Converts the whole state saved under `key` to weights (partition, feature, weight, aux),
  /// nullopt when it is not a state the caller can read. The store does not read states: their
  /// format is the scorer's (the naturalizer asks it, sdk::StateWeights).
  using StateWeights = std::function<std::optional<std::vector<StoredWeightChange>>(
      const std::string& key, const std::string& state)>;
  /// Folds every "user:NAME" key into `key`, partition NAME (docs/naturalization.md §5 "Learned
  /// state"), in one transaction: a saved state first (read by `state_weights`; its partition
  /// "" becomes NAME), then the key's weight rows (partition "" becomes NAME), each added to the
  /// row of `key` (so a weight is exactly what the old build loaded: state + sum of changes).
  /// Returns the state keys `state_weights` could not read: they stay (and their user's rows
  /// with them, so nothing is served half).
  std::vector<std::string> fold_user_weights(const std::string& key,
                                             const StateWeights& state_weights);

  /// Replaces the recorded failures of preload file `file` with `failures`, in one transaction.
  /// Best effort (a report, not the lexicon): false when it did not store (read-only, full or
  /// busy store). Writes nothing when there is nothing to record or to clear.
  bool record_preload_failures(const std::string& file,
                               const std::vector<PreloadFailure>& failures);
  /// The recorded preload failures (file, then line order).
  std::vector<PreloadFailure> preload_failures() const;

  /// JSON Lines: one object per line, `{"type":"definition"|"rule"|"weights"|"weight"|
  /// "preload_failure", ...}`. A rule for which `quarantine_reason` returns a reason gets
  /// `"quarantined": reason`, and so does a definition whose row does not decode.
  void export_jsonl(std::ostream& out,
                    const std::function<std::optional<std::string>(const StoredRule&)>&
                        quarantine_reason = {}) const;
  /// Imports an export verbatim (one transaction, keeping ids and `created`). A definition or
  /// rule id already stored is refused (bad_request), never replaced. Returns lines imported.
  std::size_t import_jsonl(std::istream& in);

  // ---- History and governance (lexicon_history.hpp; docs/naturalization.md §5) ----
  /// Whether the store keeps a history (false only for a read-only store older than schema 5;
  /// the calls below then throw lexicon_read_only).
  bool has_history() const;
  /// Entries in commit order, filtered.
  std::vector<HistoryEntry> history(const HistoryFilter& filter = {}) const;
  /// The last entry's seq (0: none).
  std::int64_t history_head() const;
  /// The last entry made at or before `time` (seconds since the epoch; 0: none).
  std::int64_t history_at_time(std::int64_t time) const;
  /// The rules live right after entry `seq`, in creation order (0: none).
  std::vector<StoredRule> rules_at(std::int64_t seq) const;
  std::vector<LexiconTag> tags() const;
  std::optional<LexiconTag> find_tag(const std::string& name) const;
  /// Names the current head of the history (refuses a taken or malformed name: bad_request).
  LexiconTag tag(const std::string& name, const std::string& author, std::int64_t time);
  /// Makes the live rules equal those right after entry `seq`, in one transaction: the live rules
  /// after the longest prefix (creation order) the two sets share are deleted, the target's rules
  /// after it re-created (verbatim copies with new ids, in their order, counters copied), each an
  /// entry `revert` by `who`. Nothing is erased.
  RevertOutcome revert_to(std::int64_t seq, const HistoryContext& who, std::int64_t time);
  /// Records that `rule` is quarantined for `reason` (once per rule and reason; best effort:
  /// false when it did not write).
  bool record_quarantine(const StoredRule& rule, const std::string& reason);

  // ---- Moderation (docs/naturalization.md §5 "Moderation"; moderation.cpp) ----
  /// Holds a definition and its rules for a researcher, with a `hold` history entry, in one
  /// transaction; returns its id ("h<N>").
  std::string hold_definition(const StoredDefinition& definition,
                              const std::vector<StoredRule>& rules);
  /// The held definitions, oldest first.
  std::vector<HeldDefinition> held() const;
  /// Stores held definition `id` as if defined now (its `define` and `induce` entries, by its
  /// author) and records an `approve` entry by `moderator`, in one transaction. Throws not_found
  /// for an id that is not held (approved, rejected or unknown).
  DefinitionCommit approve_held(const std::string& id, const HistoryContext& moderator,
                                std::int64_t time);
  /// Drops held definition `id` with a `reject` entry by `moderator` (not_found as above).
  HeldDefinition reject_held(const std::string& id, const HistoryContext& moderator,
                             std::int64_t time);

 private:
  struct Impl;
  std::unique_ptr<Impl> impl_;
};

}  // namespace flipper::naturalization
