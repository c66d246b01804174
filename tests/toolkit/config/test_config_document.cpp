// ConfigDocument (toolkit/config/document.hpp): a file over the files it extends, --set
// overlays, who wrote each key, and the paths and messages that follow from it.
#include <filesystem>
#include <string>

#include "config_test_support.hpp"

using configtest::config_error;
using configtest::rules;
using configtest::write_file;
using flipper::toolkit::config::ConfigDocument;

namespace {
std::string text_at(const ConfigDocument& doc, const std::string& key) {
  const auto node = doc.find(key);
  return node && node->IsScalar() ? node->Scalar() : "(absent)";
}
std::string dir_of(const std::string& path) {
  return std::filesystem::path(path).parent_path().string();
}
}  // namespace

TEST_CASE("a document over the files it extends knows which file wrote each key",
          "[toolkit][config][extends]") {
  const std::string base = write_file("origins/base/base.yaml",
                                      "grammar: {file: base.grammar}\nworld: {file: w.json}\n"
                                      "session: {k: 7}\n");
  const std::string top = write_file("origins/top/top.yaml",
                                     "extends: ../base/base.yaml\ngrammar: {file: top.grammar}\n");
  const ConfigDocument doc = ConfigDocument::read(top, {"data.file=x.dat"}, rules());
  CHECK(doc.source() == top);
  CHECK(doc.base_dir() == dir_of(top));
  CHECK_FALSE(doc.find("extends"));
  CHECK(text_at(doc, "session.k") == "7");
  CHECK(text_at(doc, "grammar.file") == "top.grammar");
  const std::string cwd = std::filesystem::current_path().string();
  CHECK(doc.resolve_path_of("world.file", "w.json") == dir_of(base) + "/w.json");
  CHECK(doc.resolve_path_of("grammar.file", "top.grammar") == dir_of(top) + "/top.grammar");
  CHECK(doc.resolve_path_of("data.file", "x.dat") == cwd + "/x.dat");
  CHECK(doc.resolve_path_of("nobody.file", "n.txt") == "/defaults/n.txt");
  CHECK(doc.resolve_path_of("world.file", "/abs/./w.json") == "/abs/w.json");
  CHECK(doc.resolve_path_of("world.file", "") == "");
  CHECK(doc.path_origin("world.file", " 'w.json'") ==
        "world.file 'w.json' from " + base + " (extended by " + top +
            "): relative to its directory " + dir_of(base));
  CHECK(doc.path_origin("grammar.file", "") ==
        "grammar.file from " + top + ": relative to its directory " + dir_of(top));
  CHECK(doc.path_origin("data.file", "") ==
        "data.file from --set: relative to the current directory " + cwd);
  CHECK(doc.path_origin("nobody.file", "") ==
        "nobody.file (the default, written in no config): relative to the default configs "
        "directory /defaults");
  // A message names the file that wrote the first key it quotes (or a key below it).
  CHECK(doc.where_written("config key 'session.k' is bad") == base + " (extended by " + top + ")");
  CHECK(doc.where_written("config key 'session' is bad") == base + " (extended by " + top + ")");
  CHECK(doc.where_written("config key 'grammar.file' is bad") == top);
  CHECK(doc.where_written("config key 'data.file' is bad") == top);
  CHECK(doc.where_written("no key quoted") == top);
  CHECK(doc.written("session"));
  CHECK(doc.written("data.file"));
  CHECK_FALSE(doc.written("nobody.file"));
  // A --set over a key of the base: the key is the command line's now.
  const ConfigDocument set = ConfigDocument::read(top, {"world.file=mine.json"}, rules());
  CHECK(set.resolve_path_of("world.file", "mine.json") == cwd + "/mine.json");
  CHECK(set.where_written("config key 'world.file' is bad") == top);
}

