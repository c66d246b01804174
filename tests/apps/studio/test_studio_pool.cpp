// The kernel pool of `flipper serve` (docs/studio.md §5) against the real binary on loopback:
// a cheap request is answered while another session's expensive one runs, and answers do not
// depend on how many kernels the server runs (nor on which of them answered).
#include <atomic>
#include <thread>

#include "studio_server.hpp"

namespace flipper::studiotest {
namespace {

// Seconds of CPU on the default world (each foreach visits every cell).
const char* kExpensive =
    "repeat 40 times { foreach point in world { foreach point in world { visit point } } }";

TEST_CASE("a cheap request is answered while another session's expensive one runs") {
  // The expensive query must finish, not stop: its CPU budgets as far as its wall backstops (it
  // takes seconds of CPU in the sanitizer build, past the 5 s default of session.cpu_budget_ms).
  StudioServer server(
      fresh_dir("pool-cheap"),
      // In process: the pool is tested here, and a fork per plan call (plugins.isolation: process,
      // serve's default; docs/plugins-untrusted.md §6) makes this query of ~10^5 plans minutes.
      {"serve.kernels=2", "session.deadline_ms=120000", "execution.deadline_ms=120000",
       "session.cpu_budget_ms=120000", "execution.cpu_budget_ms=120000",
       "plugins.isolation=in_process"});
  auto heavy_http = server.client();
  heavy_http.set_read_timeout(120);
  const std::string heavy = new_session(heavy_http);
  auto http = server.client();
  const std::string light = new_session(http);
  std::atomic<bool> heavy_done{false};
  std::thread t([&] {
    const Reply r = post_json(heavy_http, heavy, {{"op", "query"}, {"text", kExpensive}});
    heavy_done = true;
    CHECK(r.body["ok"] == true);
  });
  // Five cheap requests in a row: with one kernel, all but perhaps the first would wait for the
  // expensive query to finish.
  int answered_meanwhile = 0;
  for (int i = 0; i < 5; ++i) {
    const Reply r = post_json(http, light, {{"op", "query"}, {"text", "move left"}});
    CHECK(r.body["ok"] == true);
    answered_meanwhile += !heavy_done;
  }
  t.join();
  CHECK(answered_meanwhile == 5);
}

// The answers of a script of two users teaching, accepting and asking, without wall times.
std::vector<std::string> script_answers(int kernels, const std::vector<std::string>& extra) {
  std::vector<std::string> sets = extra;
  sets.push_back("serve.kernels=" + std::to_string(kernels));
  StudioServer server(fresh_dir("pool-script"), sets);
  auto http = server.client();
  const std::string ana = new_session(http), bob = new_session(http);
  const std::vector<std::pair<std::string, json>> steps{
      {ana, {{"op", "define"}, {"head", "zig left"}, {"body", {"move left", "move left"}}}},
      {ana, {{"op", "query"}, {"text", "zig left"}}},
      {ana, {{"op", "accept"}, {"rank", 0}}},
      {bob, {{"op", "query"}, {"text", "zig left"}}},
      {bob, {{"op", "accept"}, {"rank", 0}}},
      {ana, {{"op", "query"}, {"text", "pick item not is red and is green"}}},
      {ana, {{"op", "accept"}, {"rank", 1}}},
      {bob, {{"op", "query"}, {"text", "pick item not is red and is green"}}},
      {bob, {{"op", "accept"}, {"rank", 1}}},
      {ana, {{"op", "query"}, {"text", "pick item not is red and is green"}}},
      {bob, {{"op", "query"}, {"text", "pick item not is red and is green"}}},
      {ana, {{"op", "rules"}}},
  };
  std::vector<std::string> out;
  for (const auto& [session, request] : steps) {
    Reply r = post_json(http, session, request);
    REQUIRE(r.body["ok"] == true);
    r.body.erase("ms");
    out.push_back(r.body.dump());
  }
  return out;
}

TEST_CASE("answers do not depend on how many kernels answer") {
  for (const auto& extra :
       {std::vector<std::string>{}, std::vector<std::string>{"lexicon.weights=per_user"}}) {
    const auto one = script_answers(1, extra);
    const auto three = script_answers(3, extra);
    REQUIRE(one.size() == three.size());
    for (std::size_t i = 0; i < one.size(); ++i) {
      INFO("step " << i);
      CHECK(three[i] == one[i]);
    }
  }
}

}  // namespace
}  // namespace flipper::studiotest
