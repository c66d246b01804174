// One floating parse. The exact part is the chart parser's algorithm unchanged (spans by
// increasing length, rules by first symbol, unary rules to a fixpoint, `beam` per category and
// span), over exact cells only. Beside each exact list a cell keeps up to `floating_beam`
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
#include <unordered_map>

#include "flipper/sdk/errors.hpp"
#include "floating_parser.hpp"
#include "start_rules.hpp"

namespace flipper::floating {

namespace {

using chart::FirstKind;
using chart::RuleIndex;
using chart::StartRules;
using chart::Sym;
using sdk::DerivationPtr;

struct Floating {
  DerivationPtr d;
  int skips = 0;
};

template <class Entry>
struct CatList {
  int cat;
  std::vector<Entry> list;  // sorted by score desc, stable (as chart's cells)
};

// Exact and floating derivations live apart: the exact lists (and the order in which their
// categories appeared) are exactly chart's, so exact parsing is not disturbed by floating work.
struct Cell {
  std::vector<CatList<DerivationPtr>> exact;
  std::vector<CatList<Floating>> floating;

  template <class Entry>
  static const std::vector<Entry>* find(const std::vector<CatList<Entry>>& cats, int cat) {
    for (const auto& c : cats)
      if (c.cat == cat) return &c.list;
    return nullptr;
  }
  template <class Entry>
  static std::vector<Entry>& get(std::vector<CatList<Entry>>& cats, int cat) {
    for (auto& c : cats)
      if (c.cat == cat) return c.list;
    cats.push_back({cat, {}});
    return cats.back().list;
  }
};

// Unary chains longer than this are cut (guards against cyclic unary rules), as in chart.
constexpr int kMaxUnaryDepth = 24;

using Rhs = std::span<const Sym>;

class Run {
 public:
  Run(const RuleIndex& index, const sdk::ParseRequest& req, const Options& o)
      : index_(index),
        req_(req),
        o_(o),
        n_(static_cast<int>(req.tokens.size())),
        token_ids_(index.token_ids(req.tokens)),
        classes_(index.classes(req.tokens)),
        starts_(index, token_ids_, classes_, req.visible, !o.rule_index) {
    ctx_ = req.context;
    if (ctx_.tokens == nullptr) ctx_.tokens = &req.tokens;
    fixed_before_.assign(1, 0);
    for (const auto& t : req.tokens)
      fixed_before_.push_back(fixed_before_.back() + (skippable(t) ? 0 : 1));
    cells_.resize(static_cast<std::size_t>(n_ + 1) * static_cast<std::size_t>(n_ + 1));
    tried_.assign(index.category_count(), 0);
  }

  sdk::ParseResult run() {
    sdk::ParseResult out;
    const int last_len = req_.whole_span ? n_ : n_ - 1;
    for (int len = 1; len <= last_len && !stopped_; ++len)
      for (int i = 0; i + len <= n_ && !stopped_; ++i) fill(i, i + len);
    if (req_.whole_span && n_ > 0) collect_candidates(out);
    out.stopped = stopped_;
    out.derivations = built_;
    if (req_.want_chart) {  // exact derivations only: the head chart of induction
      for (int i = 0; i < n_; ++i)
        for (int j = i + 1; j <= n_; ++j) {
          if (i == 0 && j == n_) continue;
          for (const auto& cc : cell(i, j).exact)
            out.chart.insert(out.chart.end(), cc.list.begin(), cc.list.end());
        }
    }
    return out;
  }

 private:
  Cell& cell(int i, int j) {
    return cells_[static_cast<std::size_t>(i) * static_cast<std::size_t>(n_ + 1) +
                  static_cast<std::size_t>(j)];
  }

  // Every token of [a, b) may be skipped.
  bool all_skippable(int a, int b) const { return fixed_before_[b] == fixed_before_[a]; }

  void fill(int i, int j) {
    pending_.clear();
    pending_floating_.clear();
    if (token_ids_[i] >= 0)
      for (int r : starts_.at(i, FirstKind::token, token_ids_[i])) try_rule(r, i, j);
    for (int b = 0; b < 4; ++b)
      if (classes_[i] & (1 << b))
        for (int r : starts_.at(i, FirstKind::klass, b)) try_rule(r, i, j);
    // Category-first rules, once per span: those of exact kids first, in chart's order; a rule
    // reached only through floating kids cannot yield an exact derivation.
    ++span_stamp_;
    auto try_first_category = [&](int cat) {
      int& st = tried_[static_cast<std::size_t>(cat)];
      if (st == span_stamp_) return;
      st = span_stamp_;
      for (int r : starts_.at(i, FirstKind::category, cat)) try_rule(r, i, j);
    };
    for (int e = i + 1; e < j; ++e)
      for (const auto& cc : cell(i, e).exact) try_first_category(cc.cat);
    for (int e = i + 1; e < j; ++e)
      for (const auto& cc : cell(i, e).floating) try_first_category(cc.cat);
    Cell& here = cell(i, j);
    struct Queued {
      DerivationPtr d;
      int depth, skips;
    };
    std::vector<Queued> queue;
    for (auto& d : pending_)
      if (insert_exact(here, d)) queue.push_back({d, 0, 0});
    for (auto& f : pending_floating_)
      if (insert_floating(here, f)) queue.push_back({f.d, 0, f.skips});
    for (std::size_t q = 0; q < queue.size() && !stopped_; ++q) {
      const Queued item = queue[q];
      if (item.depth >= kMaxUnaryDepth) continue;
      const int cat = index_.category_id(item.d->rule->lhs);
      for (int r : index_.unary_from(cat)) {
        if (!starts_.visible(r)) continue;
        kids_.assign(1, item.d);
        auto d = build(r, i, j, {});
        if (!d) continue;
        const bool kept =
            item.skips == 0 ? insert_exact(here, d) : insert_floating(here, {d, item.skips});
        if (kept) queue.push_back({std::move(d), item.depth + 1, item.skips});
      }
    }
  }

