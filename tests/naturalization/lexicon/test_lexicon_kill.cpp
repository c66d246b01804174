// Kill test (docs/naturalization.md §5): a writer killed with SIGKILL at random moments never loses
// an acknowledged definition and never corrupts the store.
#include <catch2/catch.hpp>
#include <chrono>
#include <filesystem>
#include <random>
#include <set>
#include <string>
#include <thread>

#include "child_process.hpp"
#include "flipper/naturalization/lexicon_store.hpp"
#include "sanitizer_build.hpp"
#include "sqlite_integrity.hpp"

namespace fs = std::filesystem;

namespace {

// Sanitizer builds (build-fuzz/) start and write several times slower: kill later, so that the
// kills still land while the writer is committing.
constexpr int kSlowdown = flipper::testsupport::kAddressSanitizer ? 6 : 1;

/// Runs the driver until killed after `ms`; returns the indices it acknowledged.
std::vector<long> run_and_kill(const std::string& store, long start, int ms) {
  flipper::testsupport::ChildProcess driver({KILL_DRIVER, store, std::to_string(start)});
  std::this_thread::sleep_for(std::chrono::milliseconds(ms));
  driver.kill_now();
  // Everything the driver wrote before dying is in the pipe: those are the answers received.
  const std::string text = driver.read_all();
  std::vector<long> acks;
  std::size_t pos = 0;
  while ((pos = text.find("ack ", pos)) != std::string::npos) {
    const std::size_t end = text.find('\n', pos);
    if (end == std::string::npos) break;  // a torn last line was never a complete answer
    acks.push_back(std::stol(text.substr(pos + 4, end - pos - 4)));
    pos = end;
  }
  return acks;
}

}  // namespace

TEST_CASE("SIGKILL at random moments loses no acknowledged definition", "[lexicon][kill]") {
  const fs::path dir =
      fs::temp_directory_path() / ("flipper-kill-" + std::to_string(std::random_device{}()));
  fs::create_directories(dir);
  const std::string store = (dir / "lexicon.db").string();
  std::mt19937 rng(20180917);
  std::uniform_int_distribution<int> delay(5 * kSlowdown, 120 * kSlowdown);
  std::set<long> acknowledged;
  long next = 0;
  int kills_with_acks = 0;
  for (int round = 0; round < 30; ++round) {
    const auto acks = run_and_kill(store, next, delay(rng));
    if (!acks.empty()) ++kills_with_acks;
    for (long a : acks) acknowledged.insert(a);
    next += 100000;            // each round's heads are distinct
    if (!fs::exists(store)) {  // killed before it created the store: nothing was acknowledged
      REQUIRE(acknowledged.empty());
      continue;
    }

    REQUIRE(flipper::testsupport::sqlite_integrity(store) == "ok");
    flipper::naturalization::LexiconStore reopened(store);  // also the store's own checks
    std::set<std::string> heads;
    for (const auto& d : reopened.definitions()) heads.insert(d.head);
    for (long a : acknowledged) {
      INFO("round " << round << ": acknowledged definition " << a);
      REQUIRE(heads.count("head " + std::to_string(a)) == 1);
    }
    // Rules commit with their definition: two per stored definition, never one.
    CHECK(reopened.rules().size() == 2 * reopened.definitions().size());
  }
  CHECK(kills_with_acks >= 20);  // the kills really hit a writer that was committing
  fs::remove_all(dir);
}
