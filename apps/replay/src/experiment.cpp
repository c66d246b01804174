// Experiment files, and the experiment as a manifest records it.
#include "flipper/replay/experiment.hpp"

#include <yaml-cpp/yaml.h>

#include <algorithm>
#include <cctype>
#include <filesystem>

#include "flipper/sdk/errors.hpp"
#include "flipper/wiring/yaml_file.hpp"

namespace flipper::replay {
namespace fs = std::filesystem;

std::string resolve_in_file(const std::string& file, const std::string& path) {
  if (path.empty() || fs::path(path).is_absolute()) return path;
  // The directory the file really is in: reached through a link (configs/ -> the repository's),
  // `../` still means the file's own parent.
  std::error_code ec;
  fs::path dir = fs::weakly_canonical(fs::absolute(file), ec).parent_path();
  if (ec) dir = fs::absolute(file).parent_path();
  return (dir / path).lexically_normal().string();
}

namespace {

std::vector<std::string> string_list(const YAML::Node& node, const std::string& where) {
  std::vector<std::string> out;
  if (!node) return out;
  if (!node.IsSequence())
    throw sdk::Error(sdk::codes::kBadConfig, where + " must be a list of strings");
  for (const auto& n : node) out.push_back(n.as<std::string>());
  return out;
}

// A variant's name is a directory under --out: one path component of letters, digits, '.', '_',
// '-', '+' and '=', so `../../x` or `/etc` cannot write outside --out.
void check_variant_name(const std::string& name, const std::string& where) {
  const bool ok = !name.empty() && name != "." && name != ".." && name.size() <= 100 &&
                  std::all_of(name.begin(), name.end(), [](char c) {
                    return std::isalnum(static_cast<unsigned char>(c)) || c == '.' || c == '_' ||
                           c == '+' || c == '=' || c == '-';
                  });
  if (!ok)
    throw sdk::Error(
        sdk::codes::kBadConfig,
        where + "variant name '" + name +
            "' must be one directory name (letters, digits, '.', '_', '-', '+', '='; not '.' "
            "or '..'; at most 100 characters): it names the output folder under --out");
}

// A sweep value as `--set` text: a scalar as written, a list or map in YAML flow style.
std::string set_text(const YAML::Node& value) {
  if (value.IsScalar()) return value.Scalar();
  YAML::Emitter out;
  out << YAML::Flow << value;
  return out.c_str();
}

std::vector<record::SweepAxis> sweep_axes(const YAML::Node& sweep, const std::string& where) {
  if (!sweep.IsMap())
    throw sdk::Error(sdk::codes::kBadConfig,
                     where +
                         "'sweep' must be a map from config keys to lists of values, e.g. "
                         "{planner.params.seed: [1, 2, 3]}");
  std::vector<record::SweepAxis> axes;
  for (const auto& kv : sweep) {
    record::SweepAxis axis{kv.first.as<std::string>(), {}};
    if (kv.second.IsSequence()) {
      for (const auto& v : kv.second) axis.values.push_back(set_text(v));
    } else if (kv.second.IsScalar()) {
      axis.values.push_back(kv.second.Scalar());
    }
    if (axis.values.empty())
      throw sdk::Error(sdk::codes::kBadConfig,
                       where + "sweep key '" + axis.key + "' needs a list of values");
    for (std::size_t i = 0; i < axis.values.size(); ++i)
      for (std::size_t j = 0; j < i; ++j)
        if (axis.values[i] == axis.values[j])
          throw sdk::Error(sdk::codes::kBadConfig, where + "sweep key '" + axis.key + "' lists '" +
                                                       axis.values[i] + "' twice");
    for (const auto& other : axes)
      if (other.key == axis.key)
        throw sdk::Error(sdk::codes::kBadConfig,
                         where + "sweep key '" + axis.key + "' is given twice");
    axes.push_back(std::move(axis));
  }
  return axes;
}

}  // namespace

Experiment load_experiment(const std::string& path) {
  Experiment e;
  e.file = fs::absolute(path).lexically_normal().string();
  const YAML::Node root = wiring::load_bounded_yaml_file(path, "experiment file");
  const std::string where = "experiment file '" + path + "': ";
  try {
    for (const auto& kv : root) {
      const auto key = kv.first.as<std::string>();
      static const char* known[] = {"name",        "config",    "corpus",      "runs",
                                    "max_queries", "bodies",    "set",         "variants",
                                    "sweep",       "isolation", "kill_after_s"};
      if (std::find(std::begin(known), std::end(known), key) == std::end(known))
        throw sdk::Error(sdk::codes::kBadConfig,
                         where + "unknown key '" + key +
                             "' (keys: name, config, corpus, runs, max_queries, bodies, set, "
                             "variants, sweep, isolation, kill_after_s)");
    }
    if (root["name"]) e.name = root["name"].as<std::string>();
    if (root["config"] && !root["config"].as<std::string>().empty())
      e.config = resolve_in_file(path, root["config"].as<std::string>());
    if (root["corpus"]) e.corpus = resolve_in_file(path, root["corpus"].as<std::string>());
    e.runs = string_list(root["runs"], where + "'runs'");
    if (root["max_queries"]) e.max_queries = root["max_queries"].as<int>();
    if (root["bodies"]) {
      const std::string bodies = root["bodies"].as<std::string>();
      if (bodies != "accepted" && bodies != "reparsed")
        throw sdk::Error(sdk::codes::kBadConfig,
                         where + "'bodies' must be accepted or reparsed, got '" + bodies + "'");
      e.reparse_bodies = bodies == "reparsed";
    }
    if (root["isolation"]) {
      const std::string isolation = root["isolation"].as<std::string>();
      if (isolation != "process" && isolation != "none")
        throw sdk::Error(sdk::codes::kBadConfig,
                         where + "'isolation' must be process or none, got '" + isolation + "'");
      e.isolate = isolation == "process";
    }
    if (root["kill_after_s"]) e.kill_after_s = root["kill_after_s"].as<int>();
    if (e.kill_after_s < 1 || e.kill_after_s > 604800)
      throw sdk::Error(sdk::codes::kBadConfig, where + "'kill_after_s' must be in [1, 604800]");
    e.sets = string_list(root["set"], where + "'set'");
    if (const auto v = root["variants"]) {
      if (!v.IsSequence())
        throw sdk::Error(sdk::codes::kBadConfig, where + "'variants' must be a list");
      for (std::size_t i = 0; i < v.size(); ++i) {
        ExperimentVariant var;
        if (!v[i]["name"])
          throw sdk::Error(sdk::codes::kBadConfig,
                           where + "variant " + std::to_string(i) + " needs a 'name'");
        var.name = v[i]["name"].as<std::string>();
        check_variant_name(var.name, where);
        for (const auto& other : e.variants)
          if (other.name == var.name)
            throw sdk::Error(sdk::codes::kBadConfig, where + "two variants are named '" + var.name +
                                                         "' (one output folder each)");
        var.sets = string_list(v[i]["set"], where + "variant '" + var.name + "' 'set'");
        e.variants.push_back(std::move(var));
      }
    }
    if (const auto sweep = root["sweep"]) e.sweep = sweep_axes(sweep, where);
  } catch (const YAML::Exception& ex) {
    throw sdk::Error(sdk::codes::kBadConfig, where + ex.what());
  }
  return e;
}

nlohmann::json experiment_json(const Experiment& e) {
  nlohmann::json variants = nlohmann::json::array(), sweep = nlohmann::json::array();
  for (const auto& v : e.variants) variants.push_back({{"name", v.name}, {"set", v.sets}});
  for (const auto& a : e.sweep) sweep.push_back({{"key", a.key}, {"values", a.values}});
  return {{"name", e.name},
          {"file", e.file},
          {"config", e.config ? nlohmann::json(*e.config) : nlohmann::json()},
          {"corpus", e.corpus},
          {"runs", e.runs},
          {"max_queries", e.max_queries},
          {"bodies", e.reparse_bodies ? "reparsed" : "accepted"},
          {"set", e.sets},
          {"variants", variants},
          {"sweep", sweep},
          {"isolation", e.isolate ? "process" : "none"},
          {"kill_after_s", e.kill_after_s}};
}

Experiment experiment_from_json(const nlohmann::json& j) {
  try {
    Experiment e;
    e.name = j.at("name").get<std::string>();
    e.file = j.value("file", std::string());
    if (j.contains("config") && j["config"].is_string()) e.config = j["config"].get<std::string>();
    e.corpus = j.at("corpus").get<std::string>();
    e.runs = j.at("runs").get<std::vector<std::string>>();
    e.max_queries = j.at("max_queries").get<int>();
    e.reparse_bodies = j.value("bodies", std::string("accepted")) == "reparsed";
    e.sets = j.at("set").get<std::vector<std::string>>();
    for (const auto& v : j.at("variants"))
      e.variants.push_back(
          {v.at("name").get<std::string>(), v.at("set").get<std::vector<std::string>>()});
    for (const auto& a : j.at("sweep"))
      e.sweep.push_back(
          {a.at("key").get<std::string>(), a.at("values").get<std::vector<std::string>>()});
    e.isolate = j.value("isolation", std::string("process")) == "process";
    e.kill_after_s = j.value("kill_after_s", e.kill_after_s);
    return e;
  } catch (const nlohmann::json::exception& ex) {
    throw sdk::Error(sdk::codes::kBadRequest,
                     std::string("the manifest's 'experiment' is incomplete: ") + ex.what());
  }
}

}  // namespace flipper::replay
