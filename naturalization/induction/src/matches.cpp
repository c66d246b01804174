// Matches (docs/naturalization.md §4.4): head-chart derivations that yield a node of the body.
#include <algorithm>
#include <tuple>
#include <unordered_set>
#include <utility>
#include <vector>

#include "flipper/naturalization/induction.hpp"
#include "flipper/sdk/errors.hpp"

namespace flipper::naturalization {

std::string category_of_sort(sdk::Sort sort) {
  using sdk::Sort;
  switch (sort) {
    case Sort::Action:
      return "$Action";
    case Sort::Condition:
      return "$Situation";
    case Sort::Point:
      return "$Point";
    case Sort::Area:
      return "$Area";
    case Sort::Collection:
      return "$AreaCollection";
    case Sort::Item:
      return "$Item";
    case Sort::CountedItem:
      return "$CountedItem";
    case Sort::Filter:
      return "$PropertySet";
    case Sort::Number:
      return "$Number";
    case Sort::Direction:
      return "$Direction";
    case Sort::Color:
      return "$Color";
    case Sort::Shape:
      return "$Shape";
    case Sort::ItemAct:
      return "$ItemAct";
    case Sort::Property:
      return "$Property";
  }
  return "$Action";
}

bool category_fits(const std::string& category, sdk::Sort program) {
  try {
    // A plain item may stand for a $CountedItem, a colour or shape word for a $Property.
    return sdk::sort_fits(sdk::category_sort(category), program);
  } catch (const sdk::Error&) {
    return false;  // $ROOT or a grammar-private category: nothing in a program has it
  }
}

bool is_primitive_category(const std::string& c) {
  return c == "$Color" || c == "$Shape" || c == "$Number" || c == "$Direction" || c == "$Point";
}

namespace {

using ProgramSet = std::unordered_set<sdk::Program, sdk::ProgramHash, sdk::ProgramEqual>;

void collect_subtrees(const sdk::Program& p, ProgramSet& out) {
  if (!p || !out.insert(p).second) return;  // an equal subtree's kids are already in
  for (const auto& k : p->kids) collect_subtrees(k, out);
}

/// The derivation's normalised category when it fits its program, else empty. Every category of
/// statements ($ROOT, $Actions, $Action) is $Action: an induced rule's statement hole must not be
/// the grammar's root, which would swallow a whole `a ; b` sequence (docs/naturalization.md).
std::string matching_category(const sdk::Derivation& d) {
  std::string cat = sdk::normalize_category(d.category());
  if (!category_fits(cat, d.sem->sort)) return {};
  if (sdk::category_sort(cat) == sdk::Sort::Action) return "$Action";
  return cat;
}

/// Every subtree of `p`, in the normal form and the full form (where the verb of pick/drop is a
/// node of its own).
ProgramSet subtrees_of(const sdk::Program& p) {
  ProgramSet out;
  collect_subtrees(p, out);
  collect_subtrees(sdk::full_form(p), out);
  return out;
}

/// The subtrees of each statement of the body: the kids of its top-level sequence, or the body.
std::vector<ProgramSet> statement_subtrees(const sdk::Program& body) {
  std::vector<ProgramSet> out;
  if (body && body->kind == sdk::Kind::Seq)
    for (const auto& s : body->kids) out.push_back(subtrees_of(s));
  else
    out.push_back(subtrees_of(body));
  return out;
}

/// The plain items the body picks or drops one of (the object of a pick/drop without `every`):
/// the only places where a $CountedItem reading of a plain item is a node of the body. The
/// original's $CountedItem of `item` was a formula of its own (one item, `setLimit 1`), so a head
/// `item` matched as $CountedItem only there and as $Item elsewhere (docs/naturalization.md §4.4).
void collect_counted_objects(const sdk::Program& p, ProgramSet& out) {
  if (!p) return;
  const bool takes_object =
      p->kind == sdk::Kind::Pick || p->kind == sdk::Kind::Drop || p->kind == sdk::Kind::ItemAction;
  for (const auto& k : p->kids) {
    if (takes_object && k && k->sort == sdk::Sort::Item) out.insert(k);
    collect_counted_objects(k, out);
  }
}

/// The subtrees of one loop's guard (the area or collection it goes over, the condition it
/// tests) and of its body.
struct LoopParts {
  ProgramSet guard, body;
};

/// Every loop of `p` (foreach over points or areas, while), with its parts' subtrees.
void collect_loops(const sdk::Program& p, std::vector<LoopParts>& out) {
  if (!p) return;
  const bool loop = p->kind == sdk::Kind::ForeachPoint || p->kind == sdk::Kind::ForeachArea ||
                    p->kind == sdk::Kind::While;
  if (loop && p->kids.size() == 2) {
    LoopParts parts;
    collect_subtrees(p->kids[0], parts.guard);
    collect_subtrees(p->kids[1], parts.body);
    out.push_back(std::move(parts));
  }
  for (const auto& k : p->kids) collect_loops(k, out);
}

/// Marks the matches that lie in a loop's body while a shorter match inside their span has its
/// program in that loop's guard: `drop green` in `drop green items` := `while robot has item is
/// green {drop item is green}` (docs/naturalization.md §4.6).
void mark_loop_guard_strands(std::vector<Match>& matches, const sdk::Program& body) {
  std::vector<LoopParts> loops;
  collect_loops(sdk::full_form(body), loops);
  if (loops.empty()) return;
  std::vector<sdk::Program> full;  // each match's program in the full form, as the body's
  full.reserve(matches.size());
  for (const auto& m : matches) full.push_back(sdk::full_form(m.program));
  for (std::size_t w = 0; w < matches.size(); ++w) {
    Match& whole = matches[w];
    for (std::size_t p = 0; p < matches.size() && !whole.strands_loop_guard; ++p) {
      const Match& part = matches[p];
      if (part.start < whole.start || part.end > whole.end) continue;
      if (part.start == whole.start && part.end == whole.end) continue;
      whole.strands_loop_guard = std::any_of(loops.begin(), loops.end(), [&](const LoopParts& l) {
        return l.body.count(full[w]) > 0 && l.guard.count(full[p]) > 0;
      });
    }
  }
}

/// Whether `d`'s tree has a node spanning exactly [a, b).
bool has_node_spanning(const sdk::Derivation& d, int a, int b) {
  if (d.start == a && d.end == b) return true;
  return std::any_of(d.kids.begin(), d.kids.end(),
                     [&](const sdk::DerivationPtr& k) { return k && has_node_spanning(*k, a, b); });
}

/// Whether a node of `d`'s tree starts or ends strictly inside [a, b).
bool has_boundary_inside(const sdk::Derivation& d, int a, int b) {
  if ((d.start > a && d.start < b) || (d.end > a && d.end < b)) return true;
  return std::any_of(d.kids.begin(), d.kids.end(), [&](const sdk::DerivationPtr& k) {
    return k && has_boundary_inside(*k, a, b);
  });
}

/// Marks the matches that the head's reading of a longer phrase splits: `drop all` in `drop all
/// blue items to room3`, where the chart reads `drop all blue` as `drop` + `blue` through
/// `$ItemAct all $Property` and has no `drop all` inside it (docs/naturalization.md §4.6). A
/// one-token match has no inside to split.
void mark_split_by_head(std::vector<Match>& matches, const std::vector<sdk::DerivationPtr>& chart,
                        int head_length) {
  for (auto& m : matches) {
    if (m.end - m.start < 2) continue;
    for (const auto& d : chart) {
      if (!d || (d->start == 0 && d->end == head_length)) continue;
      if (d->start > m.start || d->end < m.end || d->end - d->start == m.end - m.start) continue;
      if (has_boundary_inside(*d, m.start, m.end) && !has_node_spanning(*d, m.start, m.end)) {
        m.split_by_head = true;
        break;
      }
    }
  }
}

ProgramSet counted_objects(const sdk::Program& body) {
  ProgramSet out;
  collect_counted_objects(body, out);
  collect_counted_objects(sdk::full_form(body), out);
  return out;
}

/// Whether the derivation uses an alignment rule with a category in its RHS (a packed one).
bool uses_packed_alignment(const sdk::Derivation& d) {
  if (d.rule && d.rule->how == sdk::RuleOrigin::alignment &&
      std::any_of(d.rule->rhs.begin(), d.rule->rhs.end(),
                  [](const sdk::Symbol& s) { return s.type == sdk::Symbol::Type::category; }))
    return true;
  return std::any_of(d.kids.begin(), d.kids.end(),
                     [](const sdk::DerivationPtr& k) { return k && uses_packed_alignment(*k); });
}

}  // namespace

std::vector<Match> find_matches(const std::vector<sdk::DerivationPtr>& chart,
                                const sdk::Program& body, int head_length, bool packed_alignment) {
  // Chart meanings are in normal form (pick/drop as Pick/Drop); the verb of an item action is a
  // node only in the full form (ItemAction(ItemAct, item)), so both forms' subtrees count.
  const ProgramSet nodes = subtrees_of(body);
  const std::vector<ProgramSet> statements = statement_subtrees(body);
  const ProgramSet counted = counted_objects(body);
  std::vector<Match> out;
  for (const auto& d : chart) {
    if (!d || !d->sem || (d->start == 0 && d->end == head_length)) continue;
    if (!nodes.count(d->sem)) continue;
    if (!packed_alignment && uses_packed_alignment(*d)) continue;
    // The loop variables `point` and `area` are words of the loop, not a point or area a rule
    // could take in their place (docs/naturalization.md §4.4).
    if (d->sem->kind == sdk::Kind::PointVar || d->sem->kind == sdk::Kind::AreaVar) continue;
    std::string cat = matching_category(*d);
    if (cat.empty()) continue;
    if (cat == "$CountedItem" && d->sem->sort == sdk::Sort::Item && !counted.count(d->sem))
      continue;
    // Keep one match per (span, category, program): the best-scoring derivation.
    auto same = std::find_if(out.begin(), out.end(), [&](const Match& m) {
      return m.start == d->start && m.end == d->end && m.category == cat &&
             sdk::equal(m.program, d->sem);
    });
    if (same != out.end()) {
      if (d->score > same->score) same->score = d->score;
      same->core_only = same->core_only || d->core_only;
      continue;
    }
    int held_by = 0;
    for (const auto& s : statements) held_by += s.count(d->sem) > 0 ? 1 : 0;
    out.push_back({d->start, d->end, std::move(cat), d->sem, d->score, d->core_only, held_by});
  }
  std::stable_sort(out.begin(), out.end(), [](const Match& a, const Match& b) {
    return std::tie(a.start, a.end) < std::tie(b.start, b.end);
  });
  mark_loop_guard_strands(out, body);
  mark_split_by_head(out, chart, head_length);
  return out;
}

}  // namespace flipper::naturalization
