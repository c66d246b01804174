#pragma once
/// @file lexicon_history.hpp
/// The lexicon's history (docs/naturalization.md §5 "History and governance"): every change to the
/// live rule set — a definition and the rules induced from it, a deletion, a quarantine, an
/// import, a revert — is one entry of an append-only table, written in the transaction of the
/// change itself. Entries are numbered in commit order (`seq`); their times never go backwards.
/// Tags name a point of that history; the live rules at any point can be rebuilt from it.

#include <cstdint>
#include <optional>
#include <string>
#include <vector>

namespace flipper::naturalization {

/// What an entry does to the live rule set.
namespace history_effect {
inline constexpr const char* kAdd = "add";        ///< `rule` becomes live
inline constexpr const char* kRemove = "remove";  ///< `rule` stops being live
inline constexpr const char* kNone = "none";      ///< a definition, a quarantine
}  // namespace history_effect

/// What kind of change an entry records.
namespace history_action {
inline constexpr const char* kDefine = "define";          ///< a definition (its rules follow)
inline constexpr const char* kInduce = "induce";          ///< a rule induced from a definition
inline constexpr const char* kDelete = "delete";          ///< an author deleted a rule
inline constexpr const char* kQuarantine = "quarantine";  ///< a stored rule stopped loading
inline constexpr const char* kImport = "import";          ///< copied in (or there before history)
inline constexpr const char* kRevert = "revert";          ///< re-created or deleted by a revert
/// lexicon.moderation = hold_new: a definition held for a researcher (its rules serve no one)
inline constexpr const char* kHold = "hold";
inline constexpr const char* kApprove = "approve";  ///< a researcher approved a held definition
inline constexpr const char* kReject = "reject";    ///< a researcher rejected a held definition
}  // namespace history_action

/// One entry of the history.
struct HistoryEntry {
  std::int64_t seq = 0;     ///< commit order, from 1
  std::int64_t time = 0;    ///< seconds since the epoch (never less than an earlier entry's)
  std::string author;       ///< who made the change
  std::string action;       ///< history_action
  std::string effect;       ///< history_effect
  std::string rule;         ///< the rule it concerns (empty for a definition)
  std::string source_rule;  ///< a revert's re-created rule: the rule it copies
  std::int64_t definition = 0;
  std::string head;               ///< the source definition
  std::vector<std::string> body;  ///< the source definition
  std::string study;              ///< the study the change was made in (when known)
  std::string site;               ///< lexicon.site of the process that made it
  std::string note;               ///< e.g. a quarantine's reason, a revert's target
};

/// What an entry being written carries; seq and time are assigned in the transaction.
struct HistoryContext {
  std::string author;
  std::string study;
  std::string note;
};

/// A name for a point of the history.
struct LexiconTag {
  std::string name;
  std::int64_t seq = 0;  ///< the last entry it includes
  std::int64_t time = 0;
  std::string author;
  std::string checksum;  ///< lexicon_checksum() of the live rules at that point
};

/// Which entries `history()` returns.
struct HistoryFilter {
  std::optional<std::string> rule;    ///< entries of this rule (or re-creating it)
  std::optional<std::string> author;  ///< entries made by this user
};

/// What a revert changed: rules deleted, and rules re-created (new id, the id it copies).
struct RevertOutcome {
  std::vector<std::string> removed;
  std::vector<std::pair<std::string, std::string>> restored;
  std::int64_t seq = 0;  ///< the point reverted to
};

/// A tag name: a letter, then letters, digits, '.', '_' or '-' (at most 64), so a tag never reads
/// as a time (`@SECONDS`, `YYYY-MM-DDTHH:MM:SSZ`) or an entry number (`#N`).
bool valid_tag_name(const std::string& name);

}  // namespace flipper::naturalization
