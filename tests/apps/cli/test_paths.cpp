// The one path rule (docs/configuration.md): relative paths given on the command line (--set)
// resolve against the current directory, relative paths written in a config file against that
// file's directory; a missing file is named with the path it resolved to and where the value came
// from.
#include "cli_test_support.hpp"

using namespace flipper::clitest;

namespace fs = std::filesystem;

namespace {
// Runs flipper from `dir`: run_flipper puts the binary first, so a harmless `--version` goes
// there and the real command follows after the `cd`.
Run run_from(const fs::path& dir, const std::string& args) {
  return run_flipper("--version >/dev/null && cd '" + dir.string() + "' && " +
                     std::string(FLIPPER_BINARY_DIR) + "/bin/flipper " + args);
}
}  // namespace

TEST_CASE("command-line (--set) paths resolve against the current directory", "[cli][paths]") {
  const fs::path dir = fs::path(scratch_dir("paths-cwd"));
  fs::create_directories(dir);
  fs::copy_file(fs::path(FLIPPER_SOURCE_DIR) / "configs/worlds/study2018.json", dir / "mine.json",
                fs::copy_options::overwrite_existing);
  // Before the rule this looked for configs/mine.json next to the embedded default.
  const Run r =
      run_from(dir, "run --set lexicon.path=:memory: --set world.file=mine.json '{move up}'");
  INFO(r.out);
  CHECK(r.status == 0);
  CHECK(contains(r.out, "move [2,5]"));

  // A lexicon path lands in the current directory, and the message names where.
  fs::remove(dir / "store.sqlite");
  const Run s = run_from(dir, "lexicon import - --set lexicon.path=store.sqlite < /dev/null");
  INFO(s.out);
  CHECK(s.status == 0);
  CHECK(contains(s.out, "into " + (dir / "store.sqlite").string()));
  CHECK(fs::exists(dir / "store.sqlite"));

  // A plugin_paths entry that is not a directory is an error naming the resolved path (it was
  // dropped silently before).
  const Run p = run_from(dir, "plugins --set 'plugin_paths=[no-such-dir]'");
  INFO(p.out);
  CHECK(p.status == 2);
  CHECK(contains(p.out,
                 "flipper plugins: [bad_config] plugin_paths entry 'no-such-dir' resolves to '" +
                     (dir / "no-such-dir").string() + "', which is not a directory"));
  CHECK(contains(p.out, "from --set: relative to the current directory " + dir.string()));
}

TEST_CASE(
    "paths in a config file resolve against its directory, and a copied config says why it fails",
    "[cli][paths]") {
  const fs::path dir = fs::path(scratch_dir("paths-config"));
  fs::create_directories(dir / "sub");
  fs::copy_file(fs::path(FLIPPER_SOURCE_DIR) / "configs/worlds/study2018.json",
                dir / "sub" / "w.json", fs::copy_options::overwrite_existing);
  fs::copy_file(fs::path(FLIPPER_SOURCE_DIR) / "configs/grammars/core.grammar",
                dir / "sub" / "g.grammar", fs::copy_options::overwrite_existing);
  std::ofstream(dir / "sub" / "c.yaml") << "world: {plugin: grid2d, file: w.json}\n"
                                           "grammar: {file: g.grammar}\n"
                                           "lexicon: {path: lex.sqlite}\n";
  // Run from another directory: the config's own paths still resolve next to it.
  const Run ok = run_from(dir, "run --config sub/c.yaml '{move up}'");
  INFO(ok.out);
  CHECK(ok.status == 0);
  CHECK(contains(ok.out, "move [2,5]"));
  CHECK(fs::exists(dir / "sub" / "lex.sqlite"));

  // configs/default.yaml copied elsewhere works: the keys it leaves to their defaults
  // (world.file, grammar.file) were written in no file, so they resolve against the default
  // configs directory, not against the copy's.
  fs::copy_file(fs::path(FLIPPER_SOURCE_DIR) / "configs/default.yaml", dir / "copy.yaml",
                fs::copy_options::overwrite_existing);
  const Run copied = run_from(dir, "config check copy.yaml --set lexicon.path=:memory:");
  INFO(copied.out);
  CHECK(copied.status == 0);

  // A config that writes the paths itself is read relative to itself: copied without its
  // worlds/, it fails, naming the resolved path and the file that wrote it.
  std::ofstream(dir / "writes.yaml") << "world: {plugin: grid2d, file: worlds/study2018.json}\n";
  const Run bad = run_from(dir, "config check writes.yaml");
  INFO(bad.out);
  CHECK(bad.status == 2);
  // The world is loaded first (its direction words are the grammar's).
  CHECK(contains(bad.out, "flipper config check: [bad_world] no world file at '" +
                              (dir / "worlds/study2018.json").string() +
                              "' (world.file 'worlds/study2018.json' from writes.yaml: relative "
                              "to its directory " +
                              dir.string() + ")"));
}

TEST_CASE("paths in an experiment file resolve against its directory", "[cli][paths]") {
  const fs::path dir = fs::path(scratch_dir("paths-experiment"));
  fs::create_directories(dir / "exp");
  fs::create_directories(dir / "elsewhere");
  fs::copy(fs::path(FLIPPER_SOURCE_DIR) / "tests/apps/replay/data", dir / "exp" / "corpus");
  std::ofstream(dir / "exp" / "e.yaml") << "corpus: corpus\n";
  // Run from a sibling directory: the corpus is found next to the experiment file, the output
  // (a command-line path) lands in the current directory.
  const Run ok = run_from(dir / "elsewhere", "replay --experiment ../exp/e.yaml --out out");
  INFO(ok.out);
  CHECK(ok.status == 0);
  CHECK(contains(ok.out, "plain: status agreement "));
  CHECK(fs::exists(dir / "elsewhere" / "out" / "latest" / "report.md"));

  // A missing corpus is named by the path it resolved to, next to the file.
  std::ofstream(dir / "exp" / "missing.yaml") << "corpus: no-such-corpus\n";
  const Run bad = run_from(dir / "elsewhere", "replay --experiment ../exp/missing.yaml --out out");
  INFO(bad.out);
  CHECK(bad.status != 0);
  CHECK(contains(bad.out, (dir / "exp" / "no-such-corpus").string()));
}
