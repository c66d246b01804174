// Run folders, sweeps and shards, parallel processes, SHA-256, manifests' provenance checks.
#include <sys/mman.h>
#include <unistd.h>

#include <csignal>

#include <atomic>
#include <catch2/catch.hpp>
#include <cstdio>
#include <filesystem>
#include <fstream>
#include <set>

#include "flipper/kernel/plugin_ref.hpp"
#include "flipper/record/checksum.hpp"
#include "flipper/record/manifest.hpp"
#include "flipper/record/processes.hpp"
#include "flipper/record/run_folder.hpp"
#include "flipper/record/sweep.hpp"
#include "flipper/sdk/errors.hpp"
#include "record_scratch.hpp"

using namespace flipper::record;
namespace fs = std::filesystem;
using nlohmann::json;

namespace {
using recordtest::scratch;
std::string shell_output(const std::string& cmd) {
  std::string out;
  FILE* p = ::popen(cmd.c_str(), "r");
  REQUIRE(p != nullptr);
  char buf[256];
  while (std::fgets(buf, sizeof buf, p) != nullptr) out += buf;
  ::pclose(p);
  return out;
}
}  // namespace

TEST_CASE("every run gets a new folder, and none is overwritten", "[record][runs]") {
  const fs::path parent = scratch("runs") / "out";  // created by the first run
  const std::string a = create_run_folder(parent.string(), "dev-replay");
  const std::string b = create_run_folder(parent.string(), "dev-replay");
  const std::string c = create_run_folder(parent.string(), "dev-replay");
  CHECK(a != b);
  CHECK(b != c);
  // <stem>-YYYYMMDD-HHMMSS: 10 + 1 + 8 + 1 + 6 characters; a second run in the same second adds -2.
  CHECK(fs::path(a).filename().string().size() == std::string("dev-replay-20250101-120000").size());
  for (const auto& dir : {a, b, c}) CHECK(fs::is_directory(dir));
  if (fs::path(a).filename().string().substr(0, 26) ==
      fs::path(b).filename().string().substr(0, 26))
    CHECK(fs::path(b).filename().string().substr(26) == "-2");
  // No `latest` until a run is final; then it links that run, relative (the parent can move).
  CHECK_FALSE(fs::exists(fs::symlink_status(parent / "latest")));
  mark_latest(b);
  CHECK(fs::read_symlink(parent / "latest") == fs::path(b).filename());
  mark_latest(c + "/");
  CHECK(fs::read_symlink(parent / "latest") == fs::path(c).filename());
  // A run folder is no parent of runs.
  std::ofstream(fs::path(a) / "manifest.json") << "{}";
  CHECK_THROWS_WITH(create_run_folder(a, "x"), Catch::Contains("is a run folder"));
  CHECK(is_run_folder(a));
  CHECK_FALSE(is_run_folder(b));
  // A user's own folder named `latest` is left alone.
  const fs::path other = scratch("runs-latest");
  fs::create_directories(other / "latest");
  mark_latest(create_run_folder(other.string(), "e"));
  CHECK(fs::is_directory(other / "latest"));
  CHECK_FALSE(fs::is_symlink(other / "latest"));
}

TEST_CASE("directory names from readable names", "[record][runs]") {
  CHECK(directory_name("planner.plugin=ompl,planner.params.seed=2") ==
        "planner.plugin=ompl+planner.params.seed=2");
  CHECK(directory_name("../../x") == ".._.._x");
  CHECK(directory_name("a b/c") == "a_b_c");
  CHECK(directory_name("..") == "_..");
  // 120 characters stay; 121 are cut to 100 plus 12 hex digits of the name's SHA-256.
  const std::string at(120, 'x'), over(121, 'x');
  CHECK(directory_name(at) == at);
  CHECK(directory_name(over) == std::string(100, 'x') + "-" + sha256_text(over).substr(0, 12));
  CHECK(directory_name(over + "a") != directory_name(over + "b"));
}

TEST_CASE("a sweep is the cartesian product, last axis fastest", "[record][sweep]") {
  const auto points = expand_grid(
      {{"planner.plugin", {"astar", "ompl"}}, {"planner.params.seed", {"1", "2", "3"}}});
  REQUIRE(points.size() == 6);
  std::vector<std::string> names;
  for (const auto& p : points) names.push_back(point_name(p));
  CHECK(names == std::vector<std::string>{"planner.plugin=astar,planner.params.seed=1",
                                          "planner.plugin=astar,planner.params.seed=2",
                                          "planner.plugin=astar,planner.params.seed=3",
                                          "planner.plugin=ompl,planner.params.seed=1",
                                          "planner.plugin=ompl,planner.params.seed=2",
                                          "planner.plugin=ompl,planner.params.seed=3"});
  CHECK(expand_grid({}).size() == 1);  // no sweep: one point, no settings
  CHECK(point_name(expand_grid({}).front()).empty());
  CHECK(is_seed_key("planner.params.seed"));
  CHECK(is_seed_key("scorer.params.init_seed"));
  CHECK_FALSE(is_seed_key("planner.params.seeds"));
  CHECK_FALSE(is_seed_key("seedling"));
}

