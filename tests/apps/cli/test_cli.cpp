// CLI: build/bin/flipper `plugins` and `config check` as a user runs them; exit status 2 for a
// missing plugin and an unknown key, and a listing that survives broken plugins.
#include <fstream>
#include <iterator>
#include "cli_test_support.hpp"

#include "kernel/kernel_test_support.hpp"

namespace {
using flipper::clitest::Run;
using flipper::clitest::run_flipper;

std::string test_args() {
  return "--config " + flipper::kerneltest::test_config_file() + " --set 'plugin_paths=[" +
         flipper::kerneltest::good_dir() + ", " + flipper::kerneltest::bad_dir() + "]'";
}
}  // namespace

TEST_CASE("flipper config check prints the effective config", "[cli]") {
  const Run r = run_flipper("config check " + test_args());
  INFO(r.out);
  CHECK(r.status == 0);
  CHECK(r.out.find("config ok: " + flipper::kerneltest::test_config_file()) != std::string::npos);
  CHECK(r.out.find("plugin: test_planner") != std::string::npos);
  CHECK(r.out.find("action_budget: 100000") != std::string::npos);
}

TEST_CASE("flipper config check exits 2 for a missing plugin and an unknown key", "[cli]") {
  const Run missing = run_flipper("config check " + test_args() + " --set planner.plugin=nope");
  INFO(missing.out);
  CHECK(missing.status == 2);
  CHECK(missing.out.find("plugin_not_found") != std::string::npos);
  const Run unknown = run_flipper("config check " + test_args() + " --set session.kk=3");
  INFO(unknown.out);
  CHECK(unknown.status == 2);
  CHECK(unknown.out.find("unknown config key 'session.kk' (did you mean 'session.k'?)") !=
        std::string::npos);
  const Run positional = run_flipper("config check /nonexistent/cfg.yaml");
  CHECK(positional.status == 2);
  CHECK(positional.out.find("cannot read config file") != std::string::npos);
}

TEST_CASE("flipper plugins lists good and broken plugins without crashing", "[cli]") {
  const Run r = run_flipper("plugins " + test_args());
  INFO(r.out);
  CHECK(r.status == 0);  // every selected plugin loads
  CHECK(r.out.find("* test_planner") != std::string::npos);
  CHECK(r.out.find("plugin_abi_mismatch") != std::string::npos);
  CHECK(r.out.find("no Flipper descriptor") != std::string::npos);
  const Run bad = run_flipper("plugins " + test_args() + " --set planner.plugin=bad_abi");
  CHECK(bad.status == 2);
  const Run misuse = run_flipper("plugins --no-such-option");
  CHECK(misuse.status == 2);
}

TEST_CASE("flipper config explain and docs/config.md list every declared key", "[cli][schema]") {
  const auto& schema = flipper::kernel::Config::schema();
  const Run all = run_flipper("config explain", false);
  REQUIRE(all.status == 0);
  std::ifstream in(std::string(FLIPPER_SOURCE_DIR) + "/docs/config.md");
  const std::string doc((std::istreambuf_iterator<char>(in)), std::istreambuf_iterator<char>());
  for (const auto& spec : schema.params) {
    INFO(spec.name);
    CHECK(all.out.find("\n" + spec.name + " ") != std::string::npos);
    CHECK(doc.find("| `" + spec.name + "` |") != std::string::npos);
  }
  for (const auto& section : schema.sections) {
    INFO(section.name);
    CHECK(doc.find("| **`" + section.name + "`** | section |") != std::string::npos);
  }
  // The documented table is the generated one, byte for byte.
  const Run markdown = run_flipper("config explain --markdown", false);
  REQUIRE(markdown.status == 0);
  const std::string begin = "<!-- config-keys:begin", end = "<!-- config-keys:end -->";
  const std::size_t b = doc.find(begin), e = doc.find(end);
  REQUIRE(b != std::string::npos);
  REQUIRE(e != std::string::npos);
  const std::size_t table = doc.find('\n', b) + 1;
  CHECK(doc.substr(table, e - table) == markdown.out);
  // One key: its row, with the range and default as declared.
  const Run one = run_flipper("config explain session.k", false);
  CHECK(one.status == 0);
  CHECK(one.out.find("session.k  int   3        [1, 1000]  candidates shown per query") !=
        std::string::npos);
  const Run unknown = run_flipper("config explain sesion");
  CHECK(unknown.status == 2);
  CHECK(unknown.out.find("flipper config explain: [bad_config] no config key or section 'sesion' "
                         "(did you mean 'session'?)") != std::string::npos);
}

TEST_CASE("flipper config print shows the effective config without loading plugins", "[cli]") {
  const Run r =
      run_flipper("config print --set planner.plugin=not_a_plugin --set session.k=7", false);
  CHECK(r.status == 0);
  CHECK(r.out.find("plugin: not_a_plugin") != std::string::npos);
  CHECK(r.out.find("  k: 7\n") != std::string::npos);
  const Run bad = run_flipper("config print --set session.k=0");
  CHECK(bad.status == 2);
  CHECK(bad.out.find("flipper config print: [bad_config] config <embedded default>: config key "
                     "'session.k' = 0 is out of range [1, 1000]") != std::string::npos);
}
