#include "flipper/toolkit/features.hpp"

namespace flipper::toolkit::features {

std::string join(Parts parts) {
  std::string s;
  for (auto p : parts) s.append(p);
  return s;
}

void node_features(const sdk::Derivation& node, const sdk::ScoreContext& ctx,
                   sdk::FeatureVector& out) {
  for_each_feature(node, ctx,
                   [&](Parts parts, double value) { out.emplace_back(join(parts), value); });
}

void add_tree_features(const sdk::Derivation& d, const sdk::ScoreContext& ctx, double coef,
                       SparseVector& out, FeatureNames& names) {
  for_each_feature(d, ctx, [&](Parts parts, double value) {
    std::string name = join(parts);
    const auto key = feature_key(name);
    out[key] += coef * value;
    names.try_emplace(key, std::move(name));
  });
  for (const auto& k : d.kids) add_tree_features(*k, ctx, coef, out, names);
}

}  // namespace flipper::toolkit::features
