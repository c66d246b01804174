#include "flipper/replay/rule_oracle.hpp"

#include <algorithm>
#include <set>

namespace flipper::replay {

namespace {

std::string our_category(const std::string& original) {
  return original == "$ItemActionFragment" ? "$ItemAct" : original;
}

std::string shape(const std::string& lhs, const std::vector<std::string>& rhs) {
  std::string s = our_category(lhs) + " ->";
  for (const auto& sym : rhs) s += " " + our_category(sym);
  return s;
}

}  // namespace

std::string original_shape(const LoggedRule& rule) {
  return shape(rule.lhs, rule.rhs);
}

std::string our_shape(const RuleShape& rule) {
  return shape(rule.lhs, rule.rhs);
}

std::string compare_rules(const std::vector<LoggedRule>& original,
                          const std::vector<RuleShape>& ours) {
  std::set<std::string> theirs, mine;
  const bool with_semantics =
      !original.empty() && std::all_of(original.begin(), original.end(),
                                       [](const LoggedRule& r) { return !r.semantics.empty(); });
  for (const auto& r : original)
    if (with_semantics)
      theirs.insert(original_shape(r) + " => " + r.semantics);
    else if (!r.alignment)
      theirs.insert(original_shape(r));
  if (theirs.empty()) return "";
  for (const auto& r : ours)
    if (with_semantics)
      mine.insert(our_shape(r) + " => " + r.semantics);
    else if (!r.alignment)  // as the original's alignment rules
      mine.insert(our_shape(r));
  if (mine == theirs) return "identical";
  const bool common = std::any_of(mine.begin(), mine.end(),
                                  [&](const std::string& s) { return theirs.count(s) != 0; });
  if (!common) return "missing";
  const bool inside = std::all_of(mine.begin(), mine.end(),
                                  [&](const std::string& s) { return theirs.count(s) != 0; });
  return inside ? "subset" : "overlap";
}

RuleIdentity classify_rules(const std::vector<LoggedRule>& original,
                            const std::vector<RuleShape>& ours,
                            const std::vector<RuleShape>& present) {
  std::set<std::string> theirs, mine, before;
  bool their_action_hole = false;
  for (const auto& r : original) {
    if (r.alignment || r.lhs == "KEYWORD_TOKEN") continue;
    theirs.insert(original_shape(r));
    their_action_hole =
        their_action_hole || std::find(r.rhs.begin(), r.rhs.end(), "$Action") != r.rhs.end();
  }
  if (theirs.empty()) return {};
  bool our_action_hole = false;
  for (const auto& r : ours) {
    if (r.alignment) continue;  // as the original's alignment rules
    mine.insert(our_shape(r));
    our_action_hole =
        our_action_hole || std::find(r.rhs.begin(), r.rhs.end(), "$Action") != r.rhs.end();
  }
  for (const auto& r : present)
    if (!r.alignment) before.insert(our_shape(r));
  auto contains = [](const std::set<std::string>& a, const std::set<std::string>& b) {
    return std::includes(a.begin(), a.end(), b.begin(), b.end());
  };
  RuleIdentity out;
  if (mine == theirs) {
    out.cls = "identical";
    return out;
  }
  const bool common = std::any_of(mine.begin(), mine.end(),
                                  [&](const std::string& s) { return theirs.count(s) != 0; });
  if (contains(theirs, mine)) {
    const bool earlier = std::all_of(theirs.begin(), theirs.end(), [&](const std::string& s) {
      return mine.count(s) != 0 || before.count(s) != 0;
    });
    out.cls = earlier ? "present" : "subset";
  } else if (contains(mine, theirs)) {
    out.cls = "superset";
  } else {
    out.cls = common ? "overlap" : "disjoint";
  }
  out.action_hole = out.cls != "present" && their_action_hole && !our_action_hole;
  return out;
}

}  // namespace flipper::replay
