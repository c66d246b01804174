// Fuzz target: the session line handler (kernel/session, docs/protocol.md) with the embedded
// default config (study map, every default plugin) and an in-memory lexicon.
// Input: up to 4 request lines (so `query` + `accept` and `define` + `query` pairs are reached).
// Oracle: handle_line never throws and answers every non-blank line with one JSON object line
// that has "ok"; sanitizers catch memory errors and UB.
// State: the world and user are reset after each input; a session whose lexicon, scorer or world
// history changed (a successful define, delete_rule or accept) is rebuilt, so an input's outcome
// does not depend on earlier inputs.
#include <unistd.h>

#include <cstdio>
#include <cstdlib>
#include <memory>
#include <nlohmann/json.hpp>
#include <string>

#include "flipper/wiring/session_factory.hpp"
#include "support/fuzz_support.hpp"

namespace fz = flipper::fuzz;
using flipper::kernel::Session;

namespace {

std::unique_ptr<Session> g_session;

// A short CPU budget and a smaller world limit keep slow inputs (long parses, big worlds) cheap, so
// the fuzzer spends its time on many inputs; the code paths are the same as at the defaults.
std::unique_ptr<Session> make_session() {
  return flipper::wiring::open_session(
      std::nullopt,
      {"lexicon.path=:memory:", "session.cpu_budget_ms=500", "world.max_cells=1048576"});
}

bool changes_state(const std::string& answer) {
  for (const char* op : {"define", "delete_rule", "accept"})
    if (answer.rfind(std::string("{\"ok\":true,\"op\":\"") + op + "\"", 0) == 0) return true;
  return false;
}

}  // namespace

extern "C" int LLVMFuzzerInitialize(int*, char***) {
  // Relative world files in requests (configs/worlds/...) resolve against the repository root.
  if (chdir(fz::source_dir().c_str()) != 0) std::abort();
  g_session = make_session();
  return 0;
}

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  const std::string_view input = fz::as_text(data, size);
  bool dirty = false;
  for (std::string_view line : fz::split_lines(input, 4)) {
    const std::string answer = g_session->handle_line(line);
    if (answer.empty()) continue;  // a blank line gets no answer
    const auto parsed = nlohmann::json::parse(answer, nullptr, /*allow_exceptions=*/false);
    if (!parsed.is_object() || !parsed.contains("ok") || answer.find('\n') != std::string::npos) {
      std::fprintf(stderr, "session_line: malformed answer: %s\n", answer.c_str());
      std::abort();
    }
    dirty = dirty || changes_state(answer);
  }
  if (dirty) {
    g_session.reset();
    g_session = make_session();
  } else {
    g_session->set_world(g_session->runtime().default_world);
    g_session->set_user("anonymous");
  }
  return 0;
}