TEST_CASE("an overlay or a --set that selects another plugin drops the other plugin's params",
          "[toolkit][config][extends]") {
  const std::string base =
      write_file("swap/base.yaml",
                 "planner: {plugin: astar, params: {heuristic: manhattan, seed: 1}}\n"
                 "session: {plugin: keep, params: {a: 1}}\n");
  const std::string other = write_file("swap/other.yaml",
                                       "extends: base.yaml\nplanner: {plugin: ompl}\n"
                                       "session: {plugin: changed}\n");
  const ConfigDocument swapped = ConfigDocument::read(other, {}, rules());
  CHECK(text_at(swapped, "planner.plugin") == "ompl");
  CHECK_FALSE(swapped.find("planner.params"));
  CHECK(text_at(swapped, "session.params.a") == "1");  // not a plugin section: merged
  const std::string same =
      write_file("swap/same.yaml", "extends: base.yaml\nplanner: {params: {seed: 2}}\n");
  const ConfigDocument merged = ConfigDocument::read(same, {}, rules());
  CHECK(text_at(merged, "planner.params.heuristic") == "manhattan");
  CHECK(text_at(merged, "planner.params.seed") == "2");
  // --set: the files' params go, the params an earlier --set gave stay.
  const ConfigDocument set = ConfigDocument::read(
      base, {"planner.params.goal=3", "planner.plugin=ompl", "planner.params.range=4"}, rules());
  CHECK_FALSE(set.find("planner.params.heuristic"));
  CHECK(text_at(set, "planner.params.goal") == "3");
  CHECK(text_at(set, "planner.params.range") == "4");
  CHECK(text_at(ConfigDocument::read(base, {"planner.plugin=astar"}, rules()),
                "planner.params.heuristic") == "manhattan");
}

TEST_CASE("a --set takes a text key verbatim unless quoted, a plugin param also as a flow value",
          "[toolkit][config][set]") {
  const auto doc = [](const std::string& assignment) {
    return ConfigDocument::parse("session: {k: 3}\nname: n\n", "<text>", "/base", {assignment},
                                 rules());
  };
  CHECK(text_at(doc("name=:memory:"), "name") == ":memory:");
  CHECK(text_at(doc("name=a #b"), "name") == "a #b");
  CHECK(text_at(doc("name='x y'"), "name") == "x y");
  CHECK(text_at(doc("name="), "name").empty());
  CHECK_FALSE(doc("name=null").find("name"));  // a null word unsets
  CHECK_FALSE(doc("session.k=~").find("session.k"));
  CHECK(doc("session.k=[1, 2]").find("session.k")->IsSequence());
  CHECK(doc("planner.params.list=[a, b]").find("planner.params.list")->IsSequence());
  CHECK(text_at(doc("planner.params.text=a: b"), "planner.params.text") == "a: b");
  CHECK(config_error([&] { (void)doc("other.params.text=[x"); })  // not a plugin section
            .rfind("malformed --set 'other.params.text=[x': the value is not a YAML scalar or flow "
                   "value (",
                   0) == 0);
  CHECK(config_error([&] { (void)doc("session.k"); }) ==
        "malformed --set 'session.k': expected key.path=value (e.g. --set planner.plugin=astar)");
  CHECK(config_error([&] { (void)doc(".k=1"); }) ==
        "malformed --set '.k=1': '.k' is not a dotted key path");
  CHECK(config_error([&] { (void)doc("session.k="); }) ==
        "malformed --set 'session.k=': the value is empty (use null to unset a key)");
  // with(): one more --set on a copy; the document it was made from is unchanged.
  const ConfigDocument first = doc("name=first");
  const ConfigDocument second = first.with("session.k=4");
  CHECK(text_at(first, "session.k") == "3");
  CHECK(text_at(second, "session.k") == "4");
  CHECK(text_at(second, "name") == "first");
  CHECK(second.resolve_path_of("name", "p") ==
        (std::filesystem::current_path() / "p").string());  // still --set's
}

