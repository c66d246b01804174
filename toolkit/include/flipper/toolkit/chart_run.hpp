#pragma once
/// @file chart_run.hpp
/// One chart parse (docs/naturalization.md §2), the engine of the toolkit's chart parsers: spans
/// by increasing length; per span every non-unary rule whose first symbol fits the span start
/// (and that StartRules keeps: its later terminals occur after it) is matched symbol by symbol
/// against the tokens and the (strictly smaller) chart cells inside the span, then unary rules run
/// to a fixpoint. Cells keep at most `beam` derivations per category, best first by score (ties:
/// creation order). Candidates are the root derivations over the whole utterance, one per
/// program, core first, then by score, then the newest rule first.
///
/// `ChartRun<Derived>` is that parse; `Derived` (CRTP) may extend it through the hooks below, as
/// the `floating` parser adds derivations that leave words out (kept apart from the exact ones, so
/// the exact parse is never disturbed). `ExactChartRun` is the parse without extensions.
/// Hooks (a `Derived` member of the same name replaces the default, which does nothing):
/// - `begin_span(i, j)`: before the rules of span [i, j) are tried;
/// - `try_more_first_categories(i, j)`: after the rules whose first category is in an exact cell
///   (call try_first_category for others);
/// - `match_rule(r, rhs, i, j)`: matches rule r over [i, j) (default: exact symbol by symbol);
/// - `queue_more(i, j, queue)`: after the exact derivations of the span entered its cell;
/// - `insert_inexact(i, j, d, skips)`: keeps a unary derivation built over one that left `skips`
///   words out;
/// - `collect_candidates(out)`: the candidates (default: the exact roots, ordered).
#include <algorithm>
#include <cstdint>
#include <span>
#include <string_view>
#include <unordered_map>
#include <utility>
#include <vector>

#include "flipper/sdk/errors.hpp"
#include "flipper/sdk/parser.hpp"
#include "flipper/toolkit/rule_index.hpp"
#include "flipper/toolkit/start_rules.hpp"

