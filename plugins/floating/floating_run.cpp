// One floating parse: the toolkit's chart run (flipper/toolkit/chart_run.hpp) unchanged over the
// exact cells, plus the skip logic. Beside each exact list a cell keeps up to `floating_beam`
// derivations that skip words, built three ways, each skipped word a wrapper node `$C -> $C`:
// - a gap between two RHS symbols: the words are wrapped onto the kid after the gap (or, before a
//   token symbol, onto the category kid before it);
// - a floating kid (a derivation of a smaller span that skipped words);
// - at the root: `$ROOT` of a sub-span wrapped out to the whole utterance (words before, after).
// A derivation never skips more than `max_skips` words. Floating candidates are the programs no
// exact derivation yields; they are never core-only, so the usual order (core first, then score,
// then the newest rule) puts every exact core reading first.
#include <algorithm>
#include <map>

#include "flipper/toolkit/chart_run.hpp"
#include "floating_parser.hpp"

namespace flipper::plugins::floating {

namespace {

using sdk::DerivationPtr;
using toolkit::Sym;

struct Floating {
  DerivationPtr d;
  int skips = 0;
};

double score_of(const Floating& f) {
  return f.d->score;
}

class FloatingRun : public toolkit::ChartRun<FloatingRun> {
 public:
  FloatingRun(const toolkit::RuleIndex& index, const sdk::ParseRequest& req, int beam,
              bool rule_index, const SkipOptions& o)
      : ChartRun(index, req, beam, !rule_index), o_(o) {
    fixed_before_.assign(1, 0);
    for (const auto& t : req.tokens)
      fixed_before_.push_back(fixed_before_.back() + (skippable(t) ? 0 : 1));
    floating_cells_.resize(cell_count());
  }

 private:
  friend class toolkit::ChartRun<FloatingRun>;
  using FloatingCell = std::vector<toolkit::CategoryList<Floating>>;

  FloatingCell& floating_cell(int i, int j) { return floating_cells_[cell_index(i, j)]; }

  // Every token of [a, b) may be skipped.
  bool all_skippable(int a, int b) const { return fixed_before_[b] == fixed_before_[a]; }

  // --- ChartRun hooks ---
  void begin_span(int, int) { pending_floating_.clear(); }

  // Rules reached only through floating kids cannot yield an exact derivation: after the exact.
  void try_more_first_categories(int i, int j) {
    for (int e = i + 1; e < j; ++e)
      for (const auto& cc : floating_cell(i, e)) try_first_category(cc.cat, i, j);
  }

  void queue_more(int i, int j, std::vector<Queued>& queue) {
    for (auto& f : pending_floating_)
      if (insert_floating(i, j, f))
        queue.push_back({f.d, 0, f.skips, index_.category_id(f.d->rule->lhs)});
  }

  bool insert_inexact(int i, int j, const DerivationPtr& d, int skips) {
    return insert_floating(i, j, {d, skips});
  }

  void match_rule(int r, Rhs rhs, int i, int j) { match(r, rhs, 0, i, i, j, 0); }

  void collect_candidates(sdk::ParseResult& out) {
    collect_exact_roots(out);
    // Floating roots: the whole span's, and sub-spans' roots with the words around them skipped.
    const int root = index_.root();
    std::vector<DerivationPtr> floating;
    for (int a = 0; a <= std::min(o_.max_skips, n_ - 1) && !stopped_; ++a)
      for (int b = n_; b > a && a + (n_ - b) <= o_.max_skips && !stopped_; --b) {
        const int around = a + (n_ - b);
        if (!all_skippable(0, a) || !all_skippable(b, n_)) continue;
        if (const auto* exact = toolkit::find_list(cell(a, b), root); exact && around > 0)
          for (const auto& d : *exact)
            if (auto w = extend(d, 0, n_)) floating.push_back(std::move(w));
        if (const auto* roots = toolkit::find_list(floating_cell(a, b), root))
          for (const auto& f : *roots)
            if (f.skips + around <= o_.max_skips)
              if (auto w = extend(f.d, 0, n_)) floating.push_back(std::move(w));
      }
    std::stable_sort(
        floating.begin(), floating.end(),
        [](const DerivationPtr& x, const DerivationPtr& y) { return x->score > y->score; });
    for (const auto& d : floating)
      if (!exact_programs_.count(d->sem))  // an exact reading already has it
        toolkit::add_candidate(out, floating_programs_, d);
    toolkit::order_candidates(out.candidates);
  }

  // --- the skip logic ---
  bool insert_floating(int i, int j, const Floating& f) {
    return toolkit::insert_in_beam(
        toolkit::list_for(floating_cell(i, j), index_.category_id(f.d->rule->lhs)), f,
        o_.floating_beam, score_of);
  }

