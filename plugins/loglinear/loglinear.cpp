// The `loglinear` scorer: sparse linear model over node features, AdaGrad + L1 learning on
// accept, marginalised over the derivations of the accepted program (docs/naturalization.md §3).
#include <cmath>
#include <map>
#include <nlohmann/json.hpp>
#include <unordered_map>

#include "features.hpp"
#include "flipper/sdk/errors.hpp"
#include "flipper/sdk/plugin.hpp"

namespace flipper::loglinear {

namespace {

using features::feature_key;

struct Weight {
  double w = 0;
  double G = 0;  // AdaGrad: running sum of squared gradients
};

struct Model {
  std::unordered_map<std::uint64_t, Weight> weights;
  features::FeatureNames names;
};

}  // namespace

// Also an IncrementalScorer (SDK 1.2): learn() remembers each touched weight's value from before
// the first pending change, so the kernel persists only changed weights and can undo exactly.
class LogLinear : public sdk::Scorer, public sdk::IncrementalScorer {
 public:
  explicit LogLinear(const sdk::Params& p) {
    if (p.has("step")) step_ = p.get_double("step");
    if (p.has("l1")) l1_ = p.get_double("l1");
    if (p.has("per_user")) per_user_ = p.get_bool("per_user");
  }

  static sdk::ParamSchema schema() {
    sdk::ParamSchema s;
    s.add_double("step", 0.1, "AdaGrad step size", 0.0, 100.0);
    s.add_double("l1", 1e-4, "L1 regularisation strength (scaled by the AdaGrad step)", 0.0, 1.0);
    s.add_bool("per_user", false, "keep one weight vector per user instead of a global one");
    return s;
  }

 protected:
  double do_score_node(const sdk::Derivation& node, const sdk::ScoreContext& ctx) const override {
    double s = node.core_only ? 1.0 : 0.0;
    const Model* m = model_for(ctx);
    if (m == nullptr || m->weights.empty()) return s;
    return features::weighted_sum(s, node, ctx, [&](std::uint64_t key) {
      auto it = m->weights.find(key);
      return it == m->weights.end() ? 0.0 : it->second.w;
    });
  }

  void do_features(const sdk::Derivation& node, const sdk::ScoreContext& ctx,
                   sdk::FeatureVector& out) const override {
    features::node_features(node, ctx, out);
  }

  void do_learn(const std::vector<sdk::Candidate>& candidates, std::size_t accepted,
                const sdk::ScoreContext& ctx) override {
    if (accepted >= candidates.size())
      throw sdk::Error(sdk::codes::kBadRequest,
                       "loglinear: accepted index " + std::to_string(accepted) + " out of range (" +
                           std::to_string(candidates.size()) + " candidates)");
    // Softmax over every derivation of every candidate (model) and over the accepted program's
    // derivations only (target); scores as computed at parse time.
    double max_score = -INFINITY;
    for (const auto& c : candidates)
      for (const auto& d : c.derivations) max_score = std::max(max_score, d->score);
    if (!std::isfinite(max_score)) return;
    double z_model = 0, z_target = 0;
    for (std::size_t ci = 0; ci < candidates.size(); ++ci)
      for (const auto& d : candidates[ci].derivations) {
        const double e = std::exp(d->score - max_score);
        z_model += e;
        if (ci == accepted) z_target += e;
      }
    if (z_target <= 0) return;
    Model& m = model_for_update(ctx);
    features::SparseVector grad;
    for (std::size_t ci = 0; ci < candidates.size(); ++ci)
      for (const auto& d : candidates[ci].derivations) {
        const double e = std::exp(d->score - max_score);
        const double coef = (ci == accepted ? e / z_target : 0.0) - e / z_model;
        if (coef == 0) continue;
        features::add_tree_features(*d, ctx, coef, grad, m.names);
      }
    const std::string model = per_user_ ? ctx.user : std::string();
    for (const auto& [key, g] : grad) {
      if (g == 0) continue;
      auto found = m.weights.find(key);
      if (found == m.weights.end()) {
        pending_.try_emplace(PendingKey{model, key}, Before{Weight{}, false});
        found = m.weights.emplace(key, Weight{}).first;
      } else {
        pending_.try_emplace(PendingKey{model, key}, Before{found->second, true});
      }
      Weight& w = found->second;
      w.G += g * g;
      const double rate = step_ / std::sqrt(w.G + 1.0);
      w.w += rate * g;
      const double shrink = rate * l1_;
      w.w = w.w > 0 ? std::max(0.0, w.w - shrink) : std::min(0.0, w.w + shrink);
    }
  }

