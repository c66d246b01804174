// Executor benchmark: every program users accepted in the dev corpus (the original's accepted
// candidate, in canonical text), each run on its world before, with the grid2d world and astar
// planner. Prints the median over several rounds of programs per second (thread CPU time, the
// machine is shared) and the median time per program kind.
#include <algorithm>
#include <cstdio>
#include <ctime>
#include <map>
#include <nlohmann/json.hpp>
#include <string>
#include <vector>

#include "corpus_data.hpp"
#include "flipper/corpus/original_text.hpp"
#include "flipper/kernel/executor.hpp"
#include "flipper/sdk/canonical.hpp"
#include "flipper/sdk/errors.hpp"
#include "plugin_fixture.hpp"

using namespace flipper;
using namespace flipper::testsupport;

namespace {
double cpu_ms() {
  timespec ts{};
  clock_gettime(CLOCK_THREAD_CPUTIME_ID, &ts);
  return static_cast<double>(ts.tv_sec) * 1e3 + static_cast<double>(ts.tv_nsec) / 1e6;
}
double median(std::vector<double> v) {
  std::sort(v.begin(), v.end());
  return v.empty() ? 0 : v[v.size() / 2];
}
}  // namespace

int main() {
  auto world = load_plugin<sdk::World>("grid2d");
  auto planner = load_plugin<sdk::Planner>("astar");
  const auto worlds = corpus_worlds();
  std::map<std::string, nlohmann::json> answers;
  for (auto& a : read_jsonl(study_path("dev/original-answers.jsonl"))) {
    std::string q = a["qid"];
    answers.emplace(std::move(q), std::move(a));
  }
  struct Job {
    sdk::Program program;
    sdk::WorldState start;
    bool loop;
  };
  std::vector<Job> jobs;
  std::map<std::string, sdk::WorldState> loaded;
  for (const auto& q : read_jsonl(study_path("dev/queries.jsonl"))) {
    if (q["kind"] != "accept" || !worlds.count(q["world_id"])) continue;
    auto ans = answers.find(q["for_qid"].get<std::string>());
    if (ans == answers.end()) continue;
    for (const auto& c : ans->second["candidates"]) {
      if (c["formula"] != q["formula"]) continue;
      try {
        const std::string text = corpus::normalize_original_pretty(c["pretty"]);
        const std::string wid = q["world_id"];
        if (!loaded.count(wid)) loaded.emplace(wid, world->load(worlds.at(wid).dump(), "."));
        const bool loop =
            text.find("foreach") != std::string::npos || text.find("while") != std::string::npos;
        jobs.push_back({sdk::read_canonical(text), loaded.at(wid), loop});
      } catch (const sdk::Error&) {
      }
      break;
    }
  }
  const kernel::Executor exec(planner);
  std::vector<double> rates, loop_us, plain_us;
  std::size_t steps = 0;
  for (int round = 0; round < 7; ++round) {
    double loop_ms = 0, plain_ms = 0;
    std::size_t nloop = 0, nplain = 0;
    const double t0 = cpu_ms();
    for (const Job& j : jobs) {
      const double s = cpu_ms();
      const sdk::Outcome o = exec.run(j.program, j.start);
      const double e = cpu_ms() - s;
      steps += o.trace.size();
      (j.loop ? loop_ms : plain_ms) += e;
      (j.loop ? nloop : nplain)++;
    }
    const double total = cpu_ms() - t0;
    rates.push_back(static_cast<double>(jobs.size()) / (total / 1e3));
    loop_us.push_back(nloop ? loop_ms * 1e3 / static_cast<double>(nloop) : 0);
    plain_us.push_back(nplain ? plain_ms * 1e3 / static_cast<double>(nplain) : 0);
  }
  std::printf("executor on %zu accepted corpus programs (study-era worlds), 7 rounds, medians:\n",
              jobs.size());
  std::printf("  throughput            %10.0f programs/s (CPU time)\n", median(rates));
  std::printf("  mean per program, loops (foreach/while)  %8.1f us\n", median(loop_us));
  std::printf("  mean per program, other                  %8.1f us\n", median(plain_us));
  std::printf("  (trace steps produced: %zu)\n", steps);
  return 0;
}
