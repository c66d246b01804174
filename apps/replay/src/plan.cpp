// The variants of an experiment: hand-written variants × sweep points (experiment.hpp).
#include <map>
#include <set>

#include "flipper/kernel/config.hpp"
#include "flipper/kernel/loader.hpp"
#include "flipper/record/run_folder.hpp"
#include "flipper/replay/experiment.hpp"
#include "flipper/sdk/errors.hpp"
#include "flipper/wiring/config_schema.hpp"

namespace flipper::replay {
namespace {

// "planner.params.seed" -> {"planner", "seed"}; {} for keys that are no plugin parameter.
std::pair<std::string, std::string> plugin_param(const std::string& key) {
  const auto dot = key.find('.');
  if (dot == std::string::npos) return {};
  const std::string section = key.substr(0, dot);
  const std::string rest = key.substr(dot + 1);
  const auto& sections = kernel::Config::plugin_sections();
  if (std::find(sections.begin(), sections.end(), section) == sections.end()) return {};
  if (rest.rfind("params.", 0) != 0) return {};
  const std::string name = rest.substr(7, rest.find('.', 7) - 7);
  return {section, name};
}

// Which parameters each plugin declares, asked once per plugin.
class DeclaredParams {
 public:
  bool declares(const kernel::Config& config, const std::string& section,
                const std::string& param) {
    const std::string plugin = config.plugin_name(section);
    auto it = cache_.find({section, plugin});
    if (it == cache_.end()) {
      const kernel::PluginLoader loader(kernel::PluginLoader::search_path_for(config));
      sdk::PluginKind kind{};
      sdk::parse_kind(section.c_str(), kind);
      std::set<std::string> names;
      for (const auto& spec : loader.open(plugin, kind).schema().params) names.insert(spec.name);
      it = cache_.emplace(std::make_pair(section, plugin), std::move(names)).first;
    }
    return it->second.count(param) != 0;
  }

 private:
  std::map<std::pair<std::string, std::string>, std::set<std::string>> cache_;
};

}  // namespace

std::vector<PlannedVariant> plan_variants(const Experiment& e) {
  std::vector<ExperimentVariant> hand = e.variants;
  const bool named = !hand.empty();
  if (!named) hand.push_back({e.sweep.empty() ? "plain" : "", {}});
  const auto points = record::expand_grid(e.sweep);
  DeclaredParams declared;
  std::map<std::string, int> applied;  // sweep key -> variants it applied to

  std::vector<PlannedVariant> out;
  std::set<std::string> directories;
  for (const auto& v : hand)
    for (const auto& point : points) {
      PlannedVariant p;
      const std::string point_text = record::point_name(point);
      p.info.name = v.name.empty()       ? point_text
                    : point_text.empty() ? v.name
                                         : v.name + "," + point_text;
      p.sets = e.sets;
      p.sets.insert(p.sets.end(), v.sets.begin(), v.sets.end());
      // The point's plugin choices first, so a parameter is checked against the plugin this
      // variant really selects.
      std::vector<std::string> with_choices = p.sets;
      for (const auto& [key, value] : point)
        if (plugin_param(key).first.empty()) with_choices.push_back(key + "=" + value);
      const kernel::Config config = wiring::load_config(e.config, with_choices);
      for (const auto& [key, value] : point) {
        const auto [section, param] = plugin_param(key);
        if (!section.empty() && config.has_section(section) &&
            !declared.declares(config, section, param)) {
          p.notes.push_back("sweep setting `" + key + "=" + value + "` left out: plugin '" +
                            config.plugin_name(section) + "' (" + section +
                            ") declares no parameter '" + param + "'");
          continue;
        }
        ++applied[key];
        p.sets.push_back(key + "=" + value);
      }
      // The condition is the name without the seed settings: the variants whose spread over
      // seeds is taken together.
      std::vector<record::Assignment> rest;
      for (const auto& a : point)
        if (!record::is_seed_key(a.first)) rest.push_back(a);
      const std::string rest_text = record::point_name(rest);
      p.info.condition = v.name.empty()      ? (rest_text.empty() ? "all" : rest_text)
                         : rest_text.empty() ? v.name
                                             : v.name + "," + rest_text;
      for (const auto& a : point)
        if (record::is_seed_key(a.first))
          p.info.seed += (p.info.seed.empty() ? "" : ",") + a.first + "=" + a.second;
      p.info.directory = record::directory_name(p.info.name);
      if (!directories.insert(p.info.directory).second)
        throw sdk::Error(sdk::codes::kBadConfig, "experiment '" + e.name +
                                                     "': two variants share the folder name '" +
                                                     p.info.directory + "' (rename a variant)");
      out.push_back(std::move(p));
    }
  for (const auto& axis : e.sweep) {
    const auto [section, param] = plugin_param(axis.key);
    if (!section.empty() && applied[axis.key] == 0)
      throw sdk::Error(sdk::codes::kBadConfig, "experiment '" + e.name + "': sweep key '" +
                                                   axis.key + "': no variant's " + section +
                                                   " plugin declares a parameter '" + param +
                                                   "' (flipper plugins --params lists them)");
  }
  return out;
}

}  // namespace flipper::replay
