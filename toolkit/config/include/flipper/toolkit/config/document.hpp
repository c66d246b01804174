#pragma once
/// @file document.hpp
/// A layered YAML configuration document (docs/configuration.md): a file over the files it
/// `extends:` (each merged under the one that extends it), then each `--set key.path=value`; a
/// null value means "not set" and is dropped. The document knows who wrote each key (the file, a
/// file it extends, or --set), so a relative path resolves against the directory of the file that
/// wrote it (a --set one against the current directory) and a message names that file. Bounded as
/// docs/bad-input.md says (yaml_bounds.hpp). What the keys mean is the schema's: the owner of the
/// document (kernel::Config) reads it into typed values (typed_values.hpp). Every error is
/// sdk::Error(bad_config).

#include <yaml-cpp/yaml.h>

#include <functional>
#include <map>
#include <optional>
#include <set>
#include <string>
#include <vector>

namespace flipper::toolkit::config {

/// What a document needs to know of the schema it will be read with.
struct DocumentRules {
  /// Keys whose --set value is text taken verbatim unless quoted (String and Path keys).
  std::function<bool(const std::string& key)> is_text_key;
  /// The sections S whose `S.plugin` says what `S.params` mean: an overlay or a --set that
  /// selects another plugin drops the params written for the one before, and a --set of
  /// `S.params.NAME` (a type only the plugin knows) may be a flow list or map.
  std::vector<std::string> plugin_sections;
  /// The directory a key that no file and no --set wrote resolves against.
  std::string defaults_dir;
};

/// The file and directory a key came from, for a key written by a file the document extends.
struct Origin {
  std::string file;
  std::string dir;
};

class ConfigDocument {
 public:
  /// `file` (named as given) over the chain of files it extends, then `overrides` (--set).
  static ConfigDocument read(const std::string& file, const std::vector<std::string>& overrides,
                             DocumentRules rules);
  /// A document given as text, named `source`, its relative paths against `base_dir` (an
  /// embedded default), then `overrides`.
  static ConfigDocument parse(const std::string& text, const std::string& source,
                              const std::string& base_dir,
                              const std::vector<std::string>& overrides, DocumentRules rules);
  /// This document with one more --set (same syntax and rules); this one is unchanged.
  ConfigDocument with(const std::string& assignment) const;

  /// The merged tree, a map without null values.
  const YAML::Node& tree() const { return tree_; }
  /// The file given, or the name of a text document.
  const std::string& source() const { return source_; }
  /// The directory of source(): what its relative paths resolve against.
  const std::string& base_dir() const { return base_dir_; }
  const DocumentRules& rules() const { return rules_; }

  /// The value at a dotted key, if the tree has one.
  std::optional<YAML::Node> find(const std::string& key) const;
  /// Whether `key` (or a key below it) was written by a file or --set.
  bool written(const std::string& key) const;
  /// Resolves the value `path` of `key`: against the current directory when --set gave it,
  /// against the directory of the file that wrote it, against rules().defaults_dir when nobody
  /// did.
  std::string resolve_path_of(const std::string& key, const std::string& path) const;
  /// Where `key` came from and what its paths are relative to, for messages:
  /// "KEY VALUE from F: relative to its directory D" (`value`: " 'text'" or empty).
  std::string path_origin(const std::string& key, const std::string& value) const;
  /// The file a message about a key was written in: the key is the first one the message quotes;
  /// when it (or a key below it) came from an extended file, "BASE (extended by SOURCE)".
  std::string where_written(const std::string& message) const;

 private:
  ConfigDocument(YAML::Node tree, std::string source, std::string base_dir,
                 std::set<std::string> cli_keys, std::map<std::string, Origin> origins,
                 const std::vector<std::string>& overrides, DocumentRules rules);

  YAML::Node tree_;
  std::string source_;
  std::string base_dir_;
  std::set<std::string> cli_keys_;         // keys given by --set: their paths resolve against cwd_
  std::map<std::string, Origin> origins_;  // keys that came from a file this one extends
  std::string cwd_;                        // the current directory when the document was read
  DocumentRules rules_;
};

/// Resolves `path` against `base`: "~" and "~/" expand to $HOME, an absolute path is normalized,
/// an empty one stays empty.
std::string resolve_against(const std::string& base, const std::string& path);

}  // namespace flipper::toolkit::config
