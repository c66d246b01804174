#pragma once
/// @file config.hpp
/// The validated configuration. Sources, in order: the file given with --config (or the embedded
/// configs/default.yaml) over the files it `extends:` (each merged under the one that extends
/// it), then each --set key.path=value: a document read by the toolkit's config module
/// (flipper/toolkit/config/document.hpp), which the kernel binds to the schema. Validation
/// happens before anything is built, by one engine (sdk::validate_params) with one wording: the
/// keys against the schema the host composed (Config::schema(): the kernel's fragment, keys.hpp
/// and keys.cpp, and each layer's above it; docs/config.md "Who declares a key"), each plugin's
/// `params` against the schema that plugin declares; unknown keys are errors with a "did you
/// mean" hint (code bad_config), and every message names the file and the full key.
///
/// Layout (Nav2-style named instances):
///   world:    {plugin: grid2d, params: {...}, file: worlds/study2018.json, resolution, origin,
///             max_cells}
///   planner:  {plugin: astar, params: {...}}
///   parser / scorer / rewriter / similarity: {plugin: NAME, params: {...}}
///   grammar:  {file, colors, shapes}
///   execution:{action_budget, step_budget, while_limit, cpu_budget_ms, deadline_ms}
///   input:    {max_chars, max_semicolons, max_line_bytes, max_json_depth, max_tokens,
///              max_body_lines, max_file_bytes}
///   session:  {k, cpu_budget_ms, deadline_ms}
///   plugin_paths: [dirs]
/// and the layers' sections (lexicon, induction: naturalization; serve: studio; dds, publish: dds).
/// Paths, one rule (docs/configuration.md): a relative path written in a config file resolves
/// against that file's directory (for a key from an extended file, that file's) (the embedded
/// default behaves as if it lived in the source tree's configs/); a relative path given on the
/// command line
/// (`--set key=path`) resolves against the current directory.

#include <cstdint>
#include <memory>
#include <optional>
#include <string>
#include <string_view>
#include <vector>

#include "flipper/kernel/keys.hpp"
#include "flipper/sdk/config_handles.hpp"
#include "flipper/sdk/params.hpp"

namespace flipper::kernel {

class Config {
 public:
  /// Loads and validates the kernel keys (plugin params are validated by the loader against
  /// each plugin's schema). Throws sdk::Error(bad_config).
  static Config load(const std::optional<std::string>& file,
                     const std::vector<std::string>& overrides);
  /// The embedded default.
  static Config embedded_default();
  /// The keys a config is validated against: types, defaults, ranges, choices, descriptions,
  /// sections. The validation, `flipper config explain` and docs/config.md's key table all read
  /// this. It is the schema the host installed, else the kernel's own.
  static const sdk::ParamSchema& schema();
  /// The kernel's own keys and plugin sections (keys.cpp): the first fragment of every schema.
  static const sdk::ParamSchema& kernel_schema();
  /// Installs the schema a host composed of the kernel's fragment and its layers' (e.g. with
  /// sdk::param::compose) before it loads a config; the process keeps it. Throws
  /// std::logic_error when it lacks a kernel key.
  static void install_schema(sdk::ParamSchema schema);

  /// "<embedded default>" or the file path.
  const std::string& source() const;
  /// Directory relative paths resolve against.
  const std::string& base_dir() const;
  /// Resolves a path relative to base_dir(); "~/" expands to $HOME. Empty stays empty.
  std::string resolve_path(const std::string& path) const;
  /// Resolves the value `path` of key `key`: against the current directory when `key` was given
  /// by --set, against the directory of the file that wrote it (base_dir() or a file it
  /// extends), and against the default configs directory when no file wrote it (a default).
  std::string resolve_path_of(const std::string& key, const std::string& path) const;
  /// Whether `key` (or a key below it) was written by a config file or --set, not defaulted.
  bool written(const std::string& key) const;
  /// Where a path key's value came from and what it is relative to, for error messages:
  /// "grammar.file 'g.grammar' from F: relative to its directory D".
  std::string path_origin(const std::string& key) const;

  /// Typed access by dotted key ("execution.action_budget"). Throws bad_config when absent or
  /// of the wrong type (after validation these only fail on programming errors).
  bool has(const std::string& key) const;
  std::string get_string(const std::string& key) const;
  std::int64_t get_int(const std::string& key) const;
  double get_double(const std::string& key) const;
  bool get_bool(const std::string& key) const;
  std::vector<std::string> get_string_list(const std::string& key) const;
  /// Typed handles (flipper/sdk/config_handles.hpp): the value of a declared key, the only way
  /// code reads a key: a Choice as its enumerator, a Path or PathList resolved with
  /// resolve_path_of() (text(): as written, e.g. `:memory:`). Throws std::logic_error for a key
  /// the installed schema lacks (a host that did not compose the layer declaring it).
  template <class Handle>
  auto get(const Handle& key) const {
    return sdk::param::get(declared(key.name), key);
  }
  std::string get(const sdk::param::Path& key) const { return get_path(std::string(key.name)); }
  template <std::size_t N>
  std::vector<std::string> get(const sdk::param::PathList<N>& key) const {
    return get_path_list(std::string(key.name));
  }
  template <class Handle>
  auto text(const Handle& key) const {
    return sdk::param::get(declared(key.name), key);
  }
  /// has(), resolve_path_of() and path_origin() of a declared key.
  template <class Handle>
  bool has(const Handle& key) const {
    return has(std::string(key.name));
  }
  std::string resolve_path_of(const sdk::param::Path& key, const std::string& path) const {
    return resolve_path_of(std::string(key.name), path);
  }
  template <class Handle>
  std::string path_origin(const Handle& key) const {
    return path_origin(std::string(key.name));
  }

  /// Sets a key after loading (same syntax and validation as --set).
  void set(const std::string& assignment);

  /// A Path-typed key resolved with resolve_path_of() ("grammar.file" -> absolute path).
  std::string get_path(const std::string& key) const;
  /// A PathList key, each element resolved with resolve_path_of().
  std::vector<std::string> get_path_list(const std::string& key) const;
  /// Whether a plugin section ("rewriter", "similarity", ...) is present.
  bool has_section(const std::string& section) const { return has(section + ".plugin"); }
  /// The plugin name a section selects ("planner" -> "astar"). Throws bad_config when absent.
  std::string plugin_name(const std::string& section) const {
    return get_string(section + ".plugin");
  }
  /// Validates `<section>.params` against a plugin's declared schema (unknown keys with a hint,
  /// types, ranges, one_of, required), resolves Path params against base_dir() and fills
  /// defaults. Throws sdk::Error(bad_config) naming the full key path.
  sdk::Params plugin_params(const std::string& section, const sdk::ParamSchema& schema) const;
  /// The plugin sections in schema order: world, planner, parser, scorer, rewriter, similarity.
  static const std::vector<std::string>& plugin_sections();

  /// The effective config as YAML text (defaults included), for run records.
  std::string dump() const;

  struct Impl;
  explicit Config(std::shared_ptr<Impl> impl);
  const Impl& impl() const { return *impl_; }

 private:
  /// The validated values, once `key` is known to be declared (else std::logic_error).
  const sdk::Params& declared(std::string_view key) const;
  std::shared_ptr<Impl> impl_;  // copy-on-write shared state
};

}  // namespace flipper::kernel
