// The `perceptron` scorer: an averaged structured perceptron over the features of the loglinear
// scorer (docs/naturalization.md §3, shared through flipper_scoring_features).
//
// On an accept, the model's prediction is the highest-scoring derivation of the query (scores as
// computed at parse time; ties: the first in candidate order). If it yields the accepted program,
// nothing changes; otherwise w += rate · (φ(accepted) − φ(predicted)), with φ summed over every
// node of the accepted program's best derivation and of the predicted derivation. Scores use the
// averaged weights w − u/c (Daumé's lazy averaging: u += c · Δ on every update, c counts the
// accepts learnt from, starting at 1), i.e. the mean of the weight vectors after every accept.
#include <cmath>
#include <nlohmann/json.hpp>
#include <unordered_map>

#include "features.hpp"
#include "flipper/sdk/canonical.hpp"
#include "flipper/sdk/errors.hpp"
#include "flipper/sdk/plugin.hpp"

namespace flipper::perceptron {

namespace {

constexpr const char* kFormat = "flipper.perceptron/1";

struct Weight {
  double w = 0;  // current weight
  double u = 0;  // Σ c · Δ over updates (for the average)
};

struct Model {
  std::unordered_map<std::uint64_t, Weight> weights;
  features::FeatureNames names;
  double c = 1;  // 1 + number of accepts learnt from
  double averaged(const Weight& x) const { return x.w - x.u / c; }
};

}  // namespace

class Perceptron : public sdk::Scorer {
 public:
  explicit Perceptron(const sdk::Params& p) {
    if (p.has("rate")) rate_ = p.get_double("rate");
    if (p.has("per_user")) per_user_ = p.get_bool("per_user");
  }

  static sdk::ParamSchema schema() {
    sdk::ParamSchema s;
    s.add_double("rate", 1.0, "size of a perceptron update", 0.0, 100.0);
    s.add_bool("per_user", false, "keep one weight vector per user instead of a global one");
    return s;
  }

 protected:
  double do_score_node(const sdk::Derivation& node, const sdk::ScoreContext& ctx) const override {
    const double s = node.core_only ? 1.0 : 0.0;
    const Model* m = model_for(ctx);
    if (m == nullptr || m->weights.empty()) return s;
    return features::weighted_sum(s, node, ctx, [&](std::uint64_t key) {
      auto it = m->weights.find(key);
      return it == m->weights.end() ? 0.0 : m->averaged(it->second);
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
                       "perceptron: accepted index " + std::to_string(accepted) +
                           " out of range (" + std::to_string(candidates.size()) + " candidates)");
    const sdk::Candidate& gold = candidates[accepted];
    if (gold.derivations.empty()) return;
    const sdk::Derivation* predicted = nullptr;
    bool predicted_is_gold = false;
    for (std::size_t ci = 0; ci < candidates.size(); ++ci)
      for (const auto& d : candidates[ci].derivations)
        if (predicted == nullptr || d->score > predicted->score) {
          predicted = d.get();
          predicted_is_gold = ci == accepted;
        }
    Model& m = model_for_update(ctx);
    if (predicted != nullptr && !predicted_is_gold && !sdk::equal(predicted->sem, gold.program)) {
      features::SparseVector delta;
      features::add_tree_features(*best_derivation(gold), ctx, rate_, delta, m.names);
      features::add_tree_features(*predicted, ctx, -rate_, delta, m.names);
      for (const auto& [key, d] : delta) {
        if (d == 0) continue;
        Weight& w = m.weights[key];
        w.w += d;
        w.u += m.c * d;
      }
    }
    m.c += 1;
  }

  std::string do_save_state() const override {
    nlohmann::json j;
    j["format"] = kFormat;
    j["per_user"] = per_user_;
    nlohmann::json models = nlohmann::json::object();
    for (const auto& [user, m] : models_) {
      nlohmann::json ws = nlohmann::json::object();
      for (const auto& [key, w] : m.weights) {
        auto name = m.names.find(key);
        if (name != m.names.end()) ws[name->second] = {w.w, w.u};
      }
      models[user] = {{"c", m.c}, {"weights", std::move(ws)}};
    }
    j["models"] = std::move(models);
    return j.dump();
  }

  void do_load_state(std::string_view state) override {
    std::unordered_map<std::string, Model> loaded;
    try {
      const auto j = nlohmann::json::parse(state);
      if (j.value("format", "") != kFormat)
        throw sdk::Error(sdk::codes::kBadConfig,
                         std::string("perceptron: unknown state format (want ") + kFormat + ")");
      for (const auto& [user, jm] : j.at("models").items()) {
        Model& m = loaded[user];
        m.c = jm.at("c").get<double>();
        if (!(m.c >= 1) || !std::isfinite(m.c))
          throw sdk::Error(sdk::codes::kBadConfig, "perceptron: bad counter c in the state");
        for (const auto& [name, v] : jm.at("weights").items()) {
          const auto key = features::feature_key(name);
          m.weights[key] = {v.at(0).get<double>(), v.at(1).get<double>()};
          m.names[key] = name;
        }
      }
    } catch (const nlohmann::json::exception& e) {
      throw sdk::Error(sdk::codes::kBadConfig,
                       std::string("perceptron: unreadable state: ") + e.what());
    }
    models_ = std::move(loaded);
  }

 private:
  // The accepted program's highest-scoring derivation (the first of equals).
  static const sdk::Derivation* best_derivation(const sdk::Candidate& c) {
    const sdk::Derivation* best = nullptr;
    for (const auto& d : c.derivations)
      if (best == nullptr || d->score > best->score) best = d.get();
    return best;
  }
  const Model* model_for(const sdk::ScoreContext& ctx) const {
    auto it = models_.find(per_user_ ? ctx.user : std::string());
    return it == models_.end() ? nullptr : &it->second;
  }
  Model& model_for_update(const sdk::ScoreContext& ctx) {
    return models_[per_user_ ? ctx.user : std::string()];
  }

  double rate_ = 1.0;
  bool per_user_ = false;
  std::unordered_map<std::string, Model> models_;  // key: user ("" when global)
};

}  // namespace flipper::perceptron

FLIPPER_PLUGIN(flipper::perceptron::Perceptron, scorer, "perceptron", FLIPPER_PLUGIN_VERSION,
               "Averaged structured perceptron over the loglinear features")
