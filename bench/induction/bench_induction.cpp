// bench_induction [SIZES...]: median time per definition with a lexicon of N induced rules
// already in the parser and the store (default N = 100, 1000, 10000; target <= 20 ms at 1,000
// for induction + store commit), with and without generalization, and the store's size on disk.
#include <algorithm>
#include <chrono>
#include <cstdio>
#include <filesystem>
#include <random>
#include <string>
#include <vector>

#include "flipper/kernel/config.hpp"
#include "flipper/kernel/executor.hpp"
#include "flipper/kernel/runtime.hpp"
#include "flipper/naturalization/lexicon_store.hpp"
#include "flipper/naturalization/naturalizer.hpp"
#include "flipper/wiring/config_schema.hpp"

namespace fs = std::filesystem;
using namespace flipper;

namespace {

/// N synthetic induced rules, vocabulary overlapping real utterances, committed in batches.
void populate(const std::string& path, int n) {
  naturalization::LexiconStore store(path);
  std::mt19937 rng(42);
  const std::vector<std::string> real = {"pick", "drop",  "items", "red",
                                         "to",   "visit", "all",   "go"};
  const std::vector<std::pair<std::string, std::string>> shapes = {
      {"$Number", "{repeat $1 times {move left}}"},
      {"$Color", "{visit {world containing item {is $1}}}"},
      {"$Area", "{foreach point in $1 {{visit point};{pick every item }}}"}};
  std::int64_t created = store.max_created();
  for (int done = 0; done < n;) {
    std::vector<naturalization::StoredRule> batch;
    for (int i = 0; i < 500 && done < n; ++i, ++done) {
      naturalization::StoredRule r;
      r.created = ++created;
      r.id = "r" + std::to_string(r.created);
      r.lhs = "$Action";
      const auto& [cat, sem] = shapes[rng() % shapes.size()];
      const std::string w1 =
          rng() % 4 == 0 ? real[rng() % real.size()] : "w" + std::to_string(rng() % 400);
      r.rhs = {w1, "w" + std::to_string(done), cat};
      r.semantics = sem;
      r.author = "u" + std::to_string(rng() % 20);
      r.head = "synthetic";
      r.body = {"synthetic"};
      r.how = "best";
      batch.push_back(std::move(r));
    }
    store.add_definition({0, "synthetic", {"synthetic"}, "bench", 0}, batch);
  }
}

double median(std::vector<double> v) {
  std::sort(v.begin(), v.end());
  return v.empty() ? 0 : v[v.size() / 2];
}

std::uintmax_t store_bytes(const std::string& path) {
  std::uintmax_t total = 0;
  for (const char* suffix : {"", "-wal"}) {
    std::error_code ec;
    const auto s = fs::file_size(path + suffix, ec);
    if (!ec) total += s;
  }
  return total;
}

}  // namespace

int main(int argc, char** argv) {
  std::vector<int> sizes;
  for (int i = 1; i < argc; ++i) sizes.push_back(std::stoi(argv[i]));
  if (sizes.empty()) sizes = {100, 1000, 10000};
  const std::vector<std::pair<std::string, std::vector<std::string>>> defs = {
      {"pick 3 items", {"repeat 3 times pick item"}},
      {"visit red triangle", {"visit world containing item is red and is triangle"}},
      {"gather red",
       {"foreach point in world containing item is red {visit point; pick every item is red}"}},
      {"red to room1",
       {"visit world containing item is red", "pick item is red", "visit room1",
        "drop every item is red"}}};
  const fs::path dir =
      fs::temp_directory_path() / ("flipper-bench-induction-" + std::to_string(getpid()));
  fs::create_directories(dir);
  std::printf("%8s %14s %14s %12s %12s %12s %10s %10s\n", "rules", "induce+commit", "with general.",
              "store KiB", "KiB/rule", "restore ms", "commit ms", "induce ms");
  for (int n : sizes) {
    const std::string path = (dir / ("lexicon-" + std::to_string(n) + ".sqlite")).string();
    populate(path, n);
    const double populated_kib = static_cast<double>(store_bytes(path)) / 1024.0;
    double med[2] = {0, 0};
    double restore_ms = 0, commit_ms = 0, induce_ms = 0;
    for (int generalize = 0; generalize < 2; ++generalize) {
      auto config = wiring::load_config(
          std::nullopt, {"lexicon.path=" + path,
                         std::string("induction.generalize=") + (generalize ? "true" : "false")});
      std::shared_ptr<kernel::Runtime> rt = kernel::make_runtime(config);
      const auto r0 = std::chrono::steady_clock::now();
      naturalization::Naturalizer nat(rt,
                                      naturalization::NaturalizeOptions::from_config(rt->config));
      restore_ms =
          std::chrono::duration<double, std::milli>(std::chrono::steady_clock::now() - r0).count();
      kernel::Executor exec(rt->planner);
      std::vector<double> ms;
      for (int i = 0; i < 40; ++i) {
        const auto& [head, body] = defs[static_cast<std::size_t>(i) % defs.size()];
        naturalization::DefineRequest req;
        req.user = "bench";
        req.head = head + " z" + std::to_string(generalize) + "x" + std::to_string(i);
        req.body = body;
        req.before = &rt->default_world;
        req.exec = &exec;
        const auto t0 = std::chrono::steady_clock::now();
        nat.define(req);
        ms.push_back(
            std::chrono::duration<double, std::milli>(std::chrono::steady_clock::now() - t0)
                .count());
      }
      med[generalize] = median(ms);
      if (generalize == 0) {  // the commit alone: a definition with two rules
        std::vector<double> cms;
        auto rules = nat.store().rules();
        std::int64_t created = nat.store().max_created();
        for (int i = 0; i < 20; ++i) {
          std::vector<naturalization::StoredRule> two(rules.end() - 2, rules.end());
          for (auto& r : two) r.id = "c" + std::to_string(r.created = ++created);
          const auto t0 = std::chrono::steady_clock::now();
          nat.store().add_definition({0, "commit", {"commit"}, "bench", 0}, two);
          cms.push_back(
              std::chrono::duration<double, std::milli>(std::chrono::steady_clock::now() - t0)
                  .count());
        }
        commit_ms = median(cms);
        std::vector<double> ims;  // induction alone (parse head and body, packings, rules)
        naturalization::Inducer inducer(rt->parser, rt->scorer, nat.options().induction,
                                        rt->usage.get());
        for (int i = 0; i < 40; ++i) {
          const auto& [head, body] = defs[static_cast<std::size_t>(i) % defs.size()];
          const auto t0 = std::chrono::steady_clock::now();
          auto p =
              inducer.prepare({head + " y" + std::to_string(i), body, "bench", {}, {}}, nullptr);
          inducer.induce(p, p.body, false, nullptr);
          ims.push_back(
              std::chrono::duration<double, std::milli>(std::chrono::steady_clock::now() - t0)
                  .count());
        }
        induce_ms = median(ims);
      }
    }
    std::printf("%8d %11.2f ms %11.2f ms %12.0f %12.3f %12.1f %10.2f %10.2f\n", n, med[0], med[1],
                populated_kib, populated_kib / n, restore_ms, commit_ms, induce_ms);
  }
  fs::remove_all(dir);
  return 0;
}