  std::string do_save_state() const override {
    nlohmann::json j;
    j["format"] = "flipper.loglinear/1";
    j["per_user"] = per_user_;
    nlohmann::json models = nlohmann::json::object();
    for (const auto& [user, m] : models_) {
      if (m.weights.empty()) continue;  // a model that never learned is no state
      nlohmann::json ws = nlohmann::json::object();
      for (const auto& [key, w] : m.weights) {
        auto name = m.names.find(key);
        if (name == m.names.end()) continue;
        ws[name->second] = {w.w, w.G};
      }
      models[user] = std::move(ws);
    }
    j["models"] = std::move(models);
    return j.dump();
  }

  std::vector<sdk::WeightChange> do_pending_changes() const override {
    std::vector<sdk::WeightChange> out;
    for (const auto& [k, before] : pending_) {
      auto m = models_.find(k.model);
      if (m == models_.end()) continue;
      auto w = m->second.weights.find(k.key);
      auto name = m->second.names.find(k.key);
      if (w == m->second.weights.end() || name == m->second.names.end()) continue;
      const double dw = w->second.w - before.value.w, dg = w->second.G - before.value.G;
      if (dw != 0 || dg != 0) out.push_back({k.model, name->second, dw, dg});
    }
    return out;
  }
  void do_commit_changes() override { pending_.clear(); }
  void do_discard_changes() override {
    for (const auto& [k, before] : pending_) {
      auto& weights = models_[k.model].weights;
      if (before.existed)
        weights[k.key] = before.value;
      else
        weights.erase(k.key);
    }
    pending_.clear();
  }
  void do_apply_changes(const std::vector<sdk::WeightChange>& changes) override {
    for (const auto& c : changes) {
      Model& m = models_[c.model];
      const auto key = feature_key(c.feature);
      Weight& w = m.weights[key];
      w.w += c.weight;
      w.G += c.aux;
      m.names[key] = c.feature;
    }
  }

  void do_load_state(std::string_view state) override {
    std::unordered_map<std::string, Model> loaded;
    try {
      const auto j = nlohmann::json::parse(state);
      if (j.value("format", "") != "flipper.loglinear/1")
        throw sdk::Error(sdk::codes::kBadConfig, "loglinear: unknown state format");
      for (const auto& [user, ws] : j.at("models").items()) {
        Model& m = loaded[user];
        for (const auto& [name, v] : ws.items()) {
          const auto key = feature_key(name);
          m.weights[key] = {v.at(0).get<double>(), v.at(1).get<double>()};
          m.names[key] = name;
        }
      }
    } catch (const nlohmann::json::exception& e) {
      throw sdk::Error(sdk::codes::kBadConfig,
                       std::string("loglinear: unreadable state: ") + e.what());
    }
    models_ = std::move(loaded);
    pending_.clear();
  }

 private:
  const Model* model_for(const sdk::ScoreContext& ctx) const {
    auto it = models_.find(per_user_ ? ctx.user : std::string());
    return it == models_.end() ? nullptr : &it->second;
  }
  Model& model_for_update(const sdk::ScoreContext& ctx) {
    return models_[per_user_ ? ctx.user : std::string()];
  }

  double step_ = 0.1;
  double l1_ = 1e-4;
  bool per_user_ = false;
  std::unordered_map<std::string, Model> models_;  // key: user ("" when global)
  struct PendingKey {
    std::string model;
    std::uint64_t key;
    bool operator<(const PendingKey& o) const {
      return key != o.key ? key < o.key : model < o.model;
    }
  };
  struct Before {
    Weight value;
    bool existed = false;
  };
  std::map<PendingKey, Before> pending_;  // weights changed since the last commit, values before
};

}  // namespace flipper::loglinear

FLIPPER_PLUGIN(flipper::loglinear::LogLinear, scorer, "loglinear", "1.0.0",
               "Log-linear ranking model with AdaGrad + L1 learning on accept")
