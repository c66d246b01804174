// Alignment (docs/naturalization.md §4.8, after the February 2018 code): a head that differs from a
// one-line body in one short stretch teaches a lexical rule for that stretch.
#include <algorithm>

#include "flipper/naturalization/induction.hpp"

namespace flipper::naturalization {

namespace {

constexpr int kMaxHeadStretch = 5;
constexpr int kMaxLengthDifference = 2;

/// The deepest node covering [start, end) whose category has a sort.
const sdk::Derivation* deepest_covering(const sdk::DerivationPtr& d, int start, int end) {
  if (!d || d->start > start || d->end < end) return nullptr;
  for (const auto& k : d->kids)
    if (const auto* inner = deepest_covering(k, start, end)) return inner;
  try {
    (void)sdk::category_sort(d->category());
  } catch (const std::exception&) {
    return nullptr;
  }
  return d.get();
}

/// When no body node spans the stretch exactly (`drop` in `drop item` has no node of its own):
/// a rule for the smallest node around it, its kids outside the stretch kept as categories,
/// e.g. `throw item` := `drop item` gives `$Action -> throw $CountedItem => {drop $1}`.
std::vector<sdk::Rule> covering_rule(const std::vector<std::string>& head, int prefix, int suffix,
                                     int body_len, const sdk::DerivationPtr& body_derivation) {
  const int m = prefix + body_len + suffix;
  const auto* node = deepest_covering(body_derivation, prefix, m - suffix);
  if (!node || !node->sem || sdk::has_holes(node->sem)) return {};
  const int shift = static_cast<int>(head.size()) - m;  // body -> head positions after the stretch
  const int head_start = node->start;
  const int head_end = node->end + shift;
  std::vector<std::string> tokens(head.begin() + head_start, head.begin() + head_end);
  std::vector<Match> packing;
  for (const auto& k : node->kids) {
    const bool outside = k->end <= prefix || k->start >= m - suffix;
    if (!outside || !k->sem) continue;
    const std::string cat = sdk::normalize_category(k->category());
    if (!category_fits(cat, k->sem->sort)) continue;
    const int off = k->start >= m - suffix ? shift : 0;
    packing.push_back({k->start + off - head_start, k->end + off - head_start, cat, k->sem,
                       k->score, k->core_only});
  }
  BuiltRule built =
      build_rule(node->category(), tokens, packing, node->sem, sdk::RuleOrigin::alignment);
  if (!built.rule) return {};
  return {std::move(*built.rule)};
}

/// Nodes of the derivation spanning exactly [start, end), outermost first.
void nodes_spanning(const sdk::DerivationPtr& d, int start, int end,
                    std::vector<const sdk::Derivation*>& out) {
  if (!d || d->end <= start || d->start >= end) return;
  if (d->start == start && d->end == end) out.push_back(d.get());
  for (const auto& k : d->kids) nodes_spanning(k, start, end, out);
}

}  // namespace

std::vector<sdk::Rule> alignment_rules(const std::vector<std::string>& head,
                                       const std::vector<std::string>& body,
                                       const sdk::DerivationPtr& body_derivation,
                                       std::size_t max_rules) {
  const int n = static_cast<int>(head.size());
  const int m = static_cast<int>(body.size());
  int prefix = 0;
  while (prefix < n && prefix < m && head[prefix] == body[prefix]) ++prefix;
  int suffix = 0;
  while (suffix < n - prefix && suffix < m - prefix && head[n - 1 - suffix] == body[m - 1 - suffix])
    ++suffix;
  const int head_len = n - prefix - suffix;
  const int body_len = m - prefix - suffix;
  // One differing stretch, anchored by at least one shared token before or after it.
  if (head_len < 1 || body_len < 1 || prefix + suffix < 1) return {};
  if (head_len > kMaxHeadStretch || std::abs(head_len - body_len) > kMaxLengthDifference) return {};

  std::vector<const sdk::Derivation*> nodes;
  nodes_spanning(body_derivation, prefix, m - suffix, nodes);
  if (nodes.empty()) return covering_rule(head, prefix, suffix, body_len, body_derivation);
  std::vector<sdk::Rule> out;
  for (const auto* node : nodes) {
    if (out.size() >= max_rules) break;
    if (!node->sem || sdk::has_holes(node->sem)) continue;
    try {
      (void)sdk::category_sort(node->category());  // not $ROOT or a private category
    } catch (const std::exception&) {
      continue;
    }
    const bool seen = std::any_of(out.begin(), out.end(),
                                  [&](const sdk::Rule& r) { return r.lhs == node->category(); });
    if (seen) continue;
    sdk::Rule rule;
    rule.lhs = node->category();
    for (int i = prefix; i < n - suffix; ++i)
      rule.rhs.push_back({sdk::Symbol::Type::token, head[static_cast<std::size_t>(i)]});
    rule.sem = node->sem;
    rule.induced = true;
    rule.how = sdk::RuleOrigin::alignment;
    out.push_back(std::move(rule));
  }
  return out;
}

}  // namespace flipper::naturalization