TEST_CASE("a text document: its base directory, nulls dropped, keys not set absent",
          "[toolkit][config]") {
  const ConfigDocument doc =
      ConfigDocument::parse("a: {b: 1, c: ~}\nd: null\n", "<embedded>", "/conf", {}, rules());
  CHECK(doc.source() == "<embedded>");
  CHECK(doc.base_dir() == "/conf");
  CHECK(text_at(doc, "a.b") == "1");
  CHECK_FALSE(doc.find("a.c"));
  CHECK_FALSE(doc.find("d"));
  CHECK(doc.resolve_path_of("a.b", "x") == "/conf/x");
  CHECK(ConfigDocument::parse("", "<empty>", "/", {}, rules()).tree().IsMap());
  CHECK(config_error([&] {
          (void)ConfigDocument::parse("a: {b: 1\n", "<t>", "/", {}, rules());
        }).rfind("config <t>:", 0) == 0);
  CHECK(config_error([&] {
          (void)ConfigDocument::parse("a: 1\nb: 2\na: 3\n", "<t>", "/", {}, rules());
        }) == "config <t>:3: duplicate key 'a' (first at line 1)");
}

TEST_CASE("extends cycles, missing bases, bad extends and deep chains are refused",
          "[toolkit][config][extends]") {
  const std::string a = write_file("cycle/a.yaml", "extends: b.yaml\n");
  const std::string b = write_file("cycle/b.yaml", "extends: ./a.yaml\n");
  CHECK(config_error([&] { (void)ConfigDocument::read(a, {}, rules()); }) ==
        "config " + b + ": extends cycle: " + a + " -> " + b + " -> " + a);
  const std::string self = write_file("cycle/self.yaml", "extends: self.yaml\n");
  CHECK(config_error([&] { (void)ConfigDocument::read(self, {}, rules()); }) ==
        "config " + self + ": extends cycle: " + self + " -> " + self);
  const std::string missing = write_file("missing.yaml", "extends: nowhere/base.yaml\n");
  CHECK(config_error([&] { (void)ConfigDocument::read(missing, {}, rules()); }) ==
        "config " + missing + ": extends 'nowhere/base.yaml', but there is no config at '" +
            dir_of(missing) + "/nowhere/base.yaml' (relative to its directory " + dir_of(missing) +
            ")");
  const std::string list = write_file("list.yaml", "extends: [a, b]\n");
  CHECK(config_error([&] { (void)ConfigDocument::read(list, {}, rules()); }) ==
        "config " + list +
            ": 'extends' must be the path of the config this one overlays, got a list");
  // An error in the base names the base file.
  const std::string bad_base = write_file("bad/base.yaml", "session: {k: 3\n");
  const std::string bad_top = write_file("bad/top.yaml", "extends: base.yaml\n");
  CHECK(config_error([&] {
          (void)ConfigDocument::read(bad_top, {}, rules());
        }).rfind("config " + bad_base + ":", 0) == 0);
  // c0 extends c1 ... extends c(n-1), which sets session.k = 7.
  const auto chain = [](int n) {
    const std::string dir = "chain" + std::to_string(n) + "/";
    for (int i = 0; i + 1 < n; ++i)
      write_file(dir + "c" + std::to_string(i) + ".yaml",
                 "extends: c" + std::to_string(i + 1) + ".yaml\n");
    write_file(dir + "c" + std::to_string(n - 1) + ".yaml", "session: {k: 7}\n");
    return write_file(dir + "c0.yaml", "extends: c1.yaml\n");
  };
  CHECK(text_at(ConfigDocument::read(chain(16), {}, rules()), "session.k") == "7");
  const std::string deep = chain(17);
  CHECK(config_error([&] { (void)ConfigDocument::read(deep, {}, rules()); }) ==
        "config " + dir_of(deep) + "/c15.yaml: more than 16 configs extend one another");
  CHECK(config_error([&] {
          (void)ConfigDocument::read(dir_of(deep) + "/none.yaml", {}, rules());
        }).find("cannot read config file '" + dir_of(deep) + "/none.yaml'") == 0);
}