  // `r` comes from StartRules: alive and visible.
  void try_rule(int r, int i, int j) {
    const auto rhs = index_.rhs(r);
    if (static_cast<int>(rhs.size()) > j - i) return;
    const Sym& last = rhs.back();
    if (last.type == Sym::Type::token && token_ids_[j - 1] != last.id) return;
    if (last.type == Sym::Type::klass && !(classes_[j - 1] & last.id)) return;
    kids_.clear();
    match(r, rhs, 0, i, i, j, 0);
  }

  // Matches RHS symbol k at position p or, leaving out words, later (not before the first).
  void match(int r, Rhs rhs, std::size_t k, int p, int i, int j, int skips) {
    if (stopped_) return;
    const std::size_t nsym = rhs.size();
    if (k == nsym) {
      if (p != j) return;
      auto d = build(r, i, j, req_.tokens[static_cast<std::size_t>(i)]);
      if (!d) return;
      if (skips == 0)
        pending_.push_back(std::move(d));
      else
        pending_floating_.push_back({std::move(d), skips});
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
      const bool fits = s.type == Sym::Type::token ? token_ids_[q] == s.id : (classes_[q] & s.id);
      if (!fits) return;
      if (q == p) {
        match(r, rhs, k + 1, q + 1, i, j, skips);
        return;
      }
      // Words before a token symbol belong to the category kid before it, if there is one.
      if (rhs[k - 1].type != Sym::Type::category) return;
      const DerivationPtr before = kids_.back();
      kids_.back() = extend(before, before->start, q);
      if (kids_.back()) match(r, rhs, k + 1, q + 1, i, j, skips);
      kids_.back() = before;
      return;
    }
    const int e_min = k + 1 == nsym ? j : q + 1;
    const int e_max = j - (remaining - 1);
    for (int e = e_min; e <= e_max; ++e) {
      if (q == i && e == j) continue;  // whole span: only unary rules (fixpoint)
      const Cell& c = cell(q, e);
      if (const auto* exact = Cell::find(c.exact, s.id))
        for (const auto& d : *exact)
          if (!use_kid(r, rhs, k, p, q, d, e, i, j, skips)) return;
      if (const auto* floating = Cell::find(c.floating, s.id))
        for (const auto& f : *floating) {
          if (skips + f.skips > o_.max_skips) continue;
          if (!use_kid(r, rhs, k, p, q, f.d, e, i, j, skips + f.skips)) return;
        }
    }
  }

