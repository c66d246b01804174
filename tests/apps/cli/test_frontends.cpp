// `serve`, `dds`, `accounts` and a session's DDS services run in the front-end modules of
// <exe>/../lib/flipper/frontends (apps/cli/frontend_module.hpp): flipper itself maps no network
// library, the commands fail in the one error format, and a missing, broken or foreign module is
// named in a clear error.
#include <sys/stat.h>

#include <filesystem>
#include <set>

#include "cli_test_support.hpp"

using namespace flipper::clitest;
namespace fs = std::filesystem;

namespace {

const std::string kBuild = FLIPPER_BINARY_DIR;

/// The DT_NEEDED libraries of an ELF file, by soname prefix up to ".so" (readelf -d).
std::set<std::string> needed(const std::string& file) {
  std::set<std::string> out;
  FILE* p = ::popen(("readelf -d '" + file + "'").c_str(), "r");
  REQUIRE(p != nullptr);
  std::array<char, 1024> buf{};
  while (std::fgets(buf.data(), buf.size(), p) != nullptr) {
    const std::string line = buf.data();
    const auto open = line.find("(NEEDED)");
    if (open == std::string::npos) continue;
    const auto l = line.find('[');
    const auto so = line.find(".so", l);
    out.insert(line.substr(l + 1, so - l - 1));
  }
  REQUIRE(::pclose(p) == 0);
  return out;
}

/// A copy of build/bin/flipper in <dir>/bin with the build's plugins and share/ (configs) but no
/// front-end modules (<dir>/lib/flipper/frontends).
std::string copied_flipper(const std::string& dir) {
  fs::create_directories(fs::path(dir) / "bin");
  fs::create_directories(fs::path(dir) / "lib" / "flipper");
  fs::create_directory_symlink(kBuild + "/lib/flipper/plugins",
                               fs::path(dir) / "lib" / "flipper" / "plugins");
  fs::create_directory_symlink(kBuild + "/share", fs::path(dir) / "share");
  const auto to = fs::path(dir) / "bin" / "flipper";
  fs::copy_file(kBuild + "/bin/flipper", to);
  return to.string();
}

/// `cmd` with its stderr merged into the output.
Run run_command(const std::string& cmd) {
  return run_shell(cmd + " 2>&1");
}

}  // namespace

TEST_CASE("flipper links no network library and its front-end modules link them",
          "[cli][frontends]") {
  const auto lite = needed(kBuild + "/bin/flipper");
  // libsodium is no network library: flipper's run records take their SHA-256 from it.
  for (const char* lib : {"libddsc", "libcpp-httplib", "libssl", "libcrypto"}) {
    INFO(lib);
    CHECK(lite.count(lib) == 0);
  }
  // serve (Boost.Beast: header-only, no library of its own; libsodium for accounts; OpenSSL
  // for HTTPS, serve.tls.*) and DDS (libddsc; OpenSSL for DDS Security keystores) are modules
  // of their own.
  const std::string modules = kBuild + "/lib/flipper/frontends/";
  const auto serve = needed(modules + "serve.so");
  CHECK(serve.count("libsodium") == 1);
  CHECK(serve.count("libssl") == 1);
  CHECK(serve.count("libcrypto") == 1);
  CHECK(serve.count("libddsc") == 0);
  CHECK(serve.count("libcpp-httplib") == 0);
  const auto dds = needed(modules + "dds.so");
  CHECK(dds.count("libddsc") == 1);
  CHECK(dds.count("libsodium") == 0);
}

TEST_CASE("serve and dds fail through their modules in the one error format", "[cli][frontends]") {
  const Run dds = run_flipper("dds --set publish.plans=xx");
  CHECK(dds.status == 2);
  CHECK(dds.out ==
        "flipper dds: [bad_config] config <embedded default>: config key 'publish.plans' = 'xx' "
        "must be one of: none, dds\n");
  const Run serve = run_flipper("serve --set serve.web_dir=/nonexistent/web");
  CHECK(serve.status == 2);
  CHECK(serve.out ==
        "flipper serve: [bad_config] serve.web_dir '/nonexistent/web' has no index.html\n");
  // Misuse is caught by flipper itself, before any module is loaded.
  const Run usage = run_flipper("serve --bogus");
  CHECK(usage.status == 2);
  CHECK(usage.out ==
        "flipper serve: [usage] The following argument was not expected: --bogus (see --help)\n");
  // A session asking for DDS services runs there too: its DDS config errors come back alike.
  const Run session = run_flipper(
      "session --set publish.plans=dds --set lexicon.path=:memory: "
      "--set lexicon.replication=dds </dev/null");
  CHECK(session.status == 2);
  CHECK(session.out ==
        "flipper session: [bad_config] lexicon.replication: dds needs this site's name in "
        "lexicon.site\n");
}

TEST_CASE("a missing or broken front-end module is named in the error", "[cli][frontends]") {
  const std::string dir = scratch_dir("frontends-missing");
  const std::string flipper = copied_flipper(dir);
  const std::string modules = dir + "/lib/flipper/frontends";
  const Run version = run_command(flipper + " --version");
  CHECK(version.status == 0);  // everything else works without them

  const Run serve = run_command(flipper + " serve");
  CHECK(serve.status == 1);
  CHECK(serve.out ==
        "flipper serve: [frontend_missing] cannot load the front-end module 'serve' "
        "from " +
            modules +
            ": no frontend plugin named 'serve'; available frontend plugins: none; "
            "searched: no existing directory (it is installed with flipper)\n");
  const Run session = run_command(flipper +
                                  " session --set publish.plans=dds --set lexicon.path=:memory: "
                                  "</dev/null");
  CHECK(session.status == 1);
  CHECK(contains(session.out,
                 "flipper session: [frontend_missing] cannot load the front-end "
                 "module 'dds' from " +
                     modules + ": no frontend plugin named 'dds'"));

  fs::create_directories(modules);
  std::ofstream(modules + "/dds.so") << "not a program\n";
  const Run broken = run_command(flipper + " dds");
  CHECK(broken.status == 1);
  CHECK(broken.out ==
        "flipper dds: [frontend_missing] cannot load the front-end module 'dds' "
        "from " +
            modules + ": cannot load plugin library '" + modules +
            "/dds.so': not an ELF shared library (14 bytes, truncated) (it is "
            "installed with flipper)\n");
}

TEST_CASE("an in-tree module runs only under the flipper command of its build",
          "[cli][frontends]") {
  // (timeout: without the check, serve would run until stopped.)
  const Run r = run_command("timeout 20 " + kBuild + "/bin/flipper frontend serve");
  CHECK(r.status == 1);
  CHECK(r.out ==
        "flipper frontend: [frontend_mismatch] the front-end module 'serve' ('flipper 0.1.0 "
        "frontends/3') runs only under `flipper serve` of the same build (a mixed install? "
        "reinstall flipper)\n");
}
