// CLI: build/bin/flipper `plugins` and `config check` as a user runs them; exit status 2 for a
// missing plugin and an unknown key, and a listing that survives broken plugins.
#include "cli_test_support.hpp"
#include "kernel_test_support.hpp"

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