TEST_CASE("shards: I/N from 0, every N-th variant, together every variant once",
          "[record][sweep]") {
  CHECK(parse_shard("0/1").count == 1);
  const Shard s = parse_shard("2/4");
  CHECK(s.index == 2);
  CHECK(s.count == 4);
  CHECK(parse_shard("3/4").index == 3);  // N-1: the last
  CHECK_THROWS_WITH(parse_shard("4/4"),
                    Catch::Contains("from 0 to 3") && Catch::Contains("--array=0-3"));
  CHECK_THROWS_WITH(parse_shard("-1/4"), Catch::Contains("from 0 to 3"));
  CHECK_THROWS_WITH(parse_shard("1/0"), Catch::Contains("at least 1"));
  CHECK_THROWS_WITH(parse_shard("1"), Catch::Contains("expected I/N"));
  CHECK_THROWS_WITH(parse_shard("a/b"), Catch::Contains("two whole numbers"));
  CHECK_THROWS_WITH(parse_shard("1/4x"), Catch::Contains("two whole numbers"));
  for (int n = 1; n <= 7; ++n) {
    std::vector<int> owners(13, 0);
    for (int i = 0; i < n; ++i)
      for (std::size_t v = 0; v < owners.size(); ++v) owners[v] += in_shard(v, {i, n});
    for (int o : owners) CHECK(o == 1);
  }
  CHECK(in_shard(5, {1, 4}));
  CHECK_FALSE(in_shard(5, {0, 4}));
}

TEST_CASE("SHA-256 of texts and files", "[record][checksum]") {
  // FIPS 180-2 examples.
  CHECK(sha256_text("") == "e3b0c44298fc1c149afbf4c8996fb92427ae41e4649b934ca495991b7852b855");
  CHECK(sha256_text("abc") == "ba7816bf8f01cfea414140de5dae2223b00361a396177a9cb410ff61f20015ad");
  // A file of several read blocks against coreutils' sha256sum.
  const fs::path f = scratch("sha") / "data.bin";
  {
    std::ofstream out(f, std::ios::binary);
    for (int i = 0; i < 200000; ++i) out.put(static_cast<char>((i * 7919) % 251));
  }
  const std::string expected = shell_output("sha256sum '" + f.string() + "'").substr(0, 64);
  CHECK(sha256_file(f.string()) == expected);
  CHECK_THROWS_WITH(sha256_file((f.parent_path() / "missing").string()),
                    Catch::Contains("cannot read"));
}

TEST_CASE("tasks run in child processes, at most `jobs` at once", "[record][processes]") {
  // Counters in memory shared with the children.
  auto* shared = static_cast<std::atomic<int>*>(
      ::mmap(nullptr, 4096, PROT_READ | PROT_WRITE, MAP_SHARED | MAP_ANONYMOUS, -1, 0));
  REQUIRE(shared != MAP_FAILED);
  std::atomic<int>& running = shared[0];
  std::atomic<int>& most = shared[1];
  std::atomic<int>& done = shared[2];
  running = most = done = 0;
  int local = 0;
  const auto status = run_in_processes(7, 2,
                                       [&](std::size_t) {
                                         const int now = ++running;
                                         for (int m = most.load();
                                              now > m && !most.compare_exchange_weak(m, now);) {
                                         }
                                         volatile double x = 0;
                                         for (int k = 0; k < 2000000; ++k) x = x + k;
                                         ++local;  // the child's copy: never the caller's
                                         ++done;
                                         --running;
                                         return 0;
                                       },
                                       {});
  CHECK(status == std::vector<int>(7, 0));
  CHECK(done == 7);
  CHECK(most <= 2);
  CHECK(most >= 1);
  CHECK(local == 0);

  // A failure stops what has not started; an exception is status 1 and reported in the child.
  done = 0;
  const auto failing = run_in_processes(
      5, 1,
      [&](std::size_t i) {
        ++done;
        if (i == 1) throw flipper::sdk::Error("bad_config", "variant 1 is broken");
        return 0;
      },
      [&](const std::exception& e) {
        shared[3] = std::string(e.what()) == "variant 1 is broken" ? 1 : 0;
      });
  CHECK(failing == std::vector<int>{0, 1, -1, -1, -1});
  CHECK(done == 2);
  CHECK(shared[3] == 1);
  CHECK(run_in_processes(1, 4, [](std::size_t) { return 7; }, {}) == std::vector<int>{7});
  CHECK(available_cores() >= 1);
  ::munmap(shared, 4096);
}

