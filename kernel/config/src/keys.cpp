// The kernel's schema fragment: its own keys (keys.hpp) and the plugin sections, in the order the
// effective config lists them. The keys of the layers above are theirs (docs/config.md "Who
// declares a key"); the host composes them with this fragment (Config::install_schema).
#include "flipper/kernel/keys.hpp"

#include <atomic>
#include <memory>
#include <mutex>
#include <stdexcept>
#include <vector>

#include "flipper/kernel/config.hpp"
#include "flipper/language/keys.hpp"

namespace flipper::kernel {
namespace {

using sdk::ParamSchema;
using sdk::ParamSpec;
using sdk::ParamType;
using sdk::param::add;

// A plugin section: `plugin` names the plugin (required; `def` empty: the section is optional),
// `params` is validated against the plugin's own schema (Config::plugin_params).
void add_plugin_section(ParamSchema& s, const std::string& section, const std::string& def,
                        const std::string& doc) {
  s.add_section(section, doc, def.empty());
  ParamSpec plugin{section + ".plugin",
                   ParamType::String,
                   {},
                   def.empty(),
                   "the " + section + " plugin",
                   {},
                   {},
                   {}};
  if (!def.empty()) plugin.default_value = def;
  s.add(std::move(plugin));
  s.add_map(section + ".params", "the plugin's params (`flipper plugins NAME` lists them)");
}

ParamSchema build() {
  ParamSchema s;
  add_plugin_section(s, "world", "grid2d", "the world plugin");
  add(s, keys::kWorldFile);
  add(s, keys::kWorldResolution);
  add(s, keys::kWorldOrigin);
  add(s, keys::kMaxWorldCells);
  add_plugin_section(s, "planner", "astar", "the planner plugin");
  add_plugin_section(s, "parser", "chart", "the parser plugin");
  add_plugin_section(s, "scorer", "loglinear", "the scorer plugin");
  add_plugin_section(s, "rewriter", "", "optional: generalization by rewriting");
  add_plugin_section(s, "similarity", "", "optional: word similarity for alignment");

  s.add_section("grammar", "the core grammar and its vocabulary");
  add(s, keys::kGrammarFile);
  add(s, keys::kGrammarColors);
  add(s, keys::kGrammarShapes);
  add(s, keys::kGrammarDirections);

  language::keys::add_config(s);  // the core language's section (language/exec)
  s.add_section("input", "limits on what a request or a file may make the kernel do");
  add(s, keys::kMaxChars);
  add(s, keys::kMaxSemicolons);
  add(s, keys::kMaxLineBytes);
  add(s, keys::kMaxJsonDepth);
  add(s, keys::kMaxTokens);
  add(s, keys::kMaxBodyLines);
  add(s, keys::kMaxFileBytes);
  s.add_section("session", "one session's answers");
  add(s, keys::kSessionK);
  add(s, keys::kCpuBudgetMs);
  add(s, keys::kDeadlineMs);
  add(s, keys::kPluginPaths);
  s.add_section("plugins", "how plugin calls run");
  add(s, keys::kPluginIsolation);
  return s;
}

// The schema the host installed (Config::install_schema), else the kernel's own. An installed
// schema lives as long as the process: a reference handed out earlier stays valid.
std::atomic<const ParamSchema*>& installed() {
  static std::atomic<const ParamSchema*> schema{nullptr};
  return schema;
}

}  // namespace

const sdk::ParamSchema& Config::kernel_schema() {
  static const ParamSchema kSchema = build();
  return kSchema;
}

void Config::install_schema(sdk::ParamSchema schema) {
  for (const auto& spec : kernel_schema().params)
    if (schema.find(spec.name) == nullptr)
      throw std::logic_error("the config schema lacks the kernel key '" + spec.name + "'");
  static std::mutex keep_mutex;
  static std::vector<std::unique_ptr<const ParamSchema>> keep;
  const std::lock_guard<std::mutex> lock(keep_mutex);
  keep.push_back(std::make_unique<const ParamSchema>(std::move(schema)));
  installed().store(keep.back().get());
}

const sdk::ParamSchema& Config::schema() {
  const ParamSchema* schema = installed().load();
  return schema != nullptr ? *schema : kernel_schema();
}

}  // namespace flipper::kernel
