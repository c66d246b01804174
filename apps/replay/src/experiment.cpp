// Experiment files and running their variants.
#include "flipper/replay/experiment.hpp"

#include <yaml-cpp/yaml.h>

#include <algorithm>
#include <cctype>
#include <filesystem>

#include "flipper/replay/corpus.hpp"
#include "flipper/replay/replayer.hpp"
#include "flipper/sdk/errors.hpp"

namespace flipper::kernel::replay {
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

}  // namespace

Experiment load_experiment(const std::string& path) {
  Experiment e;
  YAML::Node root;
  try {
    root = YAML::LoadFile(path);
  } catch (const YAML::Exception& ex) {
    throw sdk::Error(sdk::codes::kBadConfig,
                     "cannot read experiment file '" + path + "': " + ex.what());
  }
  const std::string where = "experiment file '" + path + "': ";
  try {
    for (const auto& kv : root) {
      const auto key = kv.first.as<std::string>();
      static const char* known[] = {"name",        "config", "corpus",  "runs",
                                    "max_queries", "set",    "variants"};
      if (std::find(std::begin(known), std::end(known), key) == std::end(known))
        throw sdk::Error(sdk::codes::kBadConfig,
                         where + "unknown key '" + key +
                             "' (keys: name, config, corpus, runs, max_queries, set, variants)");
    }
    if (root["name"]) e.name = root["name"].as<std::string>();
    if (root["config"] && !root["config"].as<std::string>().empty())
      e.config = resolve_in_file(path, root["config"].as<std::string>());
    if (root["corpus"]) e.corpus = resolve_in_file(path, root["corpus"].as<std::string>());
    e.runs = string_list(root["runs"], where + "'runs'");
    if (root["max_queries"]) e.max_queries = root["max_queries"].as<int>();
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
  } catch (const YAML::Exception& ex) {
    throw sdk::Error(sdk::codes::kBadConfig, where + ex.what());
  }
  return e;
}

std::vector<Variant> run_experiment(
    const Experiment& experiment, const std::string& out,
    const std::function<void(const std::string&, std::size_t, std::size_t, const std::string&)>&
        progress) {
  if (experiment.corpus.empty())
    throw sdk::Error(sdk::codes::kBadConfig, "no corpus given (experiment 'corpus' or --corpus)");
  const Corpus corpus = load_corpus(experiment.corpus);
  std::vector<ExperimentVariant> variants = experiment.variants;
  if (variants.empty()) variants.push_back({"plain", {}});

  std::vector<Variant> results;
  std::vector<std::string> runs;
  for (const auto& v : variants) {
    ReplayOptions options;
    options.config_file = experiment.config;
    options.sets = experiment.sets;
    options.sets.insert(options.sets.end(), v.sets.begin(), v.sets.end());
    options.runs = experiment.runs;
    options.max_queries = experiment.max_queries;
    if (progress)
      options.progress = [&](std::size_t done, std::size_t total, const std::string& run) {
        progress(v.name, done, total, run);
      };
    ReplayResult result = replay(corpus, options);
    runs = result.runs;
    Variant out_v{v.name, options.sets, compute_metrics(result), v.name};
    write_metrics(out + "/" + v.name, result, out_v.metrics);
    write_figures(out + "/" + v.name, out_v.metrics);
    results.push_back(std::move(out_v));
  }
  if (results.size() > 1) write_variant_figure(out, results);
  write_report(out, experiment.name, results, experiment.corpus, runs);
  return results;
}

}  // namespace flipper::kernel::replay
