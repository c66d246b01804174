// Planner benchmark experiment files (docs/planners.md §5).
#include "flipper/planbench/experiment.hpp"

#include <yaml-cpp/yaml.h>

#include <algorithm>
#include <filesystem>

#include "flipper/replay/experiment.hpp"
#include "flipper/sdk/errors.hpp"
#include "flipper/wiring/yaml_file.hpp"

namespace flipper::planbench {
namespace {

using replay::resolve_in_file;

[[noreturn]] void bad(const std::string& where, const std::string& what) {
  throw sdk::Error(sdk::codes::kBadConfig, where + what);
}

void only_keys(const YAML::Node& map, const std::vector<std::string>& known,
               const std::string& where) {
  if (!map.IsMap()) bad(where, "must be a map");
  for (const auto& kv : map) {
    const auto key = kv.first.as<std::string>();
    if (std::find(known.begin(), known.end(), key) != known.end()) continue;
    std::string list;
    for (const auto& k : known) list += (list.empty() ? "" : ", ") + k;
    bad(where, "unknown key '" + key + "' (keys: " + list + ")");
  }
}

// A plugin's params as --set text: YAML flow style ("{resolution: 1, body: box}").
std::string flow_text(const YAML::Node& node, const std::string& where) {
  if (!node || node.IsNull()) return "";
  if (!node.IsMap()) bad(where, "'params' must be a map of the plugin's params");
  YAML::Emitter out;
  out << YAML::Flow << node;
  return out.c_str();
}

std::string required_text(const YAML::Node& node, const std::string& key,
                          const std::string& where) {
  if (!node[key] || !node[key].IsScalar() || node[key].Scalar().empty())
    bad(where, "needs '" + key + "'");
  return node[key].Scalar();
}

// A label is a column value and part of a variant's name: letters, digits, '.', '_', '-', '+'.
void check_label(const std::string& label, const std::string& where) {
  const bool ok =
      !label.empty() && label.size() <= 60 && std::all_of(label.begin(), label.end(), [](char c) {
        return std::isalnum(static_cast<unsigned char>(c)) || c == '.' || c == '_' || c == '-' ||
               c == '+';
      });
  if (!ok)
    bad(where, "name '" + label +
                   "' must be 1-60 letters, digits, '.', '_', '-' or '+' (it labels rows and "
                   "plots)");
}

TaskSource task_source(const std::string& file, const YAML::Node& node, const std::string& where) {
  only_keys(node, {"random", "seed", "file"}, where);
  TaskSource t{0, 1, ""};
  if (node["file"]) {
    if (node["random"]) bad(where, "give either 'random' or 'file', not both");
    t.file = resolve_in_file(file, node["file"].as<std::string>());
    return t;
  }
  if (!node["random"]) bad(where, "needs 'random: N' (random tasks) or 'file: F' (a task file)");
  t.random = node["random"].as<int>();
  if (t.random < 1 || t.random > 100000) bad(where, "'random' must be in [1, 100000]");
  if (node["seed"]) t.seed = node["seed"].as<std::uint64_t>();
  return t;
}

}  // namespace

BenchExperiment load_bench_experiment(const std::string& path) {
  BenchExperiment e;
  e.file = std::filesystem::absolute(path).lexically_normal().string();
  const YAML::Node root = wiring::load_bounded_yaml_file(path, "experiment file");
  const std::string where = "experiment file '" + path + "': ";
  try {
    only_keys(root,
              {"name", "config", "set", "plugin_paths", "seeds", "repetitions", "cpu_budget_ms",
               "deadline_ms", "kill_after_s", "tasks", "worlds", "planners"},
              where);
    e.name = root["name"] ? root["name"].as<std::string>() : "planner benchmark";
    if (root["config"] && !root["config"].as<std::string>().empty())
      e.config = resolve_in_file(path, root["config"].as<std::string>());
    if (root["set"]) e.sets = root["set"].as<std::vector<std::string>>();
    if (root["plugin_paths"])
      for (const auto& p : root["plugin_paths"].as<std::vector<std::string>>())
        e.plugin_paths.push_back(resolve_in_file(path, p));
    if (root["seeds"]) {
      e.seeds = root["seeds"].as<std::vector<std::uint64_t>>();
      if (e.seeds.empty()) bad(where, "'seeds' must list at least one seed");
      for (std::size_t i = 0; i < e.seeds.size(); ++i)
        for (std::size_t j = 0; j < i; ++j)
          if (e.seeds[i] == e.seeds[j])
            bad(where, "'seeds' lists " + std::to_string(e.seeds[i]) + " twice");
    }
    if (root["repetitions"]) e.repetitions = root["repetitions"].as<int>();
    if (e.repetitions < 1 || e.repetitions > 1000) bad(where, "'repetitions' must be in [1, 1000]");
    if (root["deadline_ms"]) e.deadline_ms = root["deadline_ms"].as<std::int64_t>();
    if (e.deadline_ms < 1) bad(where, "'deadline_ms' must be at least 1");
    if (root["cpu_budget_ms"]) e.cpu_budget_ms = root["cpu_budget_ms"].as<std::int64_t>();
    if (e.cpu_budget_ms < 1) bad(where, "'cpu_budget_ms' must be at least 1");
    if (root["kill_after_s"]) e.kill_after_s = root["kill_after_s"].as<int>();
    if (e.kill_after_s < 1 || e.kill_after_s > 86400)
      bad(where, "'kill_after_s' must be in [1, 86400]");
    if (root["tasks"]) e.tasks = task_source(path, root["tasks"], where + "'tasks' ");

    const YAML::Node worlds = root["worlds"], planners = root["planners"];
    if (!worlds || !worlds.IsSequence() || worlds.size() == 0)
      bad(where, "'worlds' must list at least one world: {name, plugin, file, params, tasks}");
    if (!planners || !planners.IsSequence() || planners.size() == 0)
      bad(where, "'planners' must list at least one planner: {name, plugin, params}");
    for (std::size_t i = 0; i < worlds.size(); ++i) {
      const std::string at = where + "world " + std::to_string(i + 1) + " ";
      only_keys(worlds[i], {"name", "plugin", "file", "params", "tasks"}, at);
      WorldSpec w;
      w.plugin = required_text(worlds[i], "plugin", at);
      w.name = worlds[i]["name"] ? worlds[i]["name"].as<std::string>() : w.plugin;
      check_label(w.name, at);
      w.file = resolve_in_file(path, required_text(worlds[i], "file", at));
      w.params = flow_text(worlds[i]["params"], at);
      if (worlds[i]["tasks"]) w.tasks = task_source(path, worlds[i]["tasks"], at + "'tasks' ");
      for (const auto& other : e.worlds)
        if (other.name == w.name) bad(at, "two worlds are named '" + w.name + "'");
      e.worlds.push_back(std::move(w));
    }
    for (std::size_t i = 0; i < planners.size(); ++i) {
      const std::string at = where + "planner " + std::to_string(i + 1) + " ";
      only_keys(planners[i], {"name", "plugin", "params"}, at);
      PlannerSpec p;
      p.plugin = required_text(planners[i], "plugin", at);
      p.name = planners[i]["name"] ? planners[i]["name"].as<std::string>() : p.plugin;
      check_label(p.name, at);
      p.params = flow_text(planners[i]["params"], at);
      for (const auto& other : e.planners)
        if (other.name == p.name)
          bad(at, "two planners are named '" + p.name + "' (give each a 'name')");
      e.planners.push_back(std::move(p));
    }
  } catch (const YAML::Exception& ex) {
    throw sdk::Error(sdk::codes::kBadConfig, where + ex.what());
  }
  return e;
}

nlohmann::json experiment_json(const BenchExperiment& e) {
  auto source = [](const TaskSource& t) {
    return t.file.empty() ? nlohmann::json{{"random", t.random}, {"seed", t.seed}}
                          : nlohmann::json{{"file", t.file}};
  };
  nlohmann::json worlds = nlohmann::json::array(), planners = nlohmann::json::array();
  for (const auto& w : e.worlds) {
    nlohmann::json j{
        {"name", w.name}, {"plugin", w.plugin}, {"file", w.file}, {"params", w.params}};
    if (w.tasks) j["tasks"] = source(*w.tasks);
    worlds.push_back(std::move(j));
  }
  for (const auto& p : e.planners)
    planners.push_back({{"name", p.name}, {"plugin", p.plugin}, {"params", p.params}});
  return {{"file", e.file},
          {"name", e.name},
          {"config", e.config},
          {"set", e.sets},
          {"plugin_paths", e.plugin_paths},
          {"seeds", e.seeds},
          {"repetitions", e.repetitions},
          {"cpu_budget_ms", e.cpu_budget_ms},
          {"deadline_ms", e.deadline_ms},
          {"kill_after_s", e.kill_after_s},
          {"tasks", source(e.tasks)},
          {"worlds", worlds},
          {"planners", planners}};
}

}  // namespace flipper::planbench
