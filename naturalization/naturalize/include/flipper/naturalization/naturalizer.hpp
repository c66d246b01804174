#pragma once
/// @file naturalizer.hpp
/// The naturalization façade (docs/naturalization.md §4–§6, session-protocol `define`, `rules`,
/// `delete_rule`): owns the lexicon store and the induced rules, keeps the parser's grammar in
/// step with the store, and decides which rules a user sees (sharing modes).
///
/// Start-up: the store's live rules are re-added to the parser in creation order — from the
/// store's rule snapshot plus the rows changed after it when there is a usable one, else from the
/// rows, leaving a snapshot for the next start (docs/naturalization.md §5 "Start-up at scale") —
/// the scorer's weights restored, then the preload file (if any) replayed through induction
/// (definitions the store already holds are skipped, so a restart does not replay them twice; one
/// that does not load is reported through `warn` and recorded in the store). A stored rule that no
/// longer loads (unknown category, bad template, a row that does not decode) is quarantined: not
/// served, reported through `warn` at every start (from the rows or the snapshot), kept in the
/// file. A store that opened degraded (read-only, full) serves its rules and refuses writes.
/// Every definition is committed to the store in one transaction before define() returns. Many
/// processes may share the store: refresh() (called before every parse, define, listing and delete)
/// picks up the rules and deletions other processes committed, incrementally.

#include <chrono>
#include <cstdint>
#include <functional>
#include <memory>
#include <optional>
#include <string>
#include <string_view>
#include <unordered_map>
#include <vector>

#include "flipper/kernel/runtime.hpp"
#include "flipper/naturalization/config_keys.hpp"
#include "flipper/naturalization/induction.hpp"
#include "flipper/naturalization/lexicon_store.hpp"
#include "flipper/naturalization/preview.hpp"
#include "flipper/naturalization/rule_snapshot.hpp"
#include "flipper/sdk/execution.hpp"
#include "flipper/sdk/world.hpp"

