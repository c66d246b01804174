// Group commit (docs/naturalization.md §5 "Group commit"): the commits of one process's
// connections share one WAL sync, each write returns only after a sync that started after its
// COMMIT, a failed sync fails exactly the writes of its batch (and, the WAL being one chain, every
// later one), and on a real store every write stays its own transaction.
#include <catch2/catch.hpp>
#include <chrono>
#include <filesystem>
#include <random>
#include <set>
#include <string>
#include <thread>
#include <vector>

#include "flipper/naturalization/lexicon_store.hpp"
#include "flipper/sdk/errors.hpp"
#include "group_sync.hpp"
#include "thrown_code.hpp"

namespace fs = std::filesystem;
using flipper::naturalization::LexiconStore;
using flipper::naturalization::LexiconStoreOptions;
using flipper::naturalization::StoredDefinition;
using flipper::naturalization::StoredRule;
using flipper::naturalization::sqlite::GroupSync;

using flipper::testsupport::thrown_code;

namespace {

/// Waits until `done()` holds, at most 30 s (a bound, not a timing: it holds within
/// microseconds unless the code under test is broken).
template <class F>
bool wait_for(F&& done) {
  const auto until = std::chrono::steady_clock::now() + std::chrono::seconds(30);
  while (!done()) {
    if (std::chrono::steady_clock::now() > until) return false;
    std::this_thread::yield();
  }
  return true;
}

}  // namespace

TEST_CASE("group commit: the writes made during one sync share the next one", "[group]") {
  GroupSync group;
  constexpr int kFollowers = 6;
  std::atomic<int> syncs_run{0};
  std::atomic<bool> second_sync_done{false};
  std::vector<std::string> order_errors;
  std::mutex errors_mutex;
  // The first writer leads; its sync lasts until every follower has committed (taken a ticket).
  std::thread first([&] {
    group.wait_durable([&]() -> GroupSync::Failure {
      ++syncs_run;
      if (!wait_for([&] { return group.writes() == 1 + kFollowers; }))
        return {"bad_lexicon", "followers never committed"};
      return {};
    });
  });
  REQUIRE(wait_for([&] { return syncs_run.load() == 1; }));
  std::vector<std::thread> followers;
  followers.reserve(kFollowers);
  for (int i = 0; i < kFollowers; ++i)
    followers.emplace_back([&] {
      group.wait_durable([&]() -> GroupSync::Failure {
        ++syncs_run;
        second_sync_done = true;
        return {};
      });
      // A follower committed after the first sync began: only a later sync covers it.
      if (!second_sync_done) {
        const std::lock_guard<std::mutex> lock(errors_mutex);
        order_errors.emplace_back("acknowledged before a sync that covers it");
      }
    });
  first.join();
  for (auto& t : followers) t.join();
  CHECK(order_errors.empty());
  CHECK(group.writes() == 1 + kFollowers);
  CHECK(group.syncs() == 2);  // 7 writes, 2 syncs: the first alone, then the 6 that waited
  CHECK(syncs_run.load() == 2);
}

TEST_CASE("group commit: a failed sync fails exactly its batch, then every later write",
          "[group]") {
  GroupSync group;
  std::atomic<int> syncs_run{0};
  std::string first_code = "unset";
  std::thread first([&] {
    first_code = thrown_code([&] {
      group.wait_durable([&]() -> GroupSync::Failure {
        ++syncs_run;
        if (!wait_for([&] { return group.writes() == 3; }))
          return {"bad_lexicon", "the batch never formed"};
        return {};
      });
    });
  });
  REQUIRE(wait_for([&] { return syncs_run.load() == 1; }));
  // Two writers commit while the first sync runs; their shared sync fails.
  std::string codes[2] = {"unset", "unset"};
  std::vector<std::thread> batch;
  for (auto& code : codes)
    batch.emplace_back([&] {
      code = thrown_code([&] {
        group.wait_durable([&]() -> GroupSync::Failure {
          ++syncs_run;
          return {"lexicon_full", "no space left on the device"};
        });
      });
    });
  first.join();
  for (auto& t : batch) t.join();
  CHECK(first_code.empty());  // acknowledged: its own sync succeeded
  CHECK(codes[0] == "lexicon_full");
  CHECK(codes[1] == "lexicon_full");
  CHECK(group.syncs() == 2);
  // A write after the failure is refused without a sync: frames after a lost one never count.
  bool synced_again = false;
  CHECK(thrown_code([&] {
          group.wait_durable([&]() -> GroupSync::Failure {
            synced_again = true;
            return {};
          });
        }) == "lexicon_full");
  CHECK_FALSE(synced_again);
  CHECK(group.syncs() == 2);
}

