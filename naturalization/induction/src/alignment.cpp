// Alignment (docs/naturalization.md §4.8): a head that differs from a one-line body in one short
// stretch teaches a lexical rule for that stretch; the February 2018 runs' window alignment maps
// every head phrase whose neighbouring tokens are a body node's to that node's category.
#include <algorithm>
#include <optional>

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

/// The categories the February 2018 runs' alignment rules have (their logs show no other):
/// actions, areas and items, never a word's category ($Property, $ItemAct, ...).
bool is_window_category(const std::string& category) {
  return category == "$Action" || category == "$Area" || category == "$CountedItem" ||
         category == "$Item";
}

/// Every node of the derivation with its span, outermost first (pre-order).
void all_nodes(const sdk::DerivationPtr& d, std::vector<const sdk::Derivation*>& out) {
  if (!d) return;
  out.push_back(d.get());
  for (const auto& k : d->kids) all_nodes(k, out);
}

/// The token before `start` (or "" at the sentence's start) and at `end` (or "" at its end).
std::string token_at(const std::vector<std::string>& tokens, int i) {
  return i < 0 || i >= static_cast<int>(tokens.size()) ? std::string()
                                                       : tokens[static_cast<std::size_t>(i)];
}

/// The category a window-aligned node teaches, or "" when it teaches none: every statement
/// category, the grammar's root included, is $Action (§4.4).
std::string window_category(const sdk::Derivation& node) {
  if (!node.sem || sdk::has_holes(node.sem) || node.end <= node.start) return {};
  try {
    const std::string cat = node.category() == "$ROOT" ? category_of_sort(node.sem->sort)
                                                       : sdk::normalize_category(node.category());
    (void)sdk::category_sort(cat);  // not a private category
    return is_window_category(cat) ? cat : std::string();
  } catch (const std::exception&) {
    return {};
  }
}

/// Whether head [hs, he) stands where `node` stands in the body: the same token before (or both
/// at the start) and after (or both at the end), lengths within 2, not the node's own words.
bool window_fits(const std::vector<std::string>& head, const std::vector<std::string>& body,
                 const sdk::Derivation& node, int hs, int he) {
  const int n = static_cast<int>(head.size());
  const int m = static_cast<int>(body.size());
  if ((hs == 0) != (node.start == 0) || token_at(head, hs - 1) != token_at(body, node.start - 1))
    return false;
  if ((he == n) != (node.end == m) || token_at(head, he) != token_at(body, node.end)) return false;
  const int head_len = he - hs;
  const int body_len = node.end - node.start;
  if (std::abs(head_len - body_len) > kMaxLengthDifference) return false;
  return head_len != body_len ||
         !std::equal(head.begin() + hs, head.begin() + he, body.begin() + node.start);
}

/// The rule from head [hs, he) to `node`: its parts packed (§4.6) with the node's matches that
/// lie inside both the phrase and the node's body positions, as the 2018 code read the chart
/// (it kept the derivations inside the node's span, in head positions), never the whole phrase.
std::optional<sdk::Rule> window_rule(const std::vector<std::string>& head,
                                     const sdk::Derivation& node, const std::string& lhs,
                                     const std::vector<Match>& matches, int hs, int he) {
  std::vector<Match> inside;
  for (const auto& m : matches)
    if (m.start >= std::max(hs, node.start) && m.end <= std::min(he, node.end) &&
        m.end - m.start < he - hs) {
      Match shifted = m;
      shifted.start -= hs;
      shifted.end -= hs;
      inside.push_back(std::move(shifted));
    }
  const std::vector<std::string> tokens(head.begin() + hs, head.begin() + he);
  return build_rule(lhs, tokens, best_packing(inside, he - hs), node.sem,
                    sdk::RuleOrigin::alignment)
      .rule;
}

}  // namespace

std::vector<sdk::Rule> window_alignment_rules(const std::vector<std::string>& head,
                                              const std::vector<std::string>& body,
                                              const sdk::DerivationPtr& body_derivation,
                                              const std::vector<sdk::DerivationPtr>& head_chart,
                                              std::size_t max_rules) {
  const int n = static_cast<int>(head.size());
  std::vector<const sdk::Derivation*> nodes;
  all_nodes(body_derivation, nodes);
  std::vector<sdk::Rule> out;
  for (const auto* node : nodes) {
    const std::string lhs = window_category(*node);
    if (lhs.empty()) continue;
    std::optional<std::vector<Match>> matches;  // against the node's program, once per node
    for (int hs = 0; hs < n; ++hs)
      for (int he = hs + 1; he <= n; ++he) {
        if (!window_fits(head, body, *node, hs, he)) continue;
        if (!matches) matches = find_matches(head_chart, node->sem, n, false);
        auto rule = window_rule(head, *node, lhs, *matches, hs, he);
        if (!rule) continue;
        const bool again = std::any_of(out.begin(), out.end(), [&](const sdk::Rule& r) {
          return r.lhs == rule->lhs && r.rhs == rule->rhs;
        });
        if (again) continue;  // the same phrase for the same category (nested nodes)
        out.push_back(std::move(*rule));
        if (out.size() >= max_rules) return out;
      }
  }
  return out;
}

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