namespace flipper::naturalization {

/// The one key the scorer's learned weights are stored under: a scorer with per-user weights
/// keeps each user's in its own partition (sdk::WeightChange::model), docs/naturalization.md §5.
inline constexpr const char* kWeightsKey = "global";

namespace naturalize_codes {
inline constexpr const char* kForbidden = "forbidden";  ///< deleting another user's rule
inline constexpr const char* kNotFound = "not_found";   ///< unknown (or hidden) rule id
/// A head token starting with '$' (the mark of grammar categories in rules).
inline constexpr const char* kHeadReservedToken = "head_reserved_token";
/// lexicon.conflicts = refuse: the definition would change other users' readings (nothing stored).
inline constexpr const char* kDefinitionConflicts = "definition_conflicts";
}  // namespace naturalize_codes

/// lexicon.conflicts (the enum: config_keys.hpp)
ConflictPolicy parse_conflict_policy(const std::string& text);  ///< throws bad_config

/// A phrase another user relies on that a definition would read differently
/// (docs/naturalization.md §5 "Conflicts").
struct DefineConflict {
  std::string phrase;  ///< a head or body line of one of `user`'s live rules
  std::string user;
  std::string kind;    ///< "first_reading" (another reading comes first) or "new_reading"
  std::string before;  ///< its first reading now (core-language text; empty: none)
  std::string after;   ///< and with the definition's rules
  std::size_t readings_before = 0;
  std::size_t readings_after = 0;
};

/// At most this many phrases are checked per definition (the newest rules' first).
inline constexpr std::size_t kMaxConflictProbes = 256;

/// lexicon.sharing (the enum: config_keys.hpp)
Sharing parse_sharing(const std::string& text);  ///< throws bad_config
const char* to_string(Sharing s);

struct NaturalizeOptions {
  std::string store_path = ":memory:";  ///< lexicon.path
  Sharing sharing = Sharing::shared;    ///< lexicon.sharing
  std::string preload;                  ///< lexicon.preload (JSON Lines; empty: none)
  LexiconStoreOptions store;            ///< lexicon.busy_timeout_ms (+ test-only limits)
  /// Start-up keeps a rule snapshot in the store once it holds this many live rules, and rebuilds
  /// it when more than max(this, an eighth of its rules) rows changed since (docs/naturalization.md
  /// §5 "Start-up at scale"). 0: never use or write one.
  std::int64_t snapshot_min_rules = keys::kSnapshotMinRules.def;  ///< lexicon.snapshot_min_rules
  /// Where warnings go (quarantined rules, preload failures, a store that opened degraded);
  /// default: standard error, "flipper: warning: ...".
  std::function<void(const std::string&)> warn;
  ConflictPolicy conflicts = ConflictPolicy::warn;  ///< lexicon.conflicts
  Moderation moderation = Moderation::off;          ///< lexicon.moderation
  InductionOptions induction;                       ///< induction.alignment (+ parser beam)
  bool generalize = keys::kGeneralize.def;          ///< induction.generalize
  bool induction_sees_everyone = false;             ///< induction.view: everyone
  int perturbed_checks = static_cast<int>(keys::kPerturbedChecks.def);  ///< induction.*
  /// Reads the keys above from a validated config (the schema filled every default).
  static NaturalizeOptions from_config(const kernel::Config& config);
};

/// lexicon.weights = per_user is a short way to write `scorer.params.per_user: true` (the
/// scorer's partition per user is the one switch, docs/naturalization.md §5 "Learned state"):
/// sets it on a config just loaded, before the runtime is made, so a scorer plugin without the
/// param refuses it (bad_config, "unknown config key 'scorer.params.per_user'"). Throws
/// bad_config when the config also writes `scorer.params.per_user: false`.
void apply_weights_switch(kernel::Config& config);
/// Throws bad_config when lexicon.weights = per_user but the scorer was not given per_user
/// (a config that did not go through apply_weights_switch): per-user weights are never global
/// silently.
void check_weights_switch(const kernel::Config& config);

struct DefineRequest {
  std::string user;
  std::string head;
  std::vector<std::string> body;
  std::vector<int> body_ranks;                  ///< optional per line
  std::vector<sdk::Program> body_programs;      ///< optional per line (null: by rank)
  const sdk::WorldState* before = nullptr;      ///< world before the first body line
  const sdk::ExecutionService* exec = nullptr;  ///< both needed for generalization
  /// The request's time limits (CPU budget, wall backstop): parses stop at them, and a
  /// definition that reaches one before its commit is refused (deadline_exceeded) with nothing
  /// stored.
  sdk::StopCondition stop;
  /// The study it is made in, when the front end knows it (kept in the lexicon's history).
  std::string study{};
  /// The history action of the definition (empty: `define`; `import`, `preload`).
  std::string via{};
  /// Induce and check for conflicts, store nothing (the outcome's rules have no ids).
  bool dry_run = false;
  /// Rules left out, by preview id ("newK": the K-th rule induced, from 1; docs/naturalization.md
  /// §5 "Preview"); bad_request for a name outside new1..newN or when no rule would be left.
  std::vector<std::string> drop{};
};

/// A rewriter candidate that generalization discarded.
struct Discarded {
  sdk::Program program;
  std::string rewriting;
  std::string reason;
};

struct DefineOutcome {
  std::vector<sdk::RulePtr> rules;  ///< the rules added (already in the parser and the store)
  sdk::Program body;                ///< the body's program: its lines' readings in sequence
  std::int64_t definition = 0;      ///< store id of the definition
  bool generalization_ran = false;
  sdk::Program generalized;  ///< the winning rewriting (null when the body won)
  std::string generalized_rewriting;
  std::vector<Discarded> discarded;
  /// Phrases of other users the rules change (lexicon.conflicts = warn: stored anyway).
  std::vector<DefineConflict> conflicts;
  bool stored = false;  ///< false for a dry run and a held definition
  /// lexicon.moderation = hold_new: the id ("h<N>") it waits under for a researcher.
  std::string held{};
  /// Preview ids ("newK") of the rules left out by DefineRequest::drop.
  std::vector<std::string> dropped{};
  /// The perturbed check of the chosen body (docs/naturalization.md §6): perturbed worlds used,
  /// how many it agreed with the user's body on, and the failures.
  int perturbations = 0;
  int perturbed_passed = 0;
  std::vector<std::string> perturbed_failed{};
  /// A preview's rules with their example sentences (session service, DefineCall::preview).
  std::vector<RulePreview> previews{};
  /// The other world a preview's sentences also ran on: the first perturbed copy of the
  /// session's world (robot elsewhere, items moved; none for a world too small to perturb).
  std::optional<sdk::WorldState> preview_elsewhere{};
};

/// "newK" for the K-th rule (from 1) a definition induces (docs/naturalization.md §5 "Preview").
std::string preview_id(std::size_t index);

/// One line of a `rules` listing.
struct RuleListing {
  sdk::RulePtr rule;
  std::uint64_t uses_by_author = 0;
  std::uint64_t uses_by_others = 0;
};

/// A stored rule that does not load (it stays in the store, unserved).
struct QuarantinedRule {
  StoredRule stored;
  std::string reason;
};

/// Preload outcome (definitions replayed, skipped because stored, failed with the reason). Each
/// failure is also a warning, and a row of the store (LexiconStore::preload_failures()).
struct PreloadReport {
  std::size_t replayed = 0;
  std::size_t already_stored = 0;
  std::vector<PreloadFailure> failures;
};

/// How start-up read the rules (docs/naturalization.md §5 "Start-up at scale").
struct StartupReport {
  bool from_snapshot = false;       ///< the stored snapshot, then the rows changed since
  std::int64_t snapshot_rules = 0;  ///< rules the snapshot held (from_snapshot)
  bool snapshot_saved = false;      ///< a fresh snapshot was stored (after reading the rows)
};

class Naturalizer {
 public:
  /// Opens the store and restores rules and weights into the runtime's parser and scorer, then
  /// preloads. Throws sdk::Error (bad_lexicon, bad_config for an unreadable preload file).
  Naturalizer(std::shared_ptr<kernel::Runtime> runtime, NaturalizeOptions options);
  ~Naturalizer();