  // Matches RHS symbol k at position p or, leaving out words, later (not before the first).
  void match(int r, Rhs rhs, std::size_t k, int p, int i, int j, int skips) {
    if (stopped_) return;
    const std::size_t nsym = rhs.size();
    if (k == nsym) {
      if (p != j) return;
      if (skips == 0) {
        complete(r, i, j);
      } else if (auto d = build(r, i, j, req_.tokens[static_cast<std::size_t>(i)])) {
        pending_floating_.push_back({std::move(d), skips});
      }
      return;
    }
    const int remaining = static_cast<int>(nsym - k);
    const int max_gap = k == 0 ? 0 : std::min(o_.max_skips - skips, j - p - remaining);
    for (int gap = 0; gap <= max_gap && !stopped_; ++gap) {
      if (gap > 0 && !all_skippable(p, p + gap)) return;  // longer gaps include this word too
      match_at(r, rhs, k, p, p + gap, i, j, skips + gap);
    }
  }

  // Symbol k starts at q; words [p, q) are left out (wrapped onto a neighbouring kid).
  void match_at(int r, Rhs rhs, std::size_t k, int p, int q, int i, int j, int skips) {
    const std::size_t nsym = rhs.size();
    const int remaining = static_cast<int>(nsym - k);
    const Sym& s = rhs[k];
    if (s.type != Sym::Type::category) {
      if (!fits(s, q)) return;
      if (q == p) {
        match(r, rhs, k + 1, q + 1, i, j, skips);
        return;
      }
      // Words before a token symbol belong to the category kid before it, if there is one.
      if (rhs[k - 1].type != Sym::Type::category) return;
      const DerivationPtr* before = kids_.back();
      const DerivationPtr extended = extend(*before, (*before)->start, q);
      if (extended) {
        kids_.back() = &extended;  // alive until the match below returns
        match(r, rhs, k + 1, q + 1, i, j, skips);
        kids_.back() = before;
      }
      return;
    }
    const int e_min = k + 1 == nsym ? j : q + 1;
    const int e_max = j - (remaining - 1);
    for (int e = e_min; e <= e_max; ++e) {
      if (q == i && e == j) continue;  // whole span: only unary rules (fixpoint)
      if (const auto* exact = toolkit::find_list(cell(q, e), s.id))
        for (const auto& d : *exact)
          if (!use_kid(r, rhs, k, p, q, d, e, i, j, skips)) return;
      if (const auto* floating = toolkit::find_list(floating_cell(q, e), s.id))
        for (const auto& f : *floating) {
          if (skips + f.skips > o_.max_skips) continue;
          if (!use_kid(r, rhs, k, p, q, f.d, e, i, j, skips + f.skips)) return;
        }
    }
  }

  // Continues the match with `d` (over [q, e)) as kid k, wrapped over [p, e). False: stopped.
  bool use_kid(int r, Rhs rhs, std::size_t k, int p, int q, const DerivationPtr& d, int e, int i,
               int j, int skips) {
    const DerivationPtr extended = q == p ? nullptr : extend(d, p, e);
    if (q != p && !extended) return false;
    kids_.push_back(q == p ? &d : &extended);  // both alive until the match below returns
    match(r, rhs, k + 1, e, i, j, skips);
    kids_.pop_back();
    return !stopped_;
  }

  // `d` wrapped out to [start, end) by one skip node per left-out word (left words first).
  DerivationPtr extend(DerivationPtr d, int start, int end) {
    while (d && d->start > start) {
      const int word = d->start - 1;
      d = skip_node(std::move(d), word);
    }
    while (d && d->end < end) {
      const int word = d->end;
      d = skip_node(std::move(d), word);
    }
    return d;
  }

  DerivationPtr skip_node(DerivationPtr kid, int word) {
    if (!count_built()) return nullptr;
    auto d = std::make_shared<sdk::Derivation>();
    d->rule = skip_rule(kid, word);
    d->start = std::min(kid->start, word);
    d->end = std::max(kid->end, word + 1);
    d->sem = kid->sem;
    d->core_only = false;
    d->newest_rule = kid->newest_rule;
    d->score = req_.scorer->score_node(*d, ctx_) + kid->score - o_.skip_cost;
    d->kids.push_back(std::move(kid));
    return d;
  }

  // `$C -> $C => $1` with id floating:skip:<word>, one per (category, word) and parse.
  sdk::RulePtr skip_rule(const DerivationPtr& kid, int word) {
    const std::string& token = req_.tokens[static_cast<std::size_t>(word)];
    auto& slot = skip_rules_[{kid->rule->lhs, token}];
    if (!slot) {
      auto r = std::make_shared<sdk::Rule>();
      r->id = "floating:skip:" + token;
      r->lhs = kid->rule->lhs;
      r->rhs.push_back({sdk::Symbol::Type::category, kid->rule->lhs});
      r->sem = sdk::make_hole(0, kid->sem ? kid->sem->sort : sdk::category_sort(r->lhs));
      slot = std::move(r);
    }
    return slot;
  }

  const SkipOptions o_;
  std::vector<int> fixed_before_;  // words that may not be skipped among tokens [0, i)
  std::vector<FloatingCell> floating_cells_;
  std::vector<Floating> pending_floating_;
  std::map<std::pair<std::string, std::string>, sdk::RulePtr> skip_rules_;
  toolkit::ProgramIndex floating_programs_;
};

}  // namespace

sdk::ParseResult parse_floating(const toolkit::RuleIndex& index, const sdk::ParseRequest& request,
                                int beam, bool rule_index, const SkipOptions& options) {
  return FloatingRun(index, request, beam, rule_index, options).run();
}

}  // namespace flipper::plugins::floating