TEST_CASE("group commit: connections on one file share syncs, each define stays whole", "[group]") {
  const fs::path dir =
      fs::temp_directory_path() / ("flipper-group-" + std::to_string(std::random_device{}()));
  fs::remove_all(dir);
  fs::create_directories(dir);
  const std::string path = (dir / "lexicon.sqlite").string();
  constexpr std::uint64_t kWriters = 6;
  constexpr std::uint64_t kDefines = 15;
  {
    std::vector<std::unique_ptr<LexiconStore>> stores;
    stores.reserve(kWriters);
    for (std::uint64_t w = 0; w < kWriters; ++w)
      stores.push_back(std::make_unique<LexiconStore>(path));
    const auto before = flipper::naturalization::group_commit_stats(path);
    std::vector<std::thread> writers;
    writers.reserve(kWriters);
    for (std::uint64_t w = 0; w < kWriters; ++w)
      writers.emplace_back([&, w] {
        for (std::uint64_t i = 0; i < kDefines; ++i) {
          StoredDefinition d;
          d.head = "zap" + std::to_string(w) + "x" + std::to_string(i);
          d.body = {"move left"};
          d.author = "u" + std::to_string(w);
          std::vector<StoredRule> rules(2);
          for (std::size_t j = 0; j < rules.size(); ++j) {
            rules[j].lhs = "$Action";
            rules[j].rhs = {d.head, std::to_string(j)};
            rules[j].semantics = "{move left}";
            rules[j].author = d.author;
            rules[j].head = d.head;
            rules[j].body = d.body;
            rules[j].how = "simple";
          }
          stores[w]->commit_definition(d, rules);
        }
      });
    for (auto& t : writers) t.join();
    const auto after = flipper::naturalization::group_commit_stats(path);
    CHECK(after.writes - before.writes == kWriters * kDefines);
    CHECK(after.syncs - before.syncs >= 1);
    CHECK(after.syncs - before.syncs <= after.writes - before.writes);
  }
  // Every define whole, ids unique and in creation order (assigned inside each transaction).
  const LexiconStore reopened(path);
  const auto rules = reopened.rules();
  REQUIRE(rules.size() == kWriters * kDefines * 2);
  std::set<std::string> ids;
  for (std::size_t i = 0; i < rules.size(); ++i) {
    ids.insert(rules[i].id);
    CHECK(rules[i].created == static_cast<std::int64_t>(i + 1));
    CHECK(rules[i].id == "r" + std::to_string(i + 1));
  }
  CHECK(ids.size() == rules.size());
  for (std::size_t i = 0; i + 1 < rules.size(); i += 2) CHECK(rules[i].head == rules[i + 1].head);
  // Without group commit (or at durability normal) nothing waits for a shared sync.
  LexiconStoreOptions plain;
  plain.group_commit = false;
  const std::string other = (dir / "plain.sqlite").string();
  {
    LexiconStore store(other, plain);
    StoredDefinition d;
    d.head = "hop";
    d.body = {"move left"};
    d.author = "u";
    store.add_definition(d, {});
    CHECK(flipper::naturalization::group_commit_stats(other).writes == 0);
  }
  fs::remove_all(dir);
}