  const NaturalizeOptions& options() const { return options_; }
  /// Whether `user` may parse with `rule` under the sharing mode.
  bool visible(const sdk::Rule& rule, const std::string& user) const;
  std::function<bool(const sdk::Rule&)> visibility_for(const std::string& user) const;

  /// §4 (after §6 when the runtime has a rewriter, generalization is on and a world is given).
  /// Throws sdk::Error: empty_head, head_reserved_token, head_is_core, body_unparsable,
  /// bad_request, and the store's codes (lexicon_busy, lexicon_full, ...: nothing changed then).
  DefineOutcome define(const DefineRequest& request);
  /// Picks up what other processes (or other kernels over the same store) committed since the
  /// last look: new rules, deletions, use counters and the weights of the scorer's current key
  /// (reloaded whole, so every kernel ranks bit for bit alike; docs/naturalization.md §5
  /// "Learned state"); a cheap check (PRAGMA data_version) when nothing changed.
  void refresh();
  /// Closes the lexicon store now (its last connection checkpoints and removes the WAL), for a
  /// process about to exit without destroying the naturalizer: every write is already committed
  /// when its op answers, so nothing is lost. Nothing that reads or writes the store may be
  /// called afterwards.
  void close_store();
  /// Live rules visible to `user`, optionally only those of `author`, in creation order.
  std::vector<RuleListing> rules(const std::string& user,
                                 const std::optional<std::string>& author = std::nullopt) const;
  /// Deletes a rule of `user`, authorship checked in the delete's transaction: forbidden for
  /// another user's visible rule, not_found for unknown ids and rules hidden from `user`; the
  /// parser forgets it, the store keeps it flagged.
  void delete_rule(const std::string& user, const std::string& id);
  /// After an accept (the scorer has learned and the session has counted the uses of the
  /// accepted derivation's induced rules): adds one use to each of those rules' stored counters
  /// and stores the scorer state, in one transaction. Throws the store's codes when it did not
  /// commit (the session then undoes the accept).
  void on_accept(const std::string& user, const std::vector<sdk::RulePtr>& used_rules);
  /// Moderation (docs/naturalization.md §5 "Moderation"): the definitions held for approval,
  /// oldest first; approve() stores one (its rules then serve as if defined now) and returns its
  /// rules, reject() drops one; both are history entries by `moderator`. Who may moderate is the
  /// front end's decision (the CLI's local user, the studio's researcher login). Throws
  /// not_found for an id that is not held.
  std::vector<HeldDefinition> pending() const;
  std::vector<sdk::RulePtr> approve(const std::string& moderator, const std::string& id);
  void reject(const std::string& moderator, const std::string& id, const std::string& reason = {});

  /// Live induced rules in creation order.
  const std::vector<sdk::RulePtr>& induced_rules() const { return rules_; }
  sdk::RulePtr find_rule(const std::string& id) const;
  const PreloadReport& preload_report() const { return preload_report_; }
  const StartupReport& startup() const { return startup_; }
  /// Stored rules that did not load, in the order they were met.
  const std::vector<QuarantinedRule>& quarantined() const { return quarantined_; }
  LexiconStore& store() { return *store_; }

