#pragma once
/// @file config_keys.hpp
/// Naturalization's config keys (docs/config.md "Who declares a key"): the community lexicon
/// (`lexicon.*`, docs/naturalization.md §5) and grammar induction (`induction.*`), declared here
/// with the SDK's typed handles and nowhere else. config_schema() is this layer's schema fragment,
/// which the host composes with the kernel's (and the other layers') before it loads a config;
/// the readers (NaturalizeOptions::from_config, the studio's accounts file, the DDS replicator)
/// read through these handles. Header-only.

#include <cstdint>

#include "flipper/sdk/config_handles.hpp"

namespace flipper::naturalization {

/// lexicon.sharing: whose rules serve a user (in the order of kSharing's names).
enum class Sharing { shared, private_, core };
/// lexicon.conflicts: what a definition that changes other users' readings gets.
enum class ConflictPolicy { warn, refuse };
/// lexicon.moderation: whether new definitions wait for a researcher's approval.
enum class Moderation { off, hold_new };

namespace keys {

namespace param = sdk::param;

/// lexicon.weights: a short way to write the scorer's per_user param (apply_weights_switch)
enum class Weights { global, per_user };
/// lexicon.durability
enum class Durability { full, normal };
/// lexicon.replication
enum class Replication { none, dds };
/// induction.alignment_mode (docs/naturalization.md §4.8)
enum class AlignmentMode { stretch, window };
/// induction.view (docs/naturalization.md §4.1)
enum class InductionView { author, everyone };

inline constexpr param::Path kLexiconPath{"lexicon.path", "~/.local/share/flipper/lexicon.sqlite",
                                          "SQLite file (`:memory:`: none)"};
inline constexpr param::Choice<Sharing, 3> kSharing{
    "lexicon.sharing", Sharing::shared, {"shared", "private", "core"}, "whose rules serve a user"};
inline constexpr param::Path kPreload{"lexicon.preload", "",
                                      "definitions replayed at start (empty: none)"};
inline constexpr param::Choice<Weights, 2> kWeights{
    "lexicon.weights",
    Weights::global,
    {"global", "per_user"},
    "per_user: sets scorer.params.per_user, the scorer's weights per user (docs/naturalization.md "
    "§3)"};
inline constexpr param::Int<std::int64_t> kBusyTimeoutMs{
    "lexicon.busy_timeout_ms", 10000, 1, 600000,
    "longest wait for other writers, then lexicon_busy"};
inline constexpr param::Int<std::int64_t> kSnapshotMinRules{
    "lexicon.snapshot_min_rules", 512, 0, 1000000000,
    "keep a rule snapshot for fast start-up once the store holds this many live rules "
    "(docs/naturalization.md §5); 0: never"};
inline constexpr param::Choice<Durability, 2> kDurability{
    "lexicon.durability",
    Durability::full,
    {"full", "normal"},
    "full: each accept/define is on disk when answered; normal: survives any process crash, a "
    "power loss may drop the last commits (docs/naturalization.md §5)"};
inline constexpr param::Bool kGroupCommit{
    "lexicon.group_commit", true,
    "with durability full: the commits of one process (serve's kernels) share one WAL sync; each "
    "is answered after a sync that covers it (docs/naturalization.md §5)"};
inline constexpr param::Choice<Replication, 2> kReplication{
    "lexicon.replication", Replication::none, {"none", "dds"}, "share rules between sites"};
inline constexpr param::Text kSite{"lexicon.site", "",
                                   "this site's name (replication; recorded in the history)"};
inline constexpr param::Choice<ConflictPolicy, 2> kConflicts{
    "lexicon.conflicts",
    ConflictPolicy::warn,
    {"warn", "refuse"},
    "a definition that changes other users' readings: shown (warn) or refused (refuse, "
    "definition_conflicts)"};
inline constexpr param::Choice<Moderation, 2> kModeration{
    "lexicon.moderation",
    Moderation::off,
    {"off", "hold_new"},
    "hold_new: a new definition's rules serve no one until a researcher approves them "
    "(docs/naturalization.md §5 \"Moderation\")"};

inline constexpr param::Bool kAlignment{"induction.alignment", true,
                                        "induce rules by aligning head and body"};
inline constexpr param::Choice<AlignmentMode, 2> kAlignmentMode{
    "induction.alignment_mode",
    AlignmentMode::stretch,
    {"stretch", "window"},
    "stretch: the one stretch where head and body differ; window: every head phrase whose "
    "neighbouring tokens are a body node's, as the February 2018 runs (docs/naturalization.md "
    "§4.8)"};
inline constexpr param::Choice<InductionView, 2> kInductionView{
    "induction.view",
    InductionView::author,
    {"author", "everyone"},
    "whose rules a definition's head and body parses see under lexicon.sharing=private: the "
    "author's, or every user's as the 2018 server's one grammar (docs/naturalization.md §4.1)"};
inline constexpr param::Bool kGeneralize{"induction.generalize", true,
                                         "generalize definitions by rewriting"};
inline constexpr param::Int<std::int64_t> kPerturbedChecks{
    "induction.perturbed_checks", 0, 0, 1000, "perturbed worlds a generalization is checked on"};

/// Naturalization's schema fragment: the sections `lexicon` and `induction`.
inline sdk::ParamSchema config_schema() {
  sdk::ParamSchema s;
  s.add_section("lexicon", "the store of induced rules (naturalization)");
  param::add(s, kLexiconPath);
  param::add(s, kSharing);
  param::add(s, kPreload);
  param::add(s, kWeights);
  param::add(s, kBusyTimeoutMs);
  param::add(s, kSnapshotMinRules);
  param::add(s, kDurability);
  param::add(s, kGroupCommit);
  param::add(s, kReplication);
  param::add(s, kSite);
  param::add(s, kConflicts);
  param::add(s, kModeration);
  s.add_section("induction", "grammar induction from definitions");
  param::add(s, kAlignment);
  param::add(s, kAlignmentMode);
  param::add(s, kInductionView);
  param::add(s, kGeneralize);
  param::add(s, kPerturbedChecks);
  return s;
}

}  // namespace keys
}  // namespace flipper::naturalization
