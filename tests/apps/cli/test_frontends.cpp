// flipper execs <exe>/../libexec/flipper-frontends for `serve`, `dds` and DDS services
// (apps/cli/frontends.hpp): flipper itself maps no network library, the two binaries fail alike,
// and a missing, broken or mismatched front-end program is named in a clear error.
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

/// A copy of build/bin/flipper in <dir>/bin with the build's lib/ and share/ (plugins, configs)
/// but no libexec/.
std::string copied_flipper(const std::string& dir) {
  fs::create_directories(fs::path(dir) / "bin");
  fs::create_directory_symlink(kBuild + "/lib", fs::path(dir) / "lib");
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

TEST_CASE("flipper links no network library and flipper-frontends links them", "[cli][frontends]") {
  const auto lite = needed(kBuild + "/bin/flipper");
  for (const char* lib : {"libddsc", "libcpp-httplib", "libssl", "libcrypto"}) {
    INFO(lib);
    CHECK(lite.count(lib) == 0);
  }
  // serve (Boost.Beast: header-only, no library of its own; libsodium for accounts) and DDS
  // (libddsc; OpenSSL for DDS Security keystores) live in flipper-frontends.
  const auto full = needed(kBuild + "/libexec/flipper-frontends");
  CHECK(full.count("libddsc") == 1);
  CHECK(full.count("libsodium") == 1);
  CHECK(full.count("libcpp-httplib") == 0);
}

TEST_CASE("serve and dds fail through flipper-frontends in the one error format",
          "[cli][frontends]") {
  const Run dds = run_flipper("dds --set publish.plans=xx");
  CHECK(dds.status == 2);
  CHECK(dds.out ==
        "flipper dds: [bad_config] config <embedded default>: config key 'publish.plans' = 'xx' "
        "must be one of: none, dds\n");
  const Run serve = run_flipper("serve --set serve.web_dir=/nonexistent/web");
  CHECK(serve.status == 2);
  CHECK(serve.out ==
        "flipper serve: [bad_config] serve.web_dir '/nonexistent/web' has no index.html\n");
  // Misuse is caught by flipper itself, before any exec.
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

TEST_CASE("a missing or broken flipper-frontends is named in the error", "[cli][frontends]") {
  const std::string dir = scratch_dir("frontends-missing");
  const std::string flipper = copied_flipper(dir);
  const std::string program = dir + "/libexec/flipper-frontends";
  const Run version = run_command(flipper + " --version");
  CHECK(version.status == 0);  // everything else works without it

  const Run serve = run_command(flipper + " serve");
  CHECK(serve.status == 1);
  CHECK(serve.out == "flipper serve: [frontend_missing] cannot run the front-end program '" +
                         program +
                         "': No such file or directory (`flipper serve` runs there; it is "
                         "installed with flipper)\n");
  const Run session = run_command(flipper +
                                  " session --set publish.plans=dds --set lexicon.path=:memory: "
                                  "</dev/null");
  CHECK(session.status == 1);
  CHECK(contains(session.out,
                 "flipper session: [frontend_missing] cannot run the front-end "
                 "program '" +
                     program + "'"));

  fs::create_directories(dir + "/libexec");
  std::ofstream(program) << "not a program\n";
  fs::permissions(program, fs::perms::owner_all);
  const Run broken = run_command(flipper + " dds");
  CHECK(broken.status == 1);
  CHECK(broken.out == "flipper dds: [frontend_missing] cannot run the front-end program '" +
                          program +
                          "': Exec format error (`flipper dds` runs there; it is installed with "
                          "flipper)\n");
}

TEST_CASE("flipper-frontends refuses to run under another flipper's tag", "[cli][frontends]") {
  const std::string program = fs::canonical(kBuild + "/libexec/flipper-frontends").string();
  // (timeout: without the check, serve would run until stopped.)
  const Run r = run_command("timeout 20 env FLIPPER_FRONTENDS_TAG='flipper 0.0.9 frontends/1' " +
                            program + " serve");
  CHECK(r.status == 1);
  CHECK(r.out == "flipper serve: [frontend_mismatch] the front-end program '" + program +
                     "' is 'flipper 0.1.0 frontends/1' but was started by 'flipper 0.0.9 "
                     "frontends/1' (a mixed install; reinstall flipper)\n");
  // Run directly, without a tag, it is the whole of flipper.
  const Run direct = run_command(program + " --version");
  CHECK(direct.status == 0);
}