 private:
  void restore();
  /// The phrases of other users that `fresh` (not yet stored) would change (conflicts.cpp).
  std::vector<DefineConflict> find_conflicts(const std::string& author,
                                             const std::vector<std::shared_ptr<sdk::Rule>>& fresh,
                                             const sdk::StopCondition& stop);
  /// Start-up from the stored snapshot plus the rows changed since; false (nothing loaded) when
  /// there is no usable snapshot or too much changed since.
  bool restore_from_snapshot();
  /// Start-up from the rule rows (after SQLite's quick_check), leaving a snapshot for the next.
  void restore_from_rows();
  /// Serves one stored rule (or quarantines it); its use counters are set by the caller.
  bool add_stored(StoredRule&& stored, const std::vector<sdk::RulePtr>& own = {});
  /// The same for a rule read from a snapshot (built straight from the blob's bytes).
  void add_viewed(const StoredRuleView& viewed);
  /// Keeps a stored rule that does not load out of the grammar, with a warning naming it.
  void quarantine(StoredRule&& stored, const std::string& reason);
  /// Writes the quarantines met since the last call into the store's history (best effort).
  void record_quarantines();
  void preload(const std::string& path);
  /// Applies changes read from the store; `own` holds this process's just-committed rules (used
  /// as they are instead of being read back).
  void apply(const LexiconChanges& changes, const std::vector<sdk::RulePtr>& own = {});
  /// Applies counters and weights learned elsewhere.
  void apply(const LearnedChanges& learned);
  /// After an accept's commit: the scorer holds exactly the stored weights again.
  void hold_stored_weights(sdk::IncrementalScorer* inc, const LexiconStore::WeightSums& sums);
  /// Folds an older store's per-user weight keys into kWeightsKey (once; see the .cpp).
  void fold_legacy_user_weights();
  void add_live(sdk::RulePtr rule);
  void remove_live(const std::string& id);
  bool exists_for(const sdk::Rule& rule, const std::string& author) const;
  std::string save_weights() const;  ///< the scorer's state (a guarded plugin call)
  /// Loads the scorer's stored weights under `key` (saved state, then additive weights).
  void load_weights(const std::string& key);

  std::shared_ptr<kernel::Runtime> runtime_;
  NaturalizeOptions options_;
  std::unique_ptr<LexiconStore> store_;
  std::vector<sdk::RulePtr> rules_;
  /// Keyed by a view of the rule's own id (rules are immutable; the value keeps the id alive):
  /// no second copy of every id.
  std::unordered_map<std::string_view, sdk::RulePtr> by_id_;
  /// shape_hash() of each rule in rules_ (same index): the candidates same_rule() compares a
  /// new rule with. Computed while the rule is hot (a hash map built at start-up cost ~10% of a
  /// 100k start; one built lazily cost the first define ~0.1 s, the rules out of the cache).
  std::vector<std::uint64_t> shapes_;
  ChangeMark mark_;                ///< how far this process has read the store's history
  std::int64_t learned_mark_ = 0;  ///< how far it has read what accepts taught
  bool held_from_state_ = false;   ///< the held weights start from a stored whole state
  std::string initial_weights_;    ///< scorer state before any learning (per_user default)
  PreloadReport preload_report_;
  StartupReport startup_;
  std::vector<QuarantinedRule> quarantined_;
  std::size_t quarantines_recorded_ = 0;  ///< quarantined_ entries already in the history
};

/// "$Action -> pick $Number items": the key rules with equal LHS and RHS share.
std::string rule_shape(const sdk::Rule& rule);
/// A hash of rule_shape()'s text, computed without building it.
std::uint64_t shape_hash(const sdk::Rule& rule);
/// A stored rule back to a grammar rule (template read with sorts from the RHS categories).
/// Throws sdk::Error when it does not load (unknown category, bad template).
sdk::RulePtr rule_from_stored(const StoredRule& stored);
/// The same, moving the strings out of `stored` (left as it was when it throws).
sdk::RulePtr rule_from_stored(StoredRule&& stored);
/// The same from a snapshot's view (nothing is copied twice).
sdk::RulePtr rule_from_stored(const StoredRuleView& stored);
/// Why a stored rule would be quarantined (nullopt: it loads).
std::optional<std::string> quarantine_reason(const StoredRule& stored);
/// Refuses a head with a token starting with '$' (head_reserved_token).
void check_head_tokens(const std::string& head);
StoredRule stored_from_rule(const sdk::Rule& rule, std::int64_t definition);

}  // namespace flipper::naturalization
