// Rule construction from a packing (docs/naturalization.md §4.7).
#include "flipper/naturalization/induction.hpp"

namespace flipper::naturalization {

namespace {

struct Slot {
  const Match* match;
  sdk::Program full;  // the match's program in full form, as it appears in the full-form body
  int hole;           // RHS category index whose hole stands for this (category, program)
};

bool takes_counted_item(sdk::Kind parent) {
  return parent == sdk::Kind::Pick || parent == sdk::Kind::Drop || parent == sdk::Kind::ItemAction;
}

/// Whether a hole of sort `hole` may replace a `p` that is a kid of a `parent` node. A plain item
/// packed as $CountedItem only stands for the object of pick/drop, where `every` may go; a colour
/// or shape packed as $Property stands for any property word (its only parent is `is`).
bool hole_may_stand(sdk::Sort hole, const sdk::Program& p, sdk::Kind parent) {
  if (hole == p->sort) return true;
  if (hole == sdk::Sort::CountedItem) return takes_counted_item(parent);
  return hole == sdk::Sort::Property && sdk::sort_fits(hole, p->sort);
}

/// `p` with every subtree equal to a packed program replaced by its hole.
sdk::Program replace_packed(const sdk::Program& p, const std::vector<Slot>& slots,
                            sdk::Kind parent = sdk::Kind::Seq) {
  for (const auto& s : slots) {
    if (p->sort != s.full->sort || !sdk::equal(p, s.full)) continue;
    const sdk::Sort hole = sdk::category_sort(s.match->category);
    if (!hole_may_stand(hole, p, parent)) continue;
    return sdk::make_hole(s.hole, hole);
  }
  if (p->kids.empty()) return p;
  std::vector<sdk::Program> kids;
  kids.reserve(p->kids.size());
  bool changed = false;
  for (const auto& k : p->kids) {
    kids.push_back(replace_packed(k, slots, p->kind));
    changed = changed || kids.back() != k;
  }
  return changed ? sdk::make(p->kind, std::move(kids)) : p;
}

}  // namespace

BuiltRule build_rule(const std::string& lhs, const std::vector<std::string>& head_tokens,
                     const std::vector<Match>& packing, const sdk::Program& body,
                     sdk::RuleOrigin how) {
  BuiltRule out;
  if (packing.size() > kMaxRuleCategories) {
    out.rejection = RuleRejection::too_many_categories;
    return out;
  }
  sdk::Rule rule;
  rule.lhs = lhs;
  rule.induced = true;
  rule.how = how;
  std::vector<Slot> slots;
  std::size_t next = 0;
  int category_index = 0;
  for (int i = 0; i < static_cast<int>(head_tokens.size());) {
    if (next < packing.size() && packing[next].start == i) {
      const Match& m = packing[next++];
      rule.rhs.push_back({sdk::Symbol::Type::category, m.category});
      bool shared = false;  // an equal (category, program) already has a hole
      for (const auto& s : slots)
        shared =
            shared || (s.match->category == m.category && sdk::equal(s.match->program, m.program));
      if (!shared) slots.push_back({&m, sdk::full_form(m.program), category_index});
      ++category_index;
      i = m.end;
    } else {
      rule.rhs.push_back({sdk::Symbol::Type::token, head_tokens[static_cast<std::size_t>(i)]});
      ++i;
    }
  }
  if (rule.rhs.size() == 1 && rule.rhs[0].type == sdk::Symbol::Type::category) {
    out.rejection = RuleRejection::single_category;
    return out;
  }
  // Work on the full form so that the verb of pick/drop can become a hole; `make` turns every
  // untouched ItemAction back into Pick/Drop.
  rule.sem = sdk::normal_form(replace_packed(sdk::full_form(body), slots));
  out.rule = std::move(rule);
  return out;
}

bool same_rule(const sdk::Rule& a, const sdk::Rule& b) {
  return a.lhs == b.lhs && a.rhs == b.rhs && sdk::equal(a.sem, b.sem);
}

}  // namespace flipper::naturalization
