#pragma once
// Shared by the conformance drivers flipper_<kind>_conformance.cpp that
// flipper_add_conformance_test() compiles: the plugin under test, created from its built library
// with the PARAMS the CMake call gave (FLIPPER_CONFORMANCE_* definitions).
#include <memory>
#include <sstream>
#include <string>
#include <vector>

#include "flipper/testing/plugin_factory.hpp"

namespace flipper::testing::driver {

/// The PARAMS of the CMake call, typed by the plugin's schema.
inline ParamValues params() {
  std::vector<std::string> settings;
  std::stringstream in(FLIPPER_CONFORMANCE_PARAMS);
  for (std::string line; std::getline(in, line);)
    if (!line.empty()) settings.push_back(line);
  return param_values(PluginLibrary(FLIPPER_CONFORMANCE_PLUGIN_PATH).schema(), settings);
}

/// A fresh instance of the plugin under test.
template <class Interface>
std::shared_ptr<Interface> plugin() {
  return load_plugin<Interface>(FLIPPER_CONFORMANCE_PLUGIN_PATH, params());
}

}  // namespace flipper::testing::driver

#include "flipper/sdk/grammar.hpp"

namespace flipper::testing::driver {

/// The core grammar (FLIPPER_CONFORMANCE_GRAMMAR) with the default config's words.
inline std::shared_ptr<const sdk::Grammar> core_grammar() {
  return std::make_shared<const sdk::Grammar>(sdk::load_grammar_file(
      FLIPPER_CONFORMANCE_GRAMMAR,
      {"black", "blue", "gray", "green", "orange", "pink", "purple", "red", "yellow"},
      {"triangle", "circle", "square"}, {"up", "down", "left", "right"}));
}

}  // namespace flipper::testing::driver