  // Continues the match with `d` (over [q, e)) as kid k, wrapped over [p, e). False: stopped.
  bool use_kid(int r, Rhs rhs, std::size_t k, int p, int q, const DerivationPtr& d, int e, int i,
               int j, int skips) {
    DerivationPtr kid = q == p ? d : extend(d, p, e);
    if (!kid) return false;
    kids_.push_back(std::move(kid));
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
    if ((++built_ & 63) == 0 && req_.stop.should_stop(built_)) {
      stopped_ = true;
      return nullptr;
    }
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

  DerivationPtr build(int r, int i, int j, std::string_view token) {
    if ((++built_ & 63) == 0 && req_.stop.should_stop(built_)) {
      stopped_ = true;
      return nullptr;
    }
    const chart::CompiledRule& rule = index_.rules()[static_cast<std::size_t>(r)];
    sems_.clear();
    for (const auto& k : kids_) sems_.push_back(k->sem);
    sdk::Program sem;
    try {
      sem = sdk::apply_rule(*rule.rule, sems_, token);
    } catch (const sdk::Error&) {
      return nullptr;  // a kid of the wrong sort: not a derivation
    }
    auto d = std::make_shared<sdk::Derivation>();
    d->rule = rule.rule;
    d->start = i;
    d->end = j;
    d->kids = kids_;
    d->sem = std::move(sem);
    d->core_only = !rule.rule->induced;
    d->newest_rule = rule.rule->induced ? rule.rule->created : 0;
    double kid_score = 0;
    for (const auto& k : kids_) {
      d->core_only = d->core_only && k->core_only;
      d->newest_rule = std::max(d->newest_rule, k->newest_rule);
      kid_score += k->score;
    }
    d->score = req_.scorer->score_node(*d, ctx_) + kid_score;
    return d;
  }

  static auto by_score_desc() {
    return [](double s, const DerivationPtr& x) { return s > x->score; };
  }

  bool insert_exact(Cell& c, const DerivationPtr& d) {
    auto& list = Cell::get(c.exact, index_.category_id(d->rule->lhs));
    if (static_cast<int>(list.size()) >= o_.beam && d->score <= list.back()->score) return false;
    list.insert(std::upper_bound(list.begin(), list.end(), d->score, by_score_desc()), d);
    if (static_cast<int>(list.size()) > o_.beam) list.pop_back();
    return true;
  }

  bool insert_floating(Cell& c, const Floating& f) {
    auto& list = Cell::get(c.floating, index_.category_id(f.d->rule->lhs));
    const int cap = o_.floating_beam;
    if (static_cast<int>(list.size()) >= cap && f.d->score <= list.back().d->score) return false;
    auto pos = std::upper_bound(list.begin(), list.end(), f.d->score,
                                [](double s, const Floating& x) { return s > x.d->score; });
    list.insert(pos, f);
    if (static_cast<int>(list.size()) > cap) list.pop_back();
    return true;
  }

  void add_root(sdk::ParseResult& out, const DerivationPtr& d, bool exact) {
    if (!sdk::loop_variables_bound(d->sem)) return;
    if (!exact && exact_programs_.count(d->sem)) return;  // an exact reading already has it
    auto& seen = exact ? exact_programs_ : floating_programs_;
    auto [it, fresh] = seen.emplace(d->sem, out.candidates.size());
    if (fresh) {
      sdk::Candidate c;
      c.program = d->sem;
      c.score = d->score;
      c.core_only = d->core_only;
      c.newest_rule = d->newest_rule;
      out.candidates.push_back(std::move(c));
    }
    sdk::Candidate& c = out.candidates[it->second];
    c.derivations.push_back(d);
    c.core_only = c.core_only || d->core_only;
  }

  void collect_candidates(sdk::ParseResult& out) {
    const int root = index_.root();
    if (const auto* roots = Cell::find(cell(0, n_).exact, root))
      for (const auto& d : *roots) add_root(out, d, true);
    // Floating roots: the whole span's, and sub-spans' roots with the words around them skipped.
    std::vector<DerivationPtr> floating;
    for (int a = 0; a <= std::min(o_.max_skips, n_ - 1) && !stopped_; ++a)
      for (int b = n_; b > a && a + (n_ - b) <= o_.max_skips && !stopped_; --b) {
        const int around = a + (n_ - b);
        if (!all_skippable(0, a) || !all_skippable(b, n_)) continue;
        const Cell& c = cell(a, b);
        if (const auto* exact = Cell::find(c.exact, root); exact && around > 0)
          for (const auto& d : *exact)
            if (auto w = extend(d, 0, n_)) floating.push_back(std::move(w));
        if (const auto* roots = Cell::find(c.floating, root))
          for (const auto& f : *roots)
            if (f.skips + around <= o_.max_skips)
              if (auto w = extend(f.d, 0, n_)) floating.push_back(std::move(w));
      }
    std::stable_sort(
        floating.begin(), floating.end(),
        [](const DerivationPtr& x, const DerivationPtr& y) { return x->score > y->score; });
    for (const auto& d : floating) add_root(out, d, false);
    // Core first, then score (desc), then the newest rule first; stable otherwise (as chart).
    std::stable_sort(out.candidates.begin(), out.candidates.end(),
                     [](const sdk::Candidate& a, const sdk::Candidate& b) {
                       if (a.core_only != b.core_only) return a.core_only;
                       if (a.score != b.score) return a.score > b.score;
                       return a.newest_rule > b.newest_rule;
                     });
  }

  using ProgramIndex =
      std::unordered_map<sdk::Program, std::size_t, sdk::ProgramHash, sdk::ProgramEqual>;

  const RuleIndex& index_;
  const sdk::ParseRequest& req_;
  const Options o_;
  const int n_;
  sdk::ScoreContext ctx_;
  const std::vector<int> token_ids_;
  const std::vector<std::uint8_t> classes_;
  StartRules starts_;
  std::vector<int> fixed_before_;  // words that may not be skipped among tokens [0, i)
  std::vector<Cell> cells_;
  std::vector<DerivationPtr> pending_;
  std::vector<Floating> pending_floating_;
  std::vector<DerivationPtr> kids_;
  std::vector<sdk::Program> sems_;
  std::vector<int> tried_;  // per category: the span whose rules of that first category ran
  std::map<std::pair<std::string, std::string>, sdk::RulePtr> skip_rules_;
  ProgramIndex exact_programs_, floating_programs_;
  int span_stamp_ = 0;
  std::uint64_t built_ = 0;
  bool stopped_ = false;
};

}  // namespace

sdk::ParseResult parse_floating(const RuleIndex& index, const sdk::ParseRequest& request,
                                const Options& options) {
  return Run(index, request, options).run();
}

}  // namespace flipper::floating
