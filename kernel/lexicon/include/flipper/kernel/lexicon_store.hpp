#pragma once
/// @file lexicon_store.hpp
/// The durable lexicon (docs/naturalization.md §5): one SQLite file holding every definition, the
/// rules induced from it (with their deletion history), the rules' use counters and the scorer
/// state. WAL journal with synchronous=FULL: a call that returned has reached the disk, so a
/// definition acknowledged after add_definition() survives a kill at any moment.
/// Not thread-safe: one owner (the naturalization façade) serialises calls.

#include <cstdint>
#include <iosfwd>
#include <memory>
#include <optional>
#include <string>
#include <vector>

namespace flipper::kernel {

namespace lexicon_codes {
/// The store file is corrupt, not a Flipper lexicon, or cannot be opened/written.
inline constexpr const char* kBadLexicon = "bad_lexicon";
}  // namespace lexicon_codes

/// One definition as the user gave it.
struct StoredDefinition {
  std::int64_t id = 0;  ///< assigned by the store
  std::string head;
  std::vector<std::string> body;
  std::string author;
  std::int64_t time = 0;  ///< seconds since the epoch
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
  std::int64_t created = 0;  ///< creation sequence number, unique and increasing
  std::int64_t definition = 0;
  bool deleted = false;
  std::int64_t deleted_at = 0;
  std::uint64_t uses_by_author = 0;
  std::uint64_t uses_by_others = 0;
};

/// Use counters of one rule, for batched updates after an accept.
struct RuleUses {
  std::string rule;
  std::uint64_t by_author = 0;
  std::uint64_t by_others = 0;
};

class LexiconStore {
 public:
  /// Opens (or creates, with parent directories) the store at `path`; ":memory:" is a private
  /// in-memory store. A corrupt or foreign file throws Error(bad_lexicon) naming the file and is
  /// left untouched.
  explicit LexiconStore(const std::string& path);
  ~LexiconStore();
  LexiconStore(const LexiconStore&) = delete;
  LexiconStore& operator=(const LexiconStore&) = delete;

  const std::string& path() const;
  static constexpr int kSchemaVersion = 1;

  /// Commits a definition and its rules in ONE transaction (durable on return). Returns the
  /// definition id; the rules' `definition` field is set to it by the store.
  std::int64_t add_definition(const StoredDefinition& definition,
                              const std::vector<StoredRule>& rules);
  /// Every definition, in commit order.
  std::vector<StoredDefinition> definitions() const;
  /// Rules in creation order; deleted ones only when asked.
  std::vector<StoredRule> rules(bool include_deleted = false) const;
  std::optional<StoredRule> rule(const std::string& id) const;
  /// Largest `created` ever stored (0 when empty); new rules continue after it.
  std::int64_t max_created() const;
  /// Flags a rule deleted (history kept). False when unknown or already deleted.
  bool mark_deleted(const std::string& id, std::int64_t time);

  /// Persists an accept: the counters of the used rules and, when `weights_key` is set, the
  /// scorer state, in one transaction.
  void record_accept(const std::vector<RuleUses>& uses, const std::string& weights_key,
                     const std::string& weights_state);
  void save_weights(const std::string& key, const std::string& state);
  std::optional<std::string> load_weights(const std::string& key) const;

  /// JSON Lines: one object per line, `{"type":"definition"|"rule"|"weights", ...}`.
  void export_jsonl(std::ostream& out) const;
  /// Imports an export (one transaction; existing ids are replaced). Returns lines imported.
  std::size_t import_jsonl(std::istream& in);

 private:
  struct Impl;
  std::unique_ptr<Impl> impl_;
};

}  // namespace flipper::kernel
