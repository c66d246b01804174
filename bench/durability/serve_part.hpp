#pragma once
// The `flipper serve` part of bench_durability (serve_part.cpp): concurrent HTTP clients on a
// pool of kernels sharing one store, at lexicon.durability full with and without group commit
// and at normal (docs/naturalization.md §5 "Group commit").
#include <cstdint>
#include <filesystem>
#include <string>
#include <vector>

namespace flipper::bench::durability {

/// One round's settings.
struct ServeRound {
  std::string level;  ///< lexicon.durability
  bool group = true;  ///< lexicon.group_commit
  int kernels = 4;    ///< serve.kernels
  int clients = 8;    ///< concurrent sessions, one HTTP connection each
  int ops = 20;       ///< defines, then query + accept pairs, per client
};

/// What a round measured: round trips (client clock, ms) and the server's group-commit counters
/// (zero without group commit).
struct ServeTimes {
  std::vector<double> accept_ms, define_ms;
  std::uint64_t writes = 0, syncs = 0;
};

/// Starts `flipper serve` on a fresh store `store`, runs the clients, stops it (SIGTERM) and adds
/// what it measured to `into`. Throws on an answer that is not ok.
void serve_round(const std::string& flipper, const std::filesystem::path& store,
                 const ServeRound& round, ServeTimes& into);

}  // namespace flipper::bench::durability
