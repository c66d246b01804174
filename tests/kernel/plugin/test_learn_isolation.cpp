// A scorer's learn in a child process (kernel/plugin_checks.hpp checked_learn,
// docs/plugins-untrusted.md §6): the learnt weights cross as values, each checked (whole bytes,
// finite numbers); a scorer without sdk::WeightValues or IncrementalScorer crosses as its whole
// saved state; an incremental scorer without values learns in process; a learn that crashes is
// plugin_crashed naming the learn, and the scorer in the parent is unchanged.
#include <unistd.h>

#include <catch2/catch.hpp>
#include <csignal>
#include <limits>
#include <memory>
#include <string>

#include "flipper/kernel/isolation.hpp"
#include "flipper/kernel/plugin_checks.hpp"
#include "flipper/sdk/answer_wire.hpp"
#include "flipper/sdk/errors.hpp"
#include "flipper/sdk/scorer.hpp"

using namespace flipper;

namespace {

// Counts its accepts in its state ("n=3"), or crashes when told to; records where it learnt.
class CountingScorer : public sdk::Scorer {
 public:
  int n = 0;
  bool crash = false;
  pid_t learnt_in = 0;

 protected:
  double do_score_node(const sdk::Derivation&, const sdk::ScoreContext&) const override {
    return 0;
  }
  void do_features(const sdk::Derivation&, const sdk::ScoreContext&,
                   sdk::FeatureVector&) const override {}
  void do_learn(const std::vector<sdk::Candidate>&, std::size_t,
                const sdk::ScoreContext&) override {
    if (crash) std::raise(SIGSEGV);
    learnt_in = ::getpid();
    ++n;
  }
  std::string do_save_state() const override { return "n=" + std::to_string(n); }
  void do_load_state(std::string_view state) override {
    n = std::stoi(std::string(state.substr(2)));
  }
};

// The same, incremental (its changes reported) but without sdk::WeightValues.
class IncrementalOnly : public CountingScorer, public sdk::IncrementalScorer {
 protected:
  std::vector<sdk::WeightChange> do_pending_changes() const override { return {}; }
  void do_commit_changes() override {}
  void do_discard_changes() override {}
  void do_apply_changes(const std::vector<sdk::WeightChange>&) override {}
};

template <class S>
kernel::PluginRef<sdk::Scorer> isolated(const std::shared_ptr<S>& scorer) {
  return kernel::PluginRef<sdk::Scorer>(std::static_pointer_cast<sdk::Scorer>(scorer),
                                        kernel::PluginId{"scorer", "counting", "/p/libc.so"})
      .with_isolation(kernel::Isolation::process);
}

void learn(const kernel::PluginRef<sdk::Scorer>& scorer) {
  const std::vector<sdk::Candidate> candidates(1);
  kernel::checked_learn(scorer, candidates, 0, sdk::ScoreContext{}, sdk::StopCondition{});
}

}  // namespace

TEST_CASE("learnt weights cross as values, whole and finite, or not at all", "[isolation][learn]") {
  const std::vector<sdk::WeightChange> values = {{"", "rule:r12", 0.1 + 0.2, 3.5},
                                                 {"ann", "#accepts", -1e-300, 0}};
  const std::string bytes = sdk::host::to_bytes(values);
  const auto back = sdk::host::weight_values_of(bytes);
  REQUIRE(back.has_value());
  REQUIRE(back->size() == 2u);
  CHECK((*back)[0].model.empty());
  CHECK((*back)[0].feature == "rule:r12");
  CHECK((*back)[0].weight == 0.1 + 0.2);  // to the last bit
  CHECK((*back)[1].model == "ann");
  CHECK((*back)[1].weight == -1e-300);
  for (std::size_t n = 0; n < bytes.size(); ++n) {
    INFO("the first " << n << " bytes");
    CHECK_FALSE(sdk::host::weight_values_of(bytes.substr(0, n)).has_value());
  }
  CHECK_FALSE(sdk::host::weight_values_of(bytes + "x").has_value());
  CHECK(sdk::host::weight_values_of(sdk::host::to_bytes(std::vector<sdk::WeightChange>{}))
            .value()
            .empty());
  for (const double bad :
       {std::numeric_limits<double>::quiet_NaN(), std::numeric_limits<double>::infinity()}) {
    auto w = values;
    w[1].weight = bad;
    CHECK_FALSE(sdk::host::weight_values_of(sdk::host::to_bytes(w)).has_value());
    w = values;
    w[0].aux = -bad;
    CHECK_FALSE(sdk::host::weight_values_of(sdk::host::to_bytes(w)).has_value());
  }
  // A count larger than the bytes could hold is refused before anything is allocated.
  std::string huge = bytes;
  huge[7] = '\x7f';
  CHECK_FALSE(sdk::host::weight_values_of(huge).has_value());
}

TEST_CASE("a scorer without values learns in a child and crosses as its whole state",
          "[isolation][learn]") {
  auto scorer = std::make_shared<CountingScorer>();
  learn(isolated(scorer));
  learn(isolated(scorer));
  CHECK(scorer->n == 2);          // the child's state, loaded here
  CHECK(scorer->learnt_in == 0);  // never learnt in this process
}

TEST_CASE("a learn that crashes is plugin_crashed, the scorer unchanged", "[isolation][learn]") {
  auto scorer = std::make_shared<CountingScorer>();
  learn(isolated(scorer));
  scorer->crash = true;
  try {
    learn(isolated(scorer));
    FAIL("no error");
  } catch (const sdk::Error& e) {
    CHECK(std::string(e.code()) == "plugin_crashed");
    CHECK(std::string(e.what()) == "plugin 'counting' (/p/libc.so): learn: SIGSEGV");
  }
  CHECK(scorer->n == 1);
}

TEST_CASE("an incremental scorer without values learns in process", "[isolation][learn]") {
  auto scorer = std::make_shared<IncrementalOnly>();
  learn(isolated(scorer));
  CHECK(scorer->n == 1);
  CHECK(scorer->learnt_in == ::getpid());
}
