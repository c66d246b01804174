// The parse itself: spans by increasing length; per span every non-unary rule whose first symbol
// fits the span start (and that StartRules keeps: its later terminals occur after it) is matched
// symbol by symbol against the tokens and the (strictly smaller) chart cells inside the span, then
// unary rules run to a fixpoint. Cells keep at most `beam` derivations per category, best first by
// score (ties: creation order).
#include <algorithm>
#include <unordered_map>

#include "chart_parser.hpp"
#include "flipper/sdk/errors.hpp"
#include "start_rules.hpp"

namespace flipper::chart {

namespace {

using sdk::DerivationPtr;

struct CatCell {
  int cat;
  std::vector<DerivationPtr> ds;  // sorted by score desc, stable
};

struct Cell {
  std::vector<CatCell> cats;
  const CatCell* find(int cat) const {
    for (const auto& c : cats)
      if (c.cat == cat) return &c;
    return nullptr;
  }
  CatCell& get(int cat) {
    for (auto& c : cats)
      if (c.cat == cat) return c;
    cats.push_back({cat, {}});
    return cats.back();
  }
};

// Unary chains longer than this are cut (guards against cyclic unary rules).
constexpr int kMaxUnaryDepth = 24;

class Run {
 public:
  Run(const RuleIndex& index, const sdk::ParseRequest& req, int beam, bool exhaustive)
      : index_(index),
        req_(req),
        beam_(beam),
        n_(static_cast<int>(req.tokens.size())),
        token_ids_(index.token_ids(req.tokens)),
        classes_(index.classes(req.tokens)),
        starts_(index, token_ids_, classes_, req.visible, exhaustive) {
    ctx_ = req.context;
    if (ctx_.tokens == nullptr) ctx_.tokens = &req.tokens;
    // (n + 1)^2 cells in size_t: with int the index wraps at 65,535 tokens (do_parse bounds n).
    cells_.resize(static_cast<std::size_t>(n_ + 1) * static_cast<std::size_t>(n_ + 1));
    tried_.assign(index.category_count(), 0);
  }

  sdk::ParseResult run() {
    sdk::ParseResult out;
    const int last_len = req_.whole_span ? n_ : n_ - 1;
    for (int len = 1; len <= last_len && !stopped_; ++len)
      for (int i = 0; i + len <= n_ && !stopped_; ++i) fill(i, i + len);
    out.stopped = stopped_;
    out.derivations = built_;
    if (req_.whole_span && n_ > 0) collect_candidates(out);
    if (req_.want_chart) {
      for (int i = 0; i < n_; ++i)
        for (int j = i + 1; j <= n_; ++j) {
          if (i == 0 && j == n_) continue;
          for (const auto& cc : cell(i, j).cats)
            out.chart.insert(out.chart.end(), cc.ds.begin(), cc.ds.end());
        }
    }
    return out;
  }

 private:
  Cell& cell(int i, int j) {
    return cells_[static_cast<std::size_t>(i) * static_cast<std::size_t>(n_ + 1) +
                  static_cast<std::size_t>(j)];
  }

  // Matching can run long without building anything (deep nesting): poll the stop condition
  // every 1024 steps there too.
  bool poll() {
    if ((++steps_ & 1023u) == 0 && req_.stop.should_stop(built_)) stopped_ = true;
    return stopped_;
  }

  void fill(int i, int j) {
    pending_.clear();
    // Non-unary rules, selected by the first symbol at position i.
    if (token_ids_[i] >= 0)
      for (int r : starts_.at(i, FirstKind::token, token_ids_[i])) try_rule(r, i, j);
    for (int b = 0; b < 4; ++b)
      if (classes_[i] & (1 << b))
        for (int r : starts_.at(i, FirstKind::klass, b)) try_rule(r, i, j);
    // A category may be in several cells (i, e); its rules are tried once per span.
    ++span_stamp_;
    for (int e = i + 1; e < j; ++e)
      for (const auto& cc : cell(i, e).cats) {
        int& st = tried_[static_cast<std::size_t>(cc.cat)];
        if (st == span_stamp_) continue;
        st = span_stamp_;
        for (int r : starts_.at(i, FirstKind::category, cc.cat)) try_rule(r, i, j);
      }
    Cell& here = cell(i, j);
    std::vector<std::pair<DerivationPtr, int>> queue;
    for (auto& d : pending_)
      if (insert(here, d)) queue.emplace_back(d, 0);
    // Unary rules to a fixpoint.
    for (std::size_t q = 0; q < queue.size() && !stopped_; ++q) {
      auto [kid, depth] = queue[q];
      if (depth >= kMaxUnaryDepth) continue;
      const int cat = index_.category_id(kid->rule->lhs);
      for (int r : index_.unary_from(cat)) {
        if (!starts_.visible(r)) continue;
        kids_.assign(1, kid);
        auto d = build(r, i, j, {});
        if (d && insert(here, d)) queue.emplace_back(std::move(d), depth + 1);
      }
    }
  }

