#pragma once
/// @file yaml_file.hpp
/// Reading a YAML file that is not a config (an experiment, a planner task list) with a config's
/// bounds (docs/bad-input.md): a regular file of at most 1 MiB whose document expands to at most
/// 100,000 nodes, aliases counted, so /dev/zero, a FIFO or an alias bomb is an error, not a hang.
/// A host's job (the study, experiment and task files of the apps), on the bounds of a config
/// document (flipper/toolkit/config/yaml_bounds.hpp).
#include <yaml-cpp/yaml.h>

#include <string>

namespace flipper::wiring {

/// The document of `path`; `what` names it in messages ("experiment file"). Every failure is
/// bad_config, its message naming `what` and `path`.
YAML::Node load_bounded_yaml_file(const std::string& path, const std::string& what);

}  // namespace flipper::wiring
