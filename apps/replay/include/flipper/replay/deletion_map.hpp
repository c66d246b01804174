#pragma once
/// @file deletion_map.hpp
/// Maps an original `:delete <index>` to rule identity. The index is 0-based into the run's
/// live induced rules in creation order (preloaded first) at that moment. The grammar log is
/// the final state after deletions, so the deleted rule itself is never in the log: we rebuild
/// the list from the logged rules of the definitions made so far (a repeated definition adds
/// nothing), find the gap at `index` (between the definitions owning entries index-1 and index)
/// and attribute the deleted rule to a definition in that gap — preferring the deleting user's
/// definitions that lost rules (rules_status none_in_log, or no logged best-packing rule), the
/// latest first. Which rule of that definition: the packings missing from its log in the order
/// simple, best; we then delete OUR rule(s) of that definition with the same `how`.
/// Checked on the dev split: the 4 deletions map to definitions whose rules are absent from the
/// final log exactly as the index arithmetic requires.

#include <string>
#include <vector>

#include "flipper/replay/corpus.hpp"

namespace flipper::replay {

struct OurRule {
  std::string id;
  std::string how;  ///< simple / best / alignment / rewriting
};

class DeletionMap {
 public:
  /// A definition was replayed (in log order); `ours` are the rules our define added.
  void add_definition(const Definition& def, const std::string& user, std::vector<OurRule> ours);

  struct Mapping {
    std::string def_id;            ///< "" when no definition fits
    std::vector<std::string> ids;  ///< our rules to delete
    std::string note;
  };
  /// Maps a deletion by `user` at `index`; updates the model (the rule is gone afterwards).
  Mapping map(const std::string& user, int index);

 private:
  struct Def {
    const Definition* def;
    std::string user;
    std::vector<OurRule> ours;
    std::vector<std::string> missing;  ///< packings absent from the log, in order simple, best
    int deleted = 0;                   ///< deletions attributed so far
  };
  std::vector<Def> defs_;
  std::vector<int> entries_;  ///< live logged rules: index into defs_ per entry
  std::vector<int> seen_lines_;
};

}  // namespace flipper::replay
