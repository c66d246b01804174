#include "flipper/toolkit/linear_model.hpp"

#include <cmath>
#include <functional>
#include <nlohmann/json.hpp>

#include "flipper/sdk/errors.hpp"

namespace flipper::toolkit {

namespace {

const std::uint64_t kAcceptsKey = features::feature_key(kAcceptsFeature);

std::string prefix(const LinearStateFormat& f) {
  return std::string(f.plugin) + ": ";
}

// Calls f(partition, feature name, weight now, weight before) for each weight changed since the
// last commit that the model still holds: what pending_changes and pending_values report.
template <class Partitions, class Pending, class F>
void for_each_pending(const Partitions& partitions, const Pending& pending, F f) {
  for (const auto& [k, before] : pending) {
    const auto m = partitions.find(k.partition);
    if (m == partitions.end()) continue;
    const auto w = m->second.weights.find(k.key);
    const auto name = m->second.names.find(k.key);
    if (w == m->second.weights.end() || name == m->second.names.end()) continue;
    f(k.partition, name->second, w->second, before.value);
  }
}

}  // namespace

const LinearPartition* LinearModel::find(const sdk::ScoreContext& ctx) const {
  auto it = partitions_.find(partition_name(ctx));
  return it == partitions_.end() ? nullptr : &it->second;
}

LinearPartition& LinearModel::partition(const sdk::ScoreContext& ctx) {
  return partitions_[partition_name(ctx)];
}

void LinearModel::add_tree_features(const sdk::Derivation& d, const sdk::ScoreContext& ctx,
                                    double coef, features::SparseVector& out) {
  features::add_tree_features(d, ctx, coef, out, partition(ctx).names);
}

LinearWeight& LinearModel::change(const sdk::ScoreContext& ctx, std::uint64_t key) {
  return change(partition_name(ctx), key);
}

LinearWeight& LinearModel::change(std::string name, std::uint64_t key) {
  LinearPartition& m = partitions_[name];
  auto found = m.weights.find(key);
  if (found == m.weights.end()) {
    pending_.try_emplace(PendingKey{std::move(name), key}, Before{LinearWeight{}, false});
    found = m.weights.emplace(key, LinearWeight{}).first;
  } else {
    pending_.try_emplace(PendingKey{std::move(name), key}, Before{found->second, true});
  }
  return found->second;
}

void LinearModel::count_accept(const sdk::ScoreContext& ctx) {
  partition(ctx).names.try_emplace(kAcceptsKey, std::string(kAcceptsFeature));
  change(ctx, kAcceptsKey).w += 1;
}

double LinearModel::accepts(const LinearPartition& m) {
  const LinearWeight* w = m.find(kAcceptsKey);
  return w == nullptr ? 0.0 : w->w;
}

std::vector<sdk::WeightChange> LinearModel::pending_changes() const {
  std::vector<sdk::WeightChange> out;
  for_each_pending(partitions_, pending_,
                   [&](const std::string& partition, const std::string& name,
                       const LinearWeight& now, const LinearWeight& before) {
                     const double dw = now.w - before.w, daux = now.aux - before.aux;
                     if (dw != 0 || daux != 0) out.push_back({partition, name, dw, daux});
                   });
  return out;
}

std::vector<sdk::WeightChange> LinearModel::pending_values() const {
  std::vector<sdk::WeightChange> out;
  for_each_pending(partitions_, pending_,
                   [&](const std::string& partition, const std::string& name,
                       const LinearWeight& now, const LinearWeight&) {
                     out.push_back({partition, name, now.w, now.aux});
                   });
  return out;
}

void LinearModel::set_values(const std::vector<sdk::WeightChange>& values) {
  for (const auto& v : values) {
    const auto key = features::feature_key(v.feature);
    partitions_[v.model].names[key] = v.feature;
    change(v.model, key) = {v.weight, v.aux};
  }
}

void LinearModel::discard_changes() {
  for (const auto& [k, before] : pending_) {
    auto& weights = partitions_[k.partition].weights;
    if (before.existed)
      weights[k.key] = before.value;
    else
      weights.erase(k.key);
  }
  pending_.clear();
}

void LinearModel::apply_changes(const std::vector<sdk::WeightChange>& changes) {
  for (const auto& c : changes) {
    LinearPartition& m = partitions_[c.model];
    const auto key = features::feature_key(c.feature);
    LinearWeight& w = m.weights[key];
    w.w += c.weight;
    w.aux += c.aux;
    m.names[key] = c.feature;
  }
}

std::string LinearModel::save_state(const LinearStateFormat& format) const {
  nlohmann::json j;
  j["format"] = format.format;
  j["per_user"] = per_user_;
  nlohmann::json partitions = nlohmann::json::object();
  for (const auto& [user, m] : partitions_) {
    if (m.weights.empty()) continue;  // a partition that never learnt is no state
    nlohmann::json ws = nlohmann::json::object();
    for (const auto& [key, w] : m.weights) {
      if (key == kAcceptsKey && !format.counter.empty()) continue;
      auto name = m.names.find(key);
      if (name != m.names.end()) ws[name->second] = {w.w, w.aux};
    }
    if (format.counter.empty())
      partitions[user] = std::move(ws);
    else
      partitions[user] = {{std::string(format.counter), 1 + accepts(m)},
                          {"weights", std::move(ws)}};
  }
  j["models"] = std::move(partitions);
  return j.dump();
}

namespace {

// Reads a saved state of `format`: f(partition, name, weight) for every weight, a partition's
// counter c > 1 as the weight kAcceptsFeature = c - 1 first (the counter counts 1 + accepts),
// then its weights in name order. Error(bad_config) naming the plugin when the text is not such
// a state; f may have been called by then.
using WeightRead =
    std::function<void(const std::string& partition, const std::string& name, LinearWeight w)>;
void read_state(std::string_view state, const LinearStateFormat& format, const WeightRead& f) {
  try {
    const auto j = nlohmann::json::parse(state);
    if (j.value("format", "") != format.format)
      throw sdk::Error(sdk::codes::kBadConfig, prefix(format) + "unknown state format (want " +
                                                   std::string(format.format) + ")");
    for (const auto& [user, jm] : j.at("models").items()) {
      const nlohmann::json* ws = &jm;
      if (!format.counter.empty()) {
        const double c = jm.at(std::string(format.counter)).get<double>();
        if (!(c >= 1) || !std::isfinite(c))
          throw sdk::Error(
              sdk::codes::kBadConfig,
              prefix(format) + "bad counter " + std::string(format.counter) + " in the state");
        if (c > 1) f(user, std::string(kAcceptsFeature), LinearWeight{c - 1, 0});
        ws = &jm.at("weights");
      }
      for (const auto& [name, v] : ws->items())
        f(user, name, LinearWeight{v.at(0).get<double>(), v.at(1).get<double>()});
    }
  } catch (const nlohmann::json::exception& e) {
    throw sdk::Error(sdk::codes::kBadConfig, prefix(format) + "unreadable state: " + e.what());
  }
}

}  // namespace

void LinearModel::load_state(std::string_view state, const LinearStateFormat& format) {
  std::unordered_map<std::string, LinearPartition> loaded;
  read_state(state, format, [&](const std::string& user, const std::string& name, LinearWeight w) {
    LinearPartition& m = loaded[user];
    const auto key = features::feature_key(name);
    m.weights[key] = w;
    m.names[key] = name;
  });
  partitions_ = std::move(loaded);
  pending_.clear();
}

std::optional<std::vector<sdk::WeightChange>> LinearModel::state_weights(
    std::string_view state, const LinearStateFormat& format) {
  std::vector<sdk::WeightChange> out;
  try {
    read_state(state, format,
               [&](const std::string& user, const std::string& name, LinearWeight w) {
                 out.push_back({user, name, w.w, w.aux});
               });
  } catch (const sdk::Error&) {
    return std::nullopt;
  }
  return out;
}

}  // namespace flipper::toolkit
