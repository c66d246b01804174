#pragma once
// Plugins created by the kernel's loader from a config, exactly as `flipper --set
// parser.plugin=floating` creates them (discovery, checks, params validated, defaults filled).
#include <memory>
#include <string>
#include <vector>

#include "flipper/kernel/config.hpp"
#include "flipper/kernel/loader.hpp"
#include "plugins/chart/parse_support.hpp"

namespace flipper::floatingtest {

template <class Interface>
std::shared_ptr<Interface> kernel_loaded(const std::string& section, const std::string& plugin,
                                         std::vector<std::string> sets = {}) {
  sets.insert(sets.begin(), section + ".plugin=" + plugin);
  const auto config = kernel::Config::load(std::nullopt, sets);
  const kernel::PluginLoader loader(kernel::PluginLoader::search_path_for(config));
  return loader.create<Interface>(config, section).shared();
}

/// A floating parser with the core grammar, and a loglinear scorer, both kernel-loaded.
struct FloatingStack {
  std::shared_ptr<sdk::Parser> parser;
  std::shared_ptr<sdk::Scorer> scorer = kernel_loaded<sdk::Scorer>("scorer", "loglinear");
  explicit FloatingStack(std::vector<std::string> sets = {})
      : parser(kernel_loaded<sdk::Parser>("parser", "floating", std::move(sets))) {
    parser->set_grammar(parsetest::core_grammar());
  }
  sdk::ParseResult parse(const std::string& utterance, const std::string& user = "u") const {
    sdk::ParseRequest req;
    req.tokens = sdk::tokenize(utterance);
    req.scorer = scorer.get();
    req.context.user = user;
    return parser->parse(req);
  }
};

/// Words the derivation leaves out: its span minus the tokens its rules consume.
inline int skipped_words(const sdk::Derivation& d) {
  int consumed = 0;
  std::function<void(const sdk::Derivation&)> walk = [&](const sdk::Derivation& n) {
    for (const auto& s : n.rule->rhs)
      if (s.type != sdk::Symbol::Type::category) ++consumed;
    for (const auto& k : n.kids) walk(*k);
  };
  walk(d);
  return d.end - d.start - consumed;
}

}  // namespace flipper::floatingtest