  // `r` comes from StartRules: alive and visible.
  void try_rule(int r, int i, int j) {
    const auto rhs = index_.rhs(r);
    if (static_cast<int>(rhs.size()) > j - i) return;
    // Cheap rejection: a final token must match the span's last token.
    const Sym& last = rhs.back();
    if (last.type == Sym::Type::token && token_ids_[j - 1] != last.id) return;
    if (last.type == Sym::Type::klass && !(classes_[j - 1] & last.id)) return;
    kids_.clear();
    match(r, rhs, 0, i, i, j);
  }

  void match(int r, std::span<const Sym> rhs, std::size_t k, int p, int i, int j) {
    if (poll()) return;
    const std::size_t nsym = rhs.size();
    if (k == nsym) {
      if (p == j) {
        auto d = build(r, i, j, req_.tokens[static_cast<std::size_t>(i)]);
        if (d) pending_.push_back(std::move(d));
      }
      return;
    }
    const int remaining = static_cast<int>(nsym - k);
    if (p + remaining > j) return;
    const Sym& s = rhs[k];
    switch (s.type) {
      case Sym::Type::token:
        if (token_ids_[p] == s.id) match(r, rhs, k + 1, p + 1, i, j);
        return;
      case Sym::Type::klass:
        if (classes_[p] & s.id) match(r, rhs, k + 1, p + 1, i, j);
        return;
      case Sym::Type::category: {
        const int e_min = k + 1 == nsym ? j : p + 1;
        const int e_max = j - (remaining - 1);
        for (int e = e_min; e <= e_max; ++e) {
          if (p == i && e == j) continue;  // whole span: only unary rules (fixpoint)
          const CatCell* cc = cell(p, e).find(s.id);
          if (cc == nullptr) continue;
          for (const auto& d : cc->ds) {
            kids_.push_back(d);
            match(r, rhs, k + 1, e, i, j);
            kids_.pop_back();
            if (stopped_) return;
          }
        }
        return;
      }
    }
  }

  DerivationPtr build(int r, int i, int j, std::string_view token) {
    if ((++built_ & 63) == 0 && req_.stop.should_stop(built_)) {
      stopped_ = true;
      return nullptr;
    }
    const CompiledRule& rule = index_.rules()[static_cast<std::size_t>(r)];
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

  bool insert(Cell& c, const DerivationPtr& d) {
    auto& list = c.get(index_.category_id(d->rule->lhs)).ds;
    if (static_cast<int>(list.size()) >= beam_ && d->score <= list.back()->score) return false;
    auto pos = std::upper_bound(list.begin(), list.end(), d->score,
                                [](double s, const DerivationPtr& x) { return s > x->score; });
    list.insert(pos, d);
    if (static_cast<int>(list.size()) > beam_) list.pop_back();
    return true;
  }

  void collect_candidates(sdk::ParseResult& out) {
    const CatCell* roots = cell(0, n_).find(index_.root());
    if (roots == nullptr) return;
    std::unordered_map<sdk::Program, std::size_t, sdk::ProgramHash, sdk::ProgramEqual> seen;
    for (const auto& d : roots->ds) {
      if (!sdk::loop_variables_bound(d->sem)) continue;
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
    // Core first, then score (desc), then the newest rule first; stable otherwise.
    std::stable_sort(out.candidates.begin(), out.candidates.end(),
                     [](const sdk::Candidate& a, const sdk::Candidate& b) {
                       if (a.core_only != b.core_only) return a.core_only;
                       if (a.score != b.score) return a.score > b.score;
                       return a.newest_rule > b.newest_rule;
                     });
  }

  const RuleIndex& index_;
  const sdk::ParseRequest& req_;
  const int beam_;
  const int n_;
  sdk::ScoreContext ctx_;
  const std::vector<int> token_ids_;
  const std::vector<std::uint8_t> classes_;
  StartRules starts_;
  std::vector<Cell> cells_;
  std::vector<DerivationPtr> pending_;
  std::vector<DerivationPtr> kids_;
  std::vector<sdk::Program> sems_;
  std::vector<int> tried_;  // per category: the span whose rules of that first category ran
  int span_stamp_ = 0;
  std::uint64_t built_ = 0;
  std::uint64_t steps_ = 0;
  bool stopped_ = false;
};

}  // namespace

sdk::ParseResult ChartParser::do_parse(const sdk::ParseRequest& request) const {
  if (request.scorer == nullptr)
    throw sdk::Error(sdk::codes::kBadRequest, "chart parser: the parse request has no scorer");
  const int beam = request.beam > 0 ? request.beam : beam_;
  if (request.tokens.empty()) return {};
  if (request.tokens.size() > max_tokens_)
    throw sdk::Error(sdk::codes::kInputTooLong,
                     "chart parser: " + std::to_string(request.tokens.size()) +
                         " tokens; the limit is max_tokens = " + std::to_string(max_tokens_));
  return Run(index_, request, beam, !rule_index_).run();
}

}  // namespace flipper::chart
