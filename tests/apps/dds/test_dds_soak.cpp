// Randomised soak of lexicon replication (apps/dds/lexicon_replicator.hpp): kSites sites on one
// DDS domain; a fixed-seed schedule of definitions at random live sites, SIGKILLs (some in the
// middle of a definition, before its answer), restarts and late joins. At the end every site is
// brought back up and must converge: every live site the same lexicon (same hash of its sorted
// rules), every acknowledged definition present, none duplicated. Bounded: kSteps steps, every
// wait bounded. FLIPPER_DDS_SOAK_SEED=N replays another schedule; the seed and the figures are
// printed.
#include <chrono>
#include <csignal>
#include <cstdio>
#include <iostream>
#include <optional>
#include <random>

#include "dds_test_support.hpp"
#include "sqlite_integrity.hpp"

using namespace flipper;
using namespace flipper::ddstest;

namespace {

constexpr int kSites = 4;
constexpr int kSteps = 60;
constexpr std::uint64_t kDefaultSeed = 20261127;

// FNV-1a of the sorted rule shapes: one number per lexicon, equal iff the rule sets are equal.
std::uint64_t lexicon_hash(const std::set<std::string>& rules) {
  std::uint64_t h = 1469598103934665603ull;
  for (const auto& r : rules)
    for (unsigned char c : r + "\n") h = (h ^ c) * 1099511628211ull;
  return h;
}

std::set<std::string> heads_of(Site& s) {
  std::set<std::string> out;
  for (const auto& r : s.rules()) out.insert(r["head"].get<std::string>());
  return out;
}

}  // namespace

TEST_CASE("soak: random kills, restarts and late joins converge with nothing lost or doubled",
          "[dds][soak]") {
  const char* env_seed = std::getenv("FLIPPER_DDS_SOAK_SEED");
  const std::uint64_t seed = env_seed != nullptr ? std::stoull(env_seed) : kDefaultSeed;
  std::cout << "dds soak: seed " << seed << " (FLIPPER_DDS_SOAK_SEED), " << kSites << " sites, "
            << kSteps << " steps" << std::endl;
  std::mt19937_64 rng(seed);
  const auto pick = [&](std::size_t n) {
    return static_cast<std::size_t>(std::uniform_int_distribution<std::size_t>(0, n - 1)(rng));
  };
  const auto dir = scratch_dir("soak");
  const int domain = test_domain();
  const auto started_at = std::chrono::steady_clock::now();

  std::vector<std::optional<Site>> sites(kSites);  // engaged: started at least once
  std::vector<bool> live(kSites, false);
  const auto name = [](std::size_t i) { return "s" + std::to_string(i); };
  const auto start = [&](std::size_t i) {
    if (!sites[i])
      sites[i].emplace(name(i), dir, domain);
    else
      sites[i]->start();
    live[i] = true;
    sites[i]->call({{"op", "user"}, {"name", "u" + std::to_string(i)}});
  };
  const auto live_sites = [&] {
    std::vector<std::size_t> out;
    for (std::size_t i = 0; i < kSites; ++i)
      if (live[i]) out.push_back(i);
    return out;
  };
  const std::vector<std::vector<std::string>> bodies = {
      {"move left"}, {"move right", "move up"}, {"move down", "move left"}, {"pick item"}};

  std::set<std::string> acknowledged, maybe;  // heads: answered ok / killed before the answer
  int kills = 0, kills_mid_define = 0, restarts = 0, late_joins = 0;
  start(0);
  start(1);
  int next_head = 0;
  for (int step = 0; step < kSteps; ++step) {
    const auto up = live_sites();
    const std::size_t roll = pick(100);
    if (roll < 55) {  // a definition at a random live site
      Site& s = *sites[up[pick(up.size())]];
      const std::string head = "soak task " + std::to_string(next_head++);
      const json r =
          s.call({{"op", "define"}, {"head", head}, {"body", bodies[pick(bodies.size())]}});
      INFO("step " << step << ": " << r.dump());
      REQUIRE(r["ok"] == true);
      acknowledged.insert(head);
    } else if (roll < 70 && up.size() > 1) {  // SIGKILL, sometimes in the middle of a define
      const std::size_t i = up[pick(up.size())];
      if (pick(2) == 0) {
        const std::string head = "soak task " + std::to_string(next_head++);
        REQUIRE(sites[i]->child->write_line(
            json{{"op", "define"}, {"head", head}, {"body", {"move up"}}}.dump()));
        maybe.insert(head);
        ++kills_mid_define;
      }
      sites[i]->child->kill_now();
      live[i] = false;
      ++kills;
    } else {  // a restart of a killed site, or a late join of a site never started
      std::vector<std::size_t> down;
      for (std::size_t i = 0; i < kSites; ++i)
        if (!live[i]) down.push_back(i);
      if (down.empty()) continue;
      const std::size_t i = down[pick(down.size())];
      (sites[i] ? restarts : late_joins) += 1;
      start(i);
    }
  }
  // Every site up, so every acknowledged definition has a live holder.
  for (std::size_t i = 0; i < kSites; ++i)
    if (!live[i]) {
      (sites[i] ? restarts : late_joins) += 1;
      start(i);
    }
  const auto settled_at = std::chrono::steady_clock::now();
  Site& reference = *sites[0];
  const bool converged = wait_until(
      [&] {
        const std::set<std::string> heads = heads_of(reference);
        if (!std::includes(heads.begin(), heads.end(), acknowledged.begin(), acknowledged.end()))
          return false;
        const std::uint64_t h = lexicon_hash(rule_shapes(reference));
        for (std::size_t i = 1; i < kSites; ++i)
          if (lexicon_hash(rule_shapes(*sites[i])) != h) return false;
        return true;
      },
      std::chrono::seconds(90));
  const auto converged_at = std::chrono::steady_clock::now();
  const auto ms = [](auto d) {
    return std::chrono::duration_cast<std::chrono::milliseconds>(d).count();
  };
  std::cout << "dds soak: " << acknowledged.size() << " acknowledged definitions, " << maybe.size()
            << " killed before their answer; " << kills << " kills (" << kills_mid_define
            << " mid-define), " << restarts << " restarts, " << late_joins
            << " late joins; converged " << (converged ? "in " : "NOT within ")
            << ms(converged_at - settled_at) << " ms after the last restart, "
            << ms(converged_at - started_at) << " ms in all" << std::endl;
  REQUIRE(converged);
  const std::set<std::string> final_heads = heads_of(reference);
  std::printf("dds soak: lexicon hash %016llx, %zu heads at every site\n",
              static_cast<unsigned long long>(lexicon_hash(rule_shapes(reference))),
              final_heads.size());
  for (const auto& head : final_heads) {
    INFO(head);
    CHECK((acknowledged.count(head) + maybe.count(head)) == 1);
  }
  for (auto& s : sites) CHECK(s->child->finish() == 0);
  for (auto& s : sites) {
    INFO(s->name);
    for (const auto& [head, n] : definitions_per_head(s->store)) {
      INFO(head);
      CHECK(n == 1);
    }
    CHECK(testsupport::sqlite_integrity(s->store) == "ok");
  }
  std::filesystem::remove_all(dir);
}
