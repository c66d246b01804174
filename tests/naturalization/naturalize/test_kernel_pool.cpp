// Several kernels over one lexicon store rank exactly as one kernel does (docs/naturalization.md
// §5 "Learned state", docs/studio.md §5): a script of requests runs once with every session on
// one kernel, and once with the sessions spread over two kernels (moving between them with
// Session::rebind, as the studio's kernel pool does); every answer must be the same, scores
// and use counts bit for bit (JSON numbers are printed to round-trip).
#include <catch2/catch.hpp>
#include <memory>
#include <string>
#include <vector>

#include "flipper/kernel/session.hpp"
#include "flipper/wiring/session_factory.hpp"
#include "naturalize_fixture.hpp"

namespace {

using flipper::kernel::Json;
using flipper::kernel::Session;
using flipper::wiring::SessionHost;

struct Step {
  int kernel;   ///< which kernel answers (ignored by the one-kernel run)
  int session;  ///< which session asks
  Json request;
};

struct Kernels {
  std::vector<SessionHost> hosts;
  std::vector<std::unique_ptr<Session>> sessions;
  std::vector<int> at;  ///< the kernel each session is on

  Kernels(const std::string& store, int kernels, int sessions_n,
          const std::vector<std::string>& extra) {
    std::vector<std::string> sets = extra;
    sets.push_back("lexicon.path=" + store);
    for (int i = 0; i < kernels; ++i)
      hosts.push_back(flipper::wiring::open_host(std::nullopt, sets));
    for (int i = 0; i < sessions_n; ++i) {
      sessions.push_back(hosts[0].open());
      at.push_back(0);
    }
  }

  Json run(const Step& step) {
    const int k = std::min(step.kernel, static_cast<int>(hosts.size()) - 1);
    Session& s = *sessions[static_cast<std::size_t>(step.session)];
    auto& where = at[static_cast<std::size_t>(step.session)];
    if (where != k) {
      s.rebind(hosts[static_cast<std::size_t>(k)].runtime,
               hosts[static_cast<std::size_t>(k)].extensions);
      where = k;
    }
    s.activate();
    Json answer = s.handle(step.request);
    answer.erase("ms");  // wall time
    return answer;
  }
};

Json query(const std::string& text) {
  return {{"op", "query"}, {"text", text}};
}
Json accept(int rank) {
  return {{"op", "accept"}, {"rank", rank}};
}

// Two users teach, accept (so weights and use counters change) and ask on alternating kernels;
// session 0 asks on kernel 0 and accepts on kernel 1 (its pending answer moves with it), once
// with a rule kernel 1 has not seen yet.
std::vector<Step> script(const std::string& ambiguous) {
  return {
      {0, 0, {{"op", "user"}, {"name", "ana"}}},
      {1, 1, {{"op", "user"}, {"name", "bob"}}},
      {0, 0, {{"op", "define"}, {"head", "zig left"}, {"body", {"move left", "move left"}}}},
      {0, 0, query("zig left")},
      {1, 0, accept(0)},  // kernel 1 has not seen the rule yet
      {1, 1, query("zig left")},
      {1, 1, accept(0)},
      {0, 0, query(ambiguous)},
      {0, 0, accept(1)},
      {1, 1, query(ambiguous)},
      {1, 1, accept(1)},
      {0, 0, query(ambiguous)},
      {1, 0, accept(1)},
      {0, 1, query(ambiguous)},
      {1, 0, query(ambiguous)},
      {0, 1, query("zig left")},
      {1, 0, {{"op", "rules"}}},
      {0, 1, {{"op", "rules"}}},
  };
}

void same_answers(const std::vector<std::string>& extra) {
  const std::string ambiguous = "pick item not is red and is green";
  const auto steps = script(ambiguous);
  Kernels one(flipper::testsupport::scratch_path("pool-one") + ".sqlite", 1, 2, extra);
  Kernels two(flipper::testsupport::scratch_path("pool-two") + ".sqlite", 2, 2, extra);
  for (std::size_t i = 0; i < steps.size(); ++i) {
    const Json a = one.run(steps[i]);
    const Json b = two.run(steps[i]);
    INFO("step " << i << ": " << steps[i].request.dump());
    REQUIRE(a.value("ok", false));
    CHECK(b.dump() == a.dump());
  }
  // The script exercises what it claims: the ambiguous query has several readings, and the
  // accepts changed its scores (so learned weights took part in the comparison).
  const Json first =
      Kernels(flipper::testsupport::scratch_path("pool-fresh") + ".sqlite", 1, 1, extra)
          .run({0, 0, query(ambiguous)});
  const Json last = one.run({0, 1, query(ambiguous)});
  REQUIRE(first["candidates"].size() >= 2);
  CHECK(first["candidates"].dump() != last["candidates"].dump());
}

}  // namespace

TEST_CASE("two kernels over one store answer exactly as one kernel (global weights)",
          "[naturalize][pool]") {
  same_answers({});
}

TEST_CASE("two kernels over one store answer exactly as one kernel (per-user weights)",
          "[naturalize][pool]") {
  same_answers({"lexicon.weights=per_user"});
}
