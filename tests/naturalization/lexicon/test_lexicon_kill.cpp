// Kill test (docs/naturalization.md §5): a writer killed with SIGKILL at random moments never loses
// an acknowledged definition and never corrupts the store.
#include <catch2/catch.hpp>
#include <chrono>
#include <filesystem>
#include <random>
#include <set>
#include <string>
#include <vector>

#include "child_process.hpp"
#include "flipper/naturalization/lexicon_store.hpp"
#include "sqlite_integrity.hpp"

namespace fs = std::filesystem;

namespace {

/// The indices acknowledged in the driver's "ack N" lines of `text` (a torn last line is none).
std::vector<long> acks_in(const std::string& text) {
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

/// Runs the driver until it has acknowledged `after` definitions (a condition, not a time: a
/// slow sanitizer build or a busy machine kills at the same point of the stream), then kills it
/// while it commits the next; returns the indices it acknowledged.
std::vector<long> run_and_kill(const std::string& store, long start, int after) {
  flipper::testsupport::ChildProcess driver({KILL_DRIVER, store, std::to_string(start)});
  std::string seen;
  for (int got = 0; got < after;) {
    // Bound: one definition commits in ~1 ms in Release; 60 s means the driver is stuck.
    const std::string line = driver.read_line(std::chrono::seconds(60));
    REQUIRE_FALSE(line.empty());
    seen += line + "\n";
    if (line.rfind("ack ", 0) == 0) ++got;
  }
  driver.kill_now();
  // Everything the driver wrote before dying is in the pipe: those are the answers received.
  return acks_in(seen + driver.read_all());
}

}  // namespace

TEST_CASE("SIGKILL at random moments loses no acknowledged definition", "[lexicon][kill]") {
  const fs::path dir =
      fs::temp_directory_path() / ("flipper-kill-" + std::to_string(std::random_device{}()));
  fs::create_directories(dir);
  const std::string store = (dir / "lexicon.db").string();
  std::mt19937 rng(20180917);
  std::uniform_int_distribution<int> after(0, 40);  // 0: killed while it starts up
  std::set<long> acknowledged;
  long next = 0;
  int kills_with_acks = 0;
  for (int round = 0; round < 30; ++round) {
    const auto acks = run_and_kill(store, next, after(rng));
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
