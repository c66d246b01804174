// Kill test (naturalization.md §5): a writer killed with SIGKILL at random moments never loses an
// acknowledged definition and never corrupts the store.
#include <signal.h>
#include <sqlite3.h>
#include <sys/wait.h>
#include <unistd.h>

#include <catch2/catch.hpp>
#include <chrono>
#include <filesystem>
#include <random>
#include <set>
#include <string>
#include <thread>

#include "flipper/kernel/lexicon_store.hpp"

namespace fs = std::filesystem;

namespace {

/// Runs the driver until killed after `ms`; returns the indices it acknowledged.
std::vector<long> run_and_kill(const std::string& store, long start, int ms) {
  int out[2];
  REQUIRE(pipe(out) == 0);
  const pid_t pid = fork();
  REQUIRE(pid >= 0);
  if (pid == 0) {
    dup2(out[1], STDOUT_FILENO);
    close(out[0]);
    close(out[1]);
    const std::string s = std::to_string(start);
    execl(KILL_DRIVER, KILL_DRIVER, store.c_str(), s.c_str(), static_cast<char*>(nullptr));
    _exit(127);
  }
  close(out[1]);
  std::this_thread::sleep_for(std::chrono::milliseconds(ms));
  kill(pid, SIGKILL);
  int status = 0;
  waitpid(pid, &status, 0);
  // Everything the driver wrote before dying is in the pipe: those are the answers received.
  std::string text;
  char buf[4096];
  ssize_t n;
  while ((n = read(out[0], buf, sizeof buf)) > 0) text.append(buf, static_cast<std::size_t>(n));
  close(out[0]);
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

std::string integrity(const std::string& path) {
  sqlite3* db = nullptr;
  REQUIRE(sqlite3_open_v2(path.c_str(), &db, SQLITE_OPEN_READWRITE, nullptr) == SQLITE_OK);
  sqlite3_stmt* st = nullptr;
  REQUIRE(sqlite3_prepare_v2(db, "PRAGMA integrity_check", -1, &st, nullptr) == SQLITE_OK);
  REQUIRE(sqlite3_step(st) == SQLITE_ROW);
  std::string result = reinterpret_cast<const char*>(sqlite3_column_text(st, 0));
  sqlite3_finalize(st);
  sqlite3_close(db);
  return result;
}

}  // namespace

TEST_CASE("SIGKILL at random moments loses no acknowledged definition", "[lexicon][kill]") {
  const fs::path dir =
      fs::temp_directory_path() / ("flipper-kill-" + std::to_string(std::random_device{}()));
  fs::create_directories(dir);
  const std::string store = (dir / "lexicon.db").string();
  std::mt19937 rng(20180917);
  std::uniform_int_distribution<int> delay(5, 120);
  std::set<long> acknowledged;
  long next = 0;
  int kills_with_acks = 0;
  for (int round = 0; round < 30; ++round) {
    const auto acks = run_and_kill(store, next, delay(rng));
    if (!acks.empty()) ++kills_with_acks;
    for (long a : acks) acknowledged.insert(a);
    next += 100000;  // each round's heads are distinct

    REQUIRE(integrity(store) == "ok");
    flipper::kernel::LexiconStore reopened(store);  // also the store's own checks
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
