// A reduced replay of the dev split (every run, its first 150 queries) with floors set from the
// measurements: 1170/1200 statuses agree (97.5 %), 290/293 accepted programs found, 229/286
// executions agree on robot, held items and floor (full split: 96.4 %, 782/807, 568/770).
#include <catch2/catch.hpp>

#include "flipper/kernel/replay/corpus.hpp"
#include "flipper/kernel/replay/metrics.hpp"
#include "flipper/kernel/replay/replayer.hpp"

using namespace flipper::kernel::replay;

TEST_CASE("reduced dev replay agrees with the original's statuses above the floor") {
  const Corpus corpus = load_corpus(FLIPPER_SHARED_DIR "/corpus/dev");
  ReplayOptions o;
  o.sets = {"induction.generalize=false"};
  o.max_queries = 150;
  const ReplayResult r = replay(corpus, o);
  const Metrics m = compute_metrics(r);
  INFO("agreement " << m.overall.agree << "/" << m.overall.n << ", accepts matched "
                    << m.exec.matched << "/" << m.exec.accepts);
  CHECK(m.overall.n == 8 * 150);
  CHECK(m.preloaded == 73);
  CHECK(m.preloaded_ok >= 70);
  CHECK(m.overall.rate() >= 0.95);
  CHECK(m.exec.matched >= m.exec.accepts * 95 / 100);
  CHECK(m.exec.all >= m.exec.compared * 3 / 4);
}