namespace flipper::toolkit {

/// The derivations (or other entries) of one category in one span, best first.
template <class Entry>
struct CategoryList {
  int cat;
  std::vector<Entry> list;
};

/// The list of `cat` among `cats`, null when there is none.
template <class Entry>
const std::vector<Entry>* find_list(const std::vector<CategoryList<Entry>>& cats, int cat) {
  for (const auto& c : cats)
    if (c.cat == cat) return &c.list;
  return nullptr;
}
/// The list of `cat` among `cats`, appended when there is none.
template <class Entry>
std::vector<Entry>& list_for(std::vector<CategoryList<Entry>>& cats, int cat) {
  for (auto& c : cats)
    if (c.cat == cat) return c.list;
  cats.push_back({cat, {}});
  return cats.back().list;
}

/// Inserts `entry` into `list` (best first by score(entry), stable: among equal scores the
/// earlier stays first), keeping at most `beam` entries. False: the entry did not make the beam.
template <class Entry, class Score>
bool insert_in_beam(std::vector<Entry>& list, const Entry& entry, int beam, Score&& score) {
  const double s = score(entry);
  if (static_cast<int>(list.size()) >= beam && s <= score(list.back())) return false;
  auto pos = std::upper_bound(list.begin(), list.end(), s,
                              [&](double v, const Entry& x) { return v > score(x); });
  list.insert(pos, entry);
  if (static_cast<int>(list.size()) > beam) list.pop_back();
  return true;
}

/// Core first, then score (desc), then the newest rule first; stable otherwise
/// (docs/naturalization.md §2, "Order").
inline void order_candidates(std::vector<sdk::Candidate>& candidates) {
  std::stable_sort(candidates.begin(), candidates.end(),
                   [](const sdk::Candidate& a, const sdk::Candidate& b) {
                     if (a.core_only != b.core_only) return a.core_only;
                     if (a.score != b.score) return a.score > b.score;
                     return a.newest_rule > b.newest_rule;
                   });
}

/// Candidates by program: the index in ParseResult::candidates.
using ProgramIndex =
    std::unordered_map<sdk::Program, std::size_t, sdk::ProgramHash, sdk::ProgramEqual>;

/// Adds root derivation `d` to the candidate of its program (a new candidate, recorded in
/// `seen`, when there is none); a program with an unbound loop variable is no candidate.
inline void add_candidate(sdk::ParseResult& out, ProgramIndex& seen, const sdk::DerivationPtr& d) {
  if (!sdk::loop_variables_bound(d->sem)) return;
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

template <class Derived>
class ChartRun {
 public:
  using Rhs = std::span<const Sym>;
  /// An entry of the unary fixpoint's queue: a derivation of the span, how many unary rules
  /// built it, the words it leaves out (0: exact) and its category (the rule's CompiledRule::lhs:
  /// no lookup of the name per derivation).
  struct Queued {
    sdk::DerivationPtr d;
    int depth, skips, cat;
  };

  /// `exhaustive`: try every rule whose first symbol fits (the unindexed matcher, the oracle of
  /// the rule index).
  ChartRun(const RuleIndex& index, const sdk::ParseRequest& req, int beam, bool exhaustive)
      : index_(index),
        req_(req),
        beam_(beam),
        n_(static_cast<int>(req.tokens.size())),
        token_ids_(index.token_ids(req.tokens)),
        classes_(index.classes(req.tokens)),
        starts_(index, token_ids_, classes_, req.visible, exhaustive) {
    ctx_ = req.context;
    if (ctx_.tokens == nullptr) ctx_.tokens = &req.tokens;
    cells_.resize(cell_count());
    tried_.assign(index.category_count(), 0);
  }

  sdk::ParseResult run() {
    sdk::ParseResult out;
    const int last_len = req_.whole_span ? n_ : n_ - 1;
    for (int len = 1; len <= last_len && !stopped_; ++len)
      for (int i = 0; i + len <= n_ && !stopped_; ++i) fill(i, i + len);
    if (req_.whole_span && n_ > 0) self().collect_candidates(out);
    out.stopped = stopped_;
    out.derivations = built_;
    if (req_.want_chart) {  // exact derivations only: the head chart of induction
      for (int i = 0; i < n_; ++i)
        for (int j = i + 1; j <= n_; ++j) {
          if (i == 0 && j == n_) continue;
          for (const auto& cc : cell(i, j))
            out.chart.insert(out.chart.end(), cc.list.begin(), cc.list.end());
        }
    }
    return out;
  }

 protected:
  using Cell = std::vector<CategoryList<sdk::DerivationPtr>>;  ///< the exact derivations

  Derived& self() { return static_cast<Derived&>(*this); }

  // --- hooks: the exact parse ---
  void begin_span(int, int) {}
  void try_more_first_categories(int, int) {}
  void queue_more(int, int, std::vector<Queued>&) {}
  bool insert_inexact(int, int, const sdk::DerivationPtr&, int) { return false; }
  void match_rule(int r, Rhs rhs, int i, int j) { match(r, rhs, 0, i, i, j); }
  void collect_candidates(sdk::ParseResult& out) {
    collect_exact_roots(out);
    order_candidates(out.candidates);
  }

  // --- for Derived ---
  // One cell per span [i, j), 0 <= i < j <= n, by end then start: n (n + 1) / 2 cells (a
  // square of (n + 1)^2 would be over half empty, and for 6 tokens or more an allocation of over
  // 1 KiB per parse, which makes glibc's malloc consolidate its fast bins: ~7k instructions, a
  // tenth of a short query). In size_t: with int the index wraps at 65,535 tokens (parsers bound
  // n).
  std::size_t cell_count() const {
    const auto n = static_cast<std::size_t>(n_);
    return n * (n + 1) / 2;
  }
  std::size_t cell_index(int i, int j) const {
    const auto end = static_cast<std::size_t>(j);
    return end * (end - 1) / 2 + static_cast<std::size_t>(i);
  }
  Cell& cell(int i, int j) { return cells_[cell_index(i, j)]; }

  /// Tries, once per span, the rules whose first symbol is category `cat` over [i, j).
  void try_first_category(int cat, int i, int j) {
    int& st = tried_[static_cast<std::size_t>(cat)];
    if (st == span_stamp_) return;
    st = span_stamp_;
    for (int r : starts_.at(i, FirstKind::category, cat)) try_rule(r, i, j);
  }

  /// Rule r has been matched over [i, j) with `kids_`: its derivation joins the span's.
  void complete(int r, int i, int j) {
    auto d = build(r, i, j, req_.tokens[static_cast<std::size_t>(i)]);
    if (d) pending_.push_back({std::move(d), 0, 0, lhs_of(r)});
  }

  /// The category id of rule r's left-hand side.
  int lhs_of(int r) const { return index_.rules()[static_cast<std::size_t>(r)].lhs; }

  /// Whether token p fits a terminal (token or class) symbol.
  bool fits(const Sym& s, int p) const {
    const auto at = static_cast<std::size_t>(p);
    return s.type == Sym::Type::token ? token_ids_[at] == s.id : (classes_[at] & s.id) != 0;
  }

  /// One more derivation built; false (and the parse stops) when the stop condition fired. The
  /// derivation budget (work) is checked every 64, the time limits every 1024 (reading a CPU
  /// clock is a syscall, a few µs in a sandbox).
  bool count_built() {
    if ((++built_ & 63) == 0 &&
        (built_ >= req_.stop.max_expansions || ((built_ & 1023u) == 0 && req_.stop.expired()))) {
      stopped_ = true;
      return false;
    }
    return true;
  }

  /// The derivation of rule r over [i, j) from `kids_`, scored; null when stopped or when a kid
  /// has the wrong sort (then it is no derivation).
  sdk::DerivationPtr build(int r, int i, int j, std::string_view token) {
    if (!count_built()) return nullptr;
    const CompiledRule& rule = index_.rules()[static_cast<std::size_t>(r)];
    sems_.clear();
    for (const sdk::DerivationPtr* k : kids_) sems_.push_back((*k)->sem);
    sdk::Program sem;
    try {
      sem = sdk::apply_rule(*rule.rule, sems_, token);
    } catch (const sdk::Error&) {
      return nullptr;
    }
    auto d = std::make_shared<sdk::Derivation>();
    d->rule = rule.rule;
    d->start = i;
    d->end = j;
    d->kids.reserve(kids_.size());
    for (const sdk::DerivationPtr* k : kids_) d->kids.push_back(*k);
    d->sem = std::move(sem);
    d->core_only = !rule.rule->induced;
    d->newest_rule = rule.rule->induced ? rule.rule->created : 0;
    double kid_score = 0;
    for (const auto& k : d->kids) {
      d->core_only = d->core_only && k->core_only;
      d->newest_rule = std::max(d->newest_rule, k->newest_rule);
      kid_score += k->score;
    }
    d->score = req_.scorer->score_node(*d, ctx_) + kid_score;
    return d;
  }

  bool insert_exact(int i, int j, const sdk::DerivationPtr& d, int cat) {
    return insert_in_beam(list_for(cell(i, j), cat), d, beam_,
                          [](const sdk::DerivationPtr& x) { return x->score; });
  }

  /// The exact root derivations as candidates.
  void collect_exact_roots(sdk::ParseResult& out) {
    if (const auto* roots = find_list(cell(0, n_), index_.root()))
      for (const auto& d : *roots) add_candidate(out, exact_programs_, d);
  }

  const RuleIndex& index_;
  const sdk::ParseRequest& req_;
  const int beam_;
  const int n_;
  sdk::ScoreContext ctx_;
  const std::vector<int> token_ids_;
  const std::vector<std::uint8_t> classes_;
  StartRules starts_;
  /// The kids matched so far, by address: each points into a cell's list (the cells of shorter
  /// spans, which no match of this span changes) or at a derivation a caller keeps alive until
  /// the match returns. A derivation copies them once it is built; matching itself copies no
  /// shared_ptr (the reference counts' atomic increments and decrements on every partial match
  /// were a quarter of a parse with many rules).
  std::vector<const sdk::DerivationPtr*> kids_;
  ProgramIndex exact_programs_;  ///< the candidates of exact root derivations
  std::uint64_t built_ = 0;
  bool stopped_ = false;

 private:
  void fill(int i, int j) {
    pending_.clear();
    self().begin_span(i, j);
    // Non-unary rules, selected by the first symbol at position i.
    if (token_ids_[i] >= 0)
      for (int r : starts_.at(i, FirstKind::token, token_ids_[i])) try_rule(r, i, j);
    for (int b = 0; b < 4; ++b)
      if (classes_[i] & (1 << b))
        for (int r : starts_.at(i, FirstKind::klass, b)) try_rule(r, i, j);
    // A category may be in several cells (i, e); its rules are tried once per span.
    ++span_stamp_;
    for (int e = i + 1; e < j; ++e)
      for (const auto& cc : cell(i, e)) try_first_category(cc.cat, i, j);
    self().try_more_first_categories(i, j);
    std::vector<Queued>& queue = queue_;
    queue.clear();
    for (auto& p : pending_)
      if (insert_exact(i, j, p.d, p.cat)) queue.push_back(p);
    self().queue_more(i, j, queue);
    // Unary rules to a fixpoint.
    for (std::size_t q = 0; q < queue.size() && !stopped_; ++q) {
      const Queued item = queue[q];
      if (item.depth >= kMaxUnaryDepth) continue;
      for (int r : index_.unary_from(item.cat)) {
        if (!starts_.visible(r)) continue;
        kids_.assign(1, &item.d);
        auto d = build(r, i, j, {});
        if (!d) continue;
        const int cat = lhs_of(r);
        const bool kept = item.skips == 0 ? insert_exact(i, j, d, cat)
                                          : self().insert_inexact(i, j, d, item.skips);
        if (kept) queue.push_back({std::move(d), item.depth + 1, item.skips, cat});
      }
    }
  }

  // `r` comes from StartRules: alive and visible.
  void try_rule(int r, int i, int j) {
    const auto rhs = index_.rhs(r);
    if (static_cast<int>(rhs.size()) > j - i) return;
    // Cheap rejection: a final terminal must match the span's last token.
    const Sym& last = rhs.back();
    if (last.type != Sym::Type::category && !fits(last, j - 1)) return;
    kids_.clear();
    self().match_rule(r, rhs, i, j);
  }

  // Matching can run long without building anything (deep nesting): poll the stop condition
  // every 1024 steps there too.
  bool poll() {
    if ((++steps_ & 1023u) == 0 && req_.stop.should_stop(built_)) stopped_ = true;
    return stopped_;
  }

  // Symbol k of rule r at position p, the span being [i, j).
  void match(int r, Rhs rhs, std::size_t k, int p, int i, int j) {
    if (poll()) return;
    const std::size_t nsym = rhs.size();
    if (k == nsym) {
      if (p == j) complete(r, i, j);
      return;
    }
    const int remaining = static_cast<int>(nsym - k);
    if (p + remaining > j) return;
    const Sym& s = rhs[k];
    if (s.type != Sym::Type::category) {
      if (fits(s, p)) match(r, rhs, k + 1, p + 1, i, j);
      return;
    }
    const int e_min = k + 1 == nsym ? j : p + 1;
    const int e_max = j - (remaining - 1);
    for (int e = e_min; e <= e_max; ++e) {
      if (p == i && e == j) continue;  // whole span: only unary rules (fixpoint)
      const auto* ds = find_list(cell(p, e), s.id);
      if (ds == nullptr) continue;
      for (const auto& d : *ds) {
        kids_.push_back(&d);
        match(r, rhs, k + 1, e, i, j);
        kids_.pop_back();
        if (stopped_) return;
      }
    }
  }

  // Unary chains longer than this are cut (guards against cyclic unary rules).
  static constexpr int kMaxUnaryDepth = 24;

  std::vector<Cell> cells_;
  std::vector<Queued> pending_;  ///< exact derivations of the span being filled (depth 0)
  std::vector<Queued> queue_;    ///< the unary fixpoint's queue of the span being filled
  std::vector<sdk::Program> sems_;
  std::vector<int> tried_;  ///< per category: the span whose rules of that first category ran
  int span_stamp_ = 0;
  std::uint64_t steps_ = 0;
};

/// The chart parse without extensions.
class ExactChartRun : public ChartRun<ExactChartRun> {
 public:
  using ChartRun::ChartRun;
};

}  // namespace flipper::toolkit
