// Time per generalized definition (rewrite, equivalence checks, σ) on the study map for bodies
// of 1-10 lines, with the real executor and astar planner, and WordNet similarity.
// Families: `move` lines (moves-to-visit and visit-by-predicate rewritings), `pick` lines (loop
// rolling and pick-by-predicate: the most candidates), and mixed lines (loop rolling only).
#include <benchmark/benchmark.h>

#include "flipper/naturalization/generalizer.hpp"
#include "flipper/sdk/similarity.hpp"
#include "study_env.hpp"

using namespace flipper;

namespace {

struct Fixture {
  testsupport::StudyEnv env;
  std::shared_ptr<sdk::Similarity> wordnet = testsupport::load_plugin<sdk::Similarity>("wordnet");
};

Fixture& fixture() {
  static Fixture f;
  return f;
}

// Stands in for the inducer: counts colour/shape/number leaves (what a head would pack).
double packing(const sdk::Program& p) {
  double s =
      (p->kind == sdk::Kind::Color || p->kind == sdk::Kind::Shape || p->kind == sdk::Kind::Num);
  for (const auto& k : p->kids) s += packing(k);
  return s;
}

sdk::Program body(const char* family, int lines) {
  std::vector<sdk::Program> s;
  const char* mixed[] = {"{visit {world containing item {is red}}}", "{pick item {is red}}",
                         "{move up}", "{drop item }", "{move right}"};
  for (int i = 0; i < lines; ++i) {
    if (std::string(family) == "move")
      s.push_back(testsupport::P(i % 3 == 2 ? "{move up}" : "{move right}"));
    else if (std::string(family) == "pick")
      s.push_back(testsupport::P("{pick item }"));
    else
      s.push_back(testsupport::P(mixed[i % 5]));
  }
  return sdk::make_seq(s);
}

void run(benchmark::State& state, const char* family, sdk::Cell start, int perturbed) {
  auto& f = fixture();
  const sdk::Program b = body(family, static_cast<int>(state.range(0)));
  naturalization::Generalizer g(f.env.rewriter, f.wordnet, f.env.exec,
                                {.perturbed_checks = perturbed});
  const auto head = sdk::tokenize("do the thing with red triangles 3 times");
  std::size_t candidates = 0;
  for (auto _ : state) {
    auto r = g.generalize(head, b, f.env.at(start), packing);
    candidates = r.candidates.size();
    benchmark::DoNotOptimize(r.winner);
  }
  state.counters["candidates"] = static_cast<double>(candidates);
}

void BM_move(benchmark::State& s) {
  run(s, "move", {2, 4}, 0);
}
void BM_pick(benchmark::State& s) {
  run(s, "pick", {7, 4}, 0);
}
void BM_mixed(benchmark::State& s) {
  run(s, "mixed", {2, 4}, 0);
}
void BM_pick_perturbed8(benchmark::State& s) {
  run(s, "pick", {7, 4}, 8);
}

// WordNet with cold caches: a new plugin instance (files mapped on first use) per definition.
void BM_pick_cold_wordnet(benchmark::State& state) {
  auto& f = fixture();
  const sdk::Program b = body("pick", static_cast<int>(state.range(0)));
  const auto head = sdk::tokenize("do the thing with red triangles 3 times");
  for (auto _ : state) {
    auto wordnet = testsupport::load_plugin<sdk::Similarity>("wordnet");
    naturalization::Generalizer g(f.env.rewriter, wordnet, f.env.exec);
    benchmark::DoNotOptimize(g.generalize(head, b, f.env.at({7, 4}), packing).winner);
  }
}

}  // namespace

BENCHMARK(BM_pick_cold_wordnet)
    ->Arg(4)
    ->Arg(10)
    ->Unit(benchmark::kMillisecond)
    ->Repetitions(5)
    ->ReportAggregatesOnly(true);
BENCHMARK(BM_move)
    ->DenseRange(1, 10)
    ->Unit(benchmark::kMillisecond)
    ->Repetitions(5)
    ->ReportAggregatesOnly(true);
BENCHMARK(BM_pick)
    ->DenseRange(1, 10)
    ->Unit(benchmark::kMillisecond)
    ->Repetitions(5)
    ->ReportAggregatesOnly(true);
BENCHMARK(BM_mixed)
    ->DenseRange(1, 10)
    ->Unit(benchmark::kMillisecond)
    ->Repetitions(5)
    ->ReportAggregatesOnly(true);
BENCHMARK(BM_pick_perturbed8)
    ->Arg(1)
    ->Arg(4)
    ->Arg(10)
    ->Unit(benchmark::kMillisecond)
    ->Repetitions(5)
    ->ReportAggregatesOnly(true);
BENCHMARK_MAIN();