TEST_CASE("a task that crashes, hangs or throws costs itself only, and says where it died",
          "[record][processes]") {
  // A "plugin" call that dies of a signal: the child's handler names plugin and operation.
  const flipper::kernel::PluginRef<int> plugin(
      std::make_shared<int>(0), flipper::kernel::PluginId{"planner", "crashy", "/x/crashy.so"});
  IsolationOptions options;
  options.jobs = 2;
  options.wall_backstop_s = 1;
  const auto exits = run_isolated(6, options, [&](std::size_t i) {
    switch (i) {
      case 1:
        plugin.call("plan", [](const int&) { std::raise(SIGSEGV); });
        return 0;
      case 2:
        plugin.call("tour", [](const int&) { std::abort(); });
        return 0;
      case 3:  // a hang inside a plugin call, ended by the backstop
        plugin.call("plan", [](const int&) {
          for (;;) ::pause();
        });
        return 0;
      case 4:
        throw flipper::sdk::Error("bad_world", "world 4 is broken");
      case 5:
        std::raise(SIGSEGV);  // outside any plugin call
        return 0;
      default:
        return 0;
    }
  });
  REQUIRE(exits.size() == 6);
  CHECK(exits[0].ok());
  CHECK(exits[0].kind() == "ok");
  CHECK(exits[1].kind() == "plugin_crashed");
  CHECK(exits[1].signal == SIGSEGV);
  CHECK(exits[1].describe() == "plugin_crashed: plugin 'crashy' (/x/crashy.so): plan: SIGSEGV");
  CHECK(exits[2].describe() == "plugin_crashed: plugin 'crashy' (/x/crashy.so): tour: SIGABRT");
  CHECK(exits[3].kind() == "wall_backstop");
  CHECK(exits[3].describe() ==
        "wall_backstop: still running at the wall-clock backstop, in plugin 'crashy' "
        "(/x/crashy.so): plan");
  CHECK(exits[4].kind() == "failed");
  CHECK(exits[4].status == 1);
  CHECK(exits[4].describe() == "[bad_world] world 4 is broken");
  CHECK(exits[5].kind() == "crashed");
  CHECK(exits[5].describe() == "crashed: SIGSEGV outside any plugin call");
  CHECK(exits[5].status == 128 + SIGSEGV);
  CHECK(signal_name(SIGABRT) == "SIGABRT");
  CHECK(signal_name(64) == "signal 64");
}

TEST_CASE("a re-check warns about what differs in the build, plugins and files",
          "[record][manifest]") {
  json recorded = {
      {"build", {{"flipper", "0.1.0"}, {"sdk", "2.1.0"}, {"commit", "aaa"}, {"dirty", "no"}}},
      {"inputs", {{{"role", "experiment"}, {"path", "/x/e.yaml"}, {"sha256", "e1"}}}},
      {"corpus", {{"files", {{{"name", "queries.jsonl"}, {"sha256", "q1"}}}}}},
      {"variants",
       {{{"name", "v"},
         {"config", {{"effective", "a: 1\nb: 2\n"}, {"files", json::array()}}},
         {"plugins",
          {{{"section", "planner"},
            {"name", "astar"},
            {"version", "1.0.0"},
            {"sha256", "p1"},
            {"file", "/x/astar.so"}}}}}}}};
  CHECK(provenance_warnings(recorded, recorded).empty());
  json now = recorded;
  now["build"]["commit"] = "bbb";
  now["inputs"][0]["path"] = "/elsewhere/e.yaml";  // moved, same content: no warning
  now["corpus"]["files"][0]["sha256"] = "q2";
  now["variants"][0]["config"]["effective"] = "a: 1\nb: 3\n";
  now["variants"][0]["plugins"][0]["sha256"] = "p2";
  now["variants"][0]["plugins"][0]["file"] = "/y/astar.so";
  const auto w = provenance_warnings(recorded, now);
  REQUIRE(w.size() == 4);
  CHECK(w[0] == "flipper commit differs: recorded aaa, now bbb");
  CHECK(w[1] == "variant 'v': the effective config differs (line 2: 'b: 3' was 'b: 2')");
  CHECK(w[2] == "plugin planner 'astar' sha256 differs: recorded p1, now p2 (/y/astar.so)");
  CHECK_THAT(w[3], Catch::StartsWith("corpus file queries.jsonl: checksum differs"));
}

TEST_CASE("manifests are written whole and read back, a folder without one is refused",
          "[record][manifest]") {
  const fs::path dir = scratch("manifest");
  write_manifest(dir.string(), {{"kind", "replay"}, {"n", 3}});
  CHECK(read_manifest(dir.string())["n"] == 3);
  CHECK_FALSE(fs::exists(dir / "manifest.json.tmp"));
  CHECK_THROWS_WITH(read_manifest((dir / "none").string()), Catch::Contains("is not a run folder"));
  std::ofstream(dir / "manifest.json") << "{not json";
  CHECK_THROWS_WITH(read_manifest(dir.string()), Catch::Contains("is not valid JSON"));
  const json files = folder_json(FLIPPER_SOURCE_DIR "/tests/apps/replay/data");
  REQUIRE(files["files"].size() == 4);
  CHECK(files["files"][0]["name"] == "definitions.jsonl");  // by name
  CHECK(files["files"][0]["sha256"] ==
        sha256_file(FLIPPER_SOURCE_DIR "/tests/apps/replay/data/definitions.jsonl"));
}
