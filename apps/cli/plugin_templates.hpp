#pragma once
// The files `flipper plugin new` writes (plugin_new.cpp), embedded at build time from
// examples/out-of-tree-planner and examples/plugin-templates/<kind> (embed_templates.cmake).
#include <string_view>
#include <vector>

namespace flipper::cli {

struct PluginTemplate {
  std::string_view kind;   ///< world, planner, ...; "any": every kind's (the CMakeLists.txt)
  std::string_view token;  ///< the example's plugin name, replaced by the new one
  std::string_view path;   ///< the file's name in the scaffold (the token replaced too)
  std::string_view text;
};

/// Every template file, in a fixed order.
const std::vector<PluginTemplate>& plugin_templates();

}  // namespace flipper::cli
