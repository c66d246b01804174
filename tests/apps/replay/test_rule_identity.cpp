// The rule-identity oracle on the whole dev split (docs/replay.md): every definition replayed in
// log order under the study's conditions, our induced rules against the original's logged ones
// (flipper/replay/rule_oracle.hpp classify_rules). The counts per class are pinned exactly: a
// change of induction that changes any definition's rules fails here and must be explained in
// docs/naturalization.md (§4, its deliberate differences name the definitions that show them).
// The status agreement of the same replay is pinned with it: rules must not buy agreement down.
#include <catch2/catch.hpp>
#include <iostream>

#include "flipper/replay/corpus.hpp"
#include "flipper/replay/metrics.hpp"
#include "flipper/replay/replayer.hpp"

using namespace flipper::replay;

TEST_CASE("dev replay: induced rules per definition against the original's, by class",
          "[replay][rules]") {
  const Corpus corpus = load_corpus(FLIPPER_STUDY_DIR "/dev");
  ReplayOptions o;
  o.sets = {"induction.generalize=false"};  // configs/experiments/dev-replay.yaml
  const ReplayResult r = replay(corpus, o);
  const Metrics m = compute_metrics(r);
  std::cout << "rule identity on dev:";
  for (const auto& [cls, n] : m.rule_identity) std::cout << " " << cls << " " << n << ";";
  std::cout << " $Action hole missing " << m.rule_action_hole << "; status agreement "
            << m.overall.agree << "/" << m.overall.n << "\n"
            << std::flush;
  auto count = [&](const char* cls) {
    auto it = m.rule_identity.find(cls);
    return it == m.rule_identity.end() ? 0 : it->second;
  };
  int compared = 0;
  for (const auto& [cls, n] : m.rule_identity) compared += n;
  CHECK(compared == 296);  // definitions with rules_status found and a comparable rule
  CHECK(count("identical") == 252);
  CHECK(count("present") == 31);
  CHECK(count("subset") == 1);
  CHECK(count("superset") == 4);
  CHECK(count("overlap") == 4);
  CHECK(count("disjoint") == 4);
  CHECK(m.rule_action_hole == 1);
  CHECK(m.overall.n == 3950);
  // 3869 before the coverage tie-break of §4.6, 3890 before its loop-guard tie-break, 3891
  // before the February runs' window alignment of §4.8.
  CHECK(m.overall.agree == 3906);
}
