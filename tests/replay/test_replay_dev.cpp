// A reduced replay of the dev split (two September runs, the first queries of each) with a
// status-agreement floor set from the measured full replay (see the report of scripts/replay-dev).
#include <catch2/catch.hpp>

#include "flipper/kernel/replay/corpus.hpp"
#include "flipper/kernel/replay/metrics.hpp"
#include "flipper/kernel/replay/replayer.hpp"

using namespace flipper::kernel::replay;

TEST_CASE("reduced dev replay agrees with the original's statuses above the floor") {
  const Corpus corpus = load_corpus(FLIPPER_SHARED_DIR "/corpus/dev");
  ReplayOptions o;
  o.sets = {"induction.generalize=false"};
  o.runs = {"sep2018/FridayMorningC", "sep2018/TuesdayAfternoon"};
  o.max_queries = 120;
  const ReplayResult r = replay(corpus, o);
  const Metrics m = compute_metrics(r);
  INFO("agreement " << m.overall.agree << "/" << m.overall.n << ", accepts matched "
                    << m.exec.matched << "/" << m.exec.accepts);
  CHECK(m.overall.n == 240);
  CHECK(m.preloaded_ok >= 35);  // of the 42 expert definitions
  CHECK(m.overall.rate() >= 0.85);
  CHECK(m.exec.matched >= m.exec.accepts * 8 / 10);
}
