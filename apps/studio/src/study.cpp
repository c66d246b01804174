#include "study.hpp"

#include <yaml-cpp/yaml.h>
#include <nlohmann/json.hpp>

#include <filesystem>

#include "flipper/kernel/keys.hpp"
#include "flipper/sdk/errors.hpp"
#include "flipper/toolkit/config/regular_file.hpp"
#include "flipper/wiring/yaml_file.hpp"
#include "registry.hpp"

namespace flipper::studio {
namespace fs = std::filesystem;
using kernel::Json;

namespace {

[[noreturn]] void fail(const std::string& file, const std::string& what) {
  throw sdk::Error(sdk::codes::kBadConfig, "study " + file + ": " + what);
}

// A task's world file, read with the default input.max_file_bytes bound (docs/bad-input.md): the
// study file names it, the server's operator wrote both.
Json read_world(const std::string& study, const fs::path& path, const std::string& key) {
  std::string text;
  try {
    text = toolkit::config::read_regular_file(
        path.string(), static_cast<std::uint64_t>(kernel::keys::kMaxFileBytes.def), "world file",
        sdk::codes::kBadConfig);
  } catch (const sdk::Error& e) {
    fail(study, key + ": " + e.what());
  }
  Json w = Json::parse(text, nullptr, false);
  if (!w.is_object()) fail(study, key + ": '" + path.string() + "' is not a JSON world object");
  return w;
}

std::string study_text(const YAML::Node& n, const std::string& study, const std::string& key,
                       bool required) {
  if (!n || n.IsNull()) {
    if (required) fail(study, "missing key '" + key + "'");
    return {};
  }
  if (!n.IsScalar()) fail(study, "'" + key + "' must be text");
  return n.as<std::string>();
}

}  // namespace

const char* sharing_of_group(const std::string& group) {
  return group == "A" ? "core" : group == "B" ? "private" : "shared";
}

std::shared_ptr<Study> Study::load(const std::string& path) {
  // Bounded like a config: a regular file of at most 1 MiB, 100,000 nodes with aliases expanded.
  const YAML::Node root = wiring::load_bounded_yaml_file(path, "study file");
  if (!root.IsMap()) fail(path, "must be a map with name, groups and tasks");
  for (const auto& kv : root) {
    const std::string key = kv.first.as<std::string>();
    if (key != "name" && key != "tutorial" && key != "groups" && key != "preload" &&
        key != "record" && key != "tasks" && key != "moderation")
      fail(path, "unknown key '" + key +
                     "' (known: name, tutorial, groups, preload, record, tasks, moderation)");
  }
  const fs::path dir = fs::absolute(path).parent_path();
  auto study = std::make_shared<Study>();
  study->name_ = study_text(root["name"], path, "name", true);
  for (char c : study->name_)
    if (!std::isalnum(static_cast<unsigned char>(c)) && c != '-' && c != '_')
      fail(path, "name '" + study->name_ + "' may hold only letters, digits, '-' and '_'");
  study->tutorial_ = study_text(root["tutorial"], path, "tutorial", false);
  if (root["groups"]) {
    if (!root["groups"].IsSequence()) fail(path, "'groups' must be a list of A, B or C");
    for (const auto& g : root["groups"]) {
      const std::string name = g.as<std::string>();
      if (name != "A" && name != "B" && name != "C")
        fail(path, "group '" + name + "' is not A (core), B (private) or C (shared)");
      study->groups_.push_back(name);
    }
  }
  if (study->groups_.empty()) study->groups_ = {"C"};
  if (auto p = study_text(root["preload"], path, "preload", false); !p.empty())
    study->preload_ = (dir / p).lexically_normal().string();
  // The study asks for moderation of its lexicons (docs/naturalization.md §5 "Moderation");
  // absent: the server's lexicon.moderation.
  study->moderation_ = study_text(root["moderation"], path, "moderation", false);
  if (!study->moderation_.empty() && study->moderation_ != "off" &&
      study->moderation_ != "hold_new")
    fail(path, "moderation '" + study->moderation_ + "' is not off or hold_new");
  std::string record = study_text(root["record"], path, "record", false);
  if (record.empty()) record = study->name_ + "-recording";
  study->record_dir_ = (dir / record).lexically_normal().string();
  const YAML::Node tasks = root["tasks"];
  if (!tasks || !tasks.IsSequence() || tasks.size() == 0)
    fail(path, "'tasks' must be a non-empty list of {name, text, start, goal}");
  for (std::size_t i = 0; i < tasks.size(); ++i) {
    const std::string key = "tasks[" + std::to_string(i) + "]";
    StudyTask t;
    t.name = study_text(tasks[i]["name"], path, key + ".name", true);
    t.text = study_text(tasks[i]["text"], path, key + ".text", true);
    t.start = read_world(path, dir / study_text(tasks[i]["start"], path, key + ".start", true),
                         key + ".start");
    // A world file, or a predicate over the world (docs/studio.md §7 "Goals").
    if (const YAML::Node goal = tasks[i]["goal"]; goal && goal.IsMap())
      t.goal = TaskGoal::of_predicate(goal, t.start, path, key + ".goal");
    else if (auto file = study_text(goal, path, key + ".goal", false); !file.empty())
      t.goal = TaskGoal::of_world(read_world(path, dir / file, key + ".goal"));
    study->tasks_.push_back(std::move(t));
  }
  return study;
}

std::vector<std::pair<std::string, kernel::Config>> Study::kernels(
    const kernel::Config& base) const {
  std::vector<std::pair<std::string, kernel::Config>> out;
  for (const auto& g : groups_) {
    bool seen = false;
    for (const auto& [name, c] : out) seen = seen || name == g;
    if (seen) continue;
    kernel::Config c = base;
    c.set(std::string("lexicon.sharing=") + sharing_of_group(g));
    c.set("lexicon.path=" + record_dir_ + "/lexicon-" + g + ".sqlite");
    c.set("lexicon.preload=" + (g == "C" ? preload_ : std::string()));
    if (!moderation_.empty()) c.set("lexicon.moderation=" + moderation_);
    out.emplace_back(g, std::move(c));
  }
  return out;
}

Json Study::page_json() const {
  Json tasks = Json::array();
  for (const auto& t : tasks_)
    tasks.push_back({{"name", t.name},
                     {"text", t.text},
                     {"start", t.start},
                     {"goal", t.goal.world()},
                     {"goal_predicate", t.goal.predicate()}});
  return Json{{"name", name_}, {"tutorial", tutorial_}, {"tasks", std::move(tasks)}};
}

}  // namespace flipper::studio
