// The checks of plugin answers (docs/plugins-untrusted.md): planners' paths and tours, parsers'
// candidates and scores, scorers' weights read from a saved state. One implementation for the
// kernel, the benchmarks and the kits.
#include "flipper/sdk/answer_check.hpp"

#include <algorithm>
#include <array>
#include <cmath>
#include <sstream>
#include <unordered_set>

#include "flipper/sdk/ast.hpp"
#include "flipper/sdk/errors.hpp"
#include "flipper/sdk/parser.hpp"
#include "flipper/sdk/planner.hpp"
#include "flipper/sdk/scorer.hpp"
#include "node_check.hpp"

namespace flipper::sdk {
inline namespace FLIPPER_ABI_NAMESPACE {

namespace {

std::string cell_text(const Geometry& g, Cell c) {
  return to_string(c, g.dims());
}

std::string number_text(double v) {
  std::ostringstream s;
  s << v;
  return s.str();
}

// The nodes or derivations already checked (a shared subtree is checked once): a scan of a small
// array while there are few, as for most parses (no allocation), a hash set beyond.
class SeenSet {
 public:
  /// False when `p` was seen before.
  bool insert(const void* p) {
    if (spilled_) return more_.insert(p).second;
    for (std::size_t i = 0; i < count_; ++i)
      if (few_[i] == p) return false;
    if (count_ < few_.size()) {
      few_[count_++] = p;
      return true;
    }
    more_.insert(few_.begin(), few_.end());
    spilled_ = true;
    return more_.insert(p).second;
  }

 private:
  std::array<const void*, 48> few_{};
  std::size_t count_ = 0;
  bool spilled_ = false;
  std::unordered_set<const void*> more_;
};

bool is_leaf(Kind k) {
  using K = Kind;
  return k == K::Num || k == K::Direction || k == K::Color || k == K::Shape || k == K::Room ||
         k == K::ItemAct || k == K::Hole;
}

// Whether `n` is a tree `make` would build: every node present, of its kind's sort, with the
// arity and kid sorts its kind takes (make's own checks, node by node, without building one).
// Shared subtrees are checked once.
std::optional<std::string> program_violation(const Node* n, SeenSet& seen) {
  if (n == nullptr) return "a missing (null) program node";
  if (!seen.insert(n)) return std::nullopt;
  if (n->kind == Kind::Hole) return "a template hole where a program was expected";
  if (n->sort != sort_of(n->kind))
    return std::string("a ") + kind_name(n->kind) + " node of sort " + sort_name(n->sort);
  if (is_leaf(n->kind)) {
    if (!n->kids.empty()) return std::string("a ") + kind_name(n->kind) + " leaf with operands";
    if (n->kind == Kind::Num && !std::isfinite(n->number)) return "a number that is not finite";
    return std::nullopt;
  }
  for (const Program& k : n->kids)
    if (auto v = program_violation(k.get(), seen)) return v;
  try {
    detail::check_operands(n->kind, n->kids);
  } catch (const Error& e) {
    return std::string("a malformed ") + kind_name(n->kind) + " node (" + e.what() + ")";
  }
  return std::nullopt;
}

// A derivation (and its kids): spans within [lo, hi] of the utterance, finite scores.
std::optional<Violation> derivation_violation(const Derivation* d, int lo, int hi, SeenSet& seen) {
  using codes::kInvalidCandidate;
  if (d == nullptr || d->rule == nullptr)
    return Violation{kInvalidCandidate, "a missing (null) derivation or rule"};
  if (d->start < lo || d->end > hi || d->start > d->end)
    return Violation{kInvalidCandidate, "a derivation spans tokens [" + std::to_string(d->start) +
                                            ", " + std::to_string(d->end) + "), outside [" +
                                            std::to_string(lo) + ", " + std::to_string(hi) + ")"};
  if (!std::isfinite(d->score))
    return Violation{codes::kInvalidScore, "a derivation over tokens [" + std::to_string(d->start) +
                                               ", " + std::to_string(d->end) + ") has the score " +
                                               number_text(d->score)};
  if (!seen.insert(d)) return std::nullopt;
  for (const DerivationPtr& k : d->kids)
    if (auto v = derivation_violation(k.get(), d->start, d->end, seen)) return v;
  return std::nullopt;
}

}  // namespace

std::optional<std::string> path_violation(const Geometry& g, const PathRequest& req,
                                          const PathResult& r) {
  if (r.status != PlanStatus::found) return std::nullopt;
  const auto& steps = g.neighbour_offsets();
  Cell at = req.start;
  for (std::size_t i = 0; i < r.path.size(); ++i) {
    const Cell next = r.path[i];
    const std::string step = "step " + std::to_string(i + 1);
    if (!g.in_bounds(next)) return step + " leaves the world at " + cell_text(g, next);
    const Cell offset{next.x - at.x, next.y - at.y, next.z - at.z};
    if (std::find(steps.begin(), steps.end(), offset) == steps.end())
      return step + " jumps from " + cell_text(g, at) + " to " + cell_text(g, next) +
             ", which is not a neighbour";
    if (!g.is_free(next)) return step + " enters wall " + cell_text(g, next);
    if (req.avoid != nullptr && next != req.start && areas::contains(*req.avoid, next))
      return step + " enters " + cell_text(g, next) + ", which the request avoids";
    at = next;
  }
  if (at != r.target)
    return "the path ends at " + cell_text(g, at) + ", not at the target it reports, " +
           cell_text(g, r.target);
  if (req.goals == nullptr || !areas::contains(*req.goals, r.target) || !g.is_free(r.target))
    return "the path ends at " + cell_text(g, r.target) + ", which is not a goal of the request";
  return std::nullopt;
}

std::optional<std::string> tour_violation(std::size_t points, const TourResult& t) {
  if (t.status != PlanStatus::found) return std::nullopt;
  std::vector<bool> used(points, false);
  bool permutation = t.order.size() == points;
  for (std::size_t k : t.order) {
    if (!permutation) break;
    if (k >= points || used[k])
      permutation = false;
    else
      used[k] = true;
  }
  if (permutation) return std::nullopt;
  std::string order;
  for (std::size_t i = 0; i < t.order.size() && i < 16; ++i)
    order += (i == 0 ? "" : ",") + std::to_string(t.order[i]);
  if (t.order.size() > 16) order += ",...";
  return "the tour order [" + order + "] is not a permutation of the " + std::to_string(points) +
         " points asked";
}

std::optional<Violation> parse_violation(const ParseRequest& req, const ParseResult& r) {
  const int n = static_cast<int>(req.tokens.size());
  SeenSet nodes;
  SeenSet derivations;
  for (std::size_t i = 0; i < r.candidates.size(); ++i) {
    const Candidate& c = r.candidates[i];
    const std::string which = "candidate " + std::to_string(i);
    if (!std::isfinite(c.score))
      return Violation{codes::kInvalidScore, which + " has the score " + number_text(c.score)};
    if (auto v = program_violation(c.program.get(), nodes))
      return Violation{codes::kInvalidCandidate, which + " is not a program: " + *v};
    if (c.program->sort != Sort::Action)
      return Violation{codes::kInvalidCandidate,
                       which + " is a " + sort_name(c.program->sort) + ", not a statement"};
    if (!loop_variables_bound(c.program))
      return Violation{codes::kInvalidCandidate,
                       which + " uses 'point' or 'area' outside a loop (core-language §3.7)"};
    for (const DerivationPtr& d : c.derivations) {
      if (d && req.whole_span && (d->start != 0 || d->end != n))
        return Violation{codes::kInvalidCandidate,
                         which + " has a derivation over tokens [" + std::to_string(d->start) +
                             ", " + std::to_string(d->end) + "), not the whole utterance [0, " +
                             std::to_string(n) + ")"};
      if (auto v = derivation_violation(d.get(), 0, n, derivations))
        return Violation{v->code, which + ": " + v->what};
    }
  }
  for (const DerivationPtr& d : r.chart)
    if (auto v = derivation_violation(d.get(), 0, n, derivations))
      return Violation{v->code, "the chart: " + v->what};
  return std::nullopt;
}

std::optional<std::string> state_weights_violation(std::size_t state_bytes,
                                                   const std::vector<WeightChange>& weights) {
  if (weights.size() > state_bytes)
    return std::to_string(weights.size()) + " weights read from a saved state of " +
           std::to_string(state_bytes) + " bytes (at most one per byte)";
  for (const auto& w : weights)
    if (!std::isfinite(w.weight) || !std::isfinite(w.aux))
      return "the weight '" + w.feature + "' of partition '" + w.model +
             "' read from a saved state is " + number_text(w.weight) + " (aux " +
             number_text(w.aux) + "), not a finite number";
  return std::nullopt;
}

}  // namespace FLIPPER_ABI_NAMESPACE
}  // namespace flipper::sdk
