#pragma once
// The features of one derivation node (docs/naturalization.md §3), written once for two sinks: a
// hashing sink (score_node: no strings built, each feature name hashed part by part with FNV-1a)
// and a naming sink (features(), learning: the readable name, whose FNV-1a hash is the same key).
// Part of the toolkit (docs/architecture.md §2): every scorer built on it (loglinear, perceptron,
// through linear_model.hpp) sees the same features.
#include <cstdint>
#include <initializer_list>
#include <string>
#include <string_view>
#include <unordered_map>

#include "flipper/sdk/scorer.hpp"

namespace flipper::toolkit::features {

using Parts = std::initializer_list<std::string_view>;

constexpr std::uint64_t kFnvOffset = 1469598103934665603ULL;
constexpr std::uint64_t kFnvPrime = 1099511628211ULL;

inline std::uint64_t fnv(std::uint64_t h, std::string_view s) {
  for (unsigned char c : s) h = (h ^ c) * kFnvPrime;
  return h;
}

/// Feature key of a name: FNV-1a of its bytes.
inline std::uint64_t feature_key(std::string_view name) {
  return fnv(kFnvOffset, name);
}

/// Calls sink(parts, value) for every feature of `node`; the name is the concatenation of parts.
template <class Sink>
void for_each_feature(const sdk::Derivation& node, const sdk::ScoreContext& ctx, Sink&& sink) {
  const sdk::Rule& rule = *node.rule;
  const std::string& cat = rule.lhs;
  sink({"rule=", rule.id}, 1.0);
  sink({"fired"}, 1.0);
  if (!rule.induced) {
    sink({"core"}, 1.0);
  } else {
    sink({"induced"}, 1.0);
    const sdk::RuleUses uses = ctx.usage != nullptr ? ctx.usage->uses(rule.id) : sdk::RuleUses{};
    const auto others = uses.by_others;
    const auto own = uses.by_author;
    if (others > 0) sink({"uses_by_others"}, static_cast<double>(others));
    sink({others > 0 ? "used_by_others=yes" : "used_by_others=no"}, 1.0);
    sink({own > 0 ? "used_by_author=yes" : "used_by_author=no"}, 1.0);
    sink({rule.how == sdk::RuleOrigin::alignment ? "alignment=yes" : "alignment=no"}, 1.0);
  }
  if (!rule.author.empty()) {
    sink({"author=", rule.author}, 1.0);
    sink({"author_user=", rule.author, ",", ctx.user}, 1.0);
    sink({rule.author == ctx.user ? "self=yes" : "self=no"}, 1.0);
  }
  if (ctx.tokens == nullptr || node.end <= node.start) return;
  const auto& t = *ctx.tokens;
  const int n = static_cast<int>(t.size());
  if (node.end > n) return;
  auto tok = [&](int i) -> std::string_view {
    if (i < 0) return "^";
    if (i >= n) return "$";
    return t[static_cast<std::size_t>(i)];
  };
  const std::string len = std::to_string(node.end - node.start);
  sink({"cat_len=", cat, ",", len}, 1.0);
  sink({"cat_span=", cat, ",", tok(node.start), "...", tok(node.end - 1)}, 1.0);
  sink({"ctx1=", tok(node.start - 1), ",", cat, ",", tok(node.end)}, 1.0);
  sink({"ctx2=", tok(node.start - 2), " ", tok(node.start - 1), ",", cat, ",", tok(node.end), " ",
        tok(node.end + 1)},
       1.0);
}

/// start + w·φ(node) for a weight lookup `weight(key) -> double` (0 for unknown keys), summed in
/// feature order; no strings built.
template <class Lookup>
double weighted_sum(double start, const sdk::Derivation& node, const sdk::ScoreContext& ctx,
                    Lookup&& weight) {
  double s = start;
  for_each_feature(node, ctx, [&](Parts parts, double value) {
    std::uint64_t h = kFnvOffset;
    for (auto p : parts) h = fnv(h, p);
    s += weight(h) * value;
  });
  return s;
}

/// The concatenation of a feature name's parts.
std::string join(Parts parts);

/// The named features of one node (Scorer::features).
void node_features(const sdk::Derivation& node, const sdk::ScoreContext& ctx,
                   sdk::FeatureVector& out);

/// Sparse vectors keyed by feature_key(name), and the names seen (for saving state by name).
using SparseVector = std::unordered_map<std::uint64_t, double>;
using FeatureNames = std::unordered_map<std::uint64_t, std::string>;

/// Adds coef * φ(d), φ summed over every node of the tree, to `out`, recording names in `names`.
void add_tree_features(const sdk::Derivation& d, const sdk::ScoreContext& ctx, double coef,
                       SparseVector& out, FeatureNames& names);

}  // namespace flipper::toolkit::features
