// append_trace_text must write exactly what dumping trace_json writes (the session splices it
// into answers in place of the tree; the tree is the terminal front ends', flipper/repl).
#include <catch2/catch.hpp>
#include <cstdint>
#include <nlohmann/json.hpp>
#include <random>
#include <string>
#include <vector>

#include "flipper/kernel/protocol.hpp"
#include "flipper/repl/outcome_json.hpp"
#include "json_strings.hpp"

namespace protocol = flipper::kernel::protocol;
namespace sdk = flipper::sdk;

namespace {
std::string via_tree(const std::vector<sdk::TraceStep>& trace, int dims) {
  return flipper::repl::trace_json(trace, dims)
      .dump(-1, ' ', false, flipper::repl::Json::error_handler_t::replace);
}
std::string via_text(const std::vector<sdk::TraceStep>& trace, int dims) {
  std::string out = "prefix:";
  protocol::append_trace_text(out, trace, dims);
  REQUIRE(out.rfind("prefix:", 0) == 0);  // appends, never overwrites
  return out.substr(7);
}
}  // namespace

TEST_CASE("trace text equals the dumped trace tree", "[protocol]") {
  using Act = sdk::TraceStep::Act;
  std::vector<sdk::TraceStep> trace;
  CHECK(via_text(trace, 2) == "[]");
  CHECK(via_text(trace, 2) == via_tree(trace, 2));

  trace.push_back({Act::move, {3, -4, 7}, {}});
  trace.push_back({Act::move, {-2147483647 - 1, 2147483647, 0}, {}});
  trace.push_back({Act::pick, {1, 2, 3}, {42, "red", "circle"}});
  trace.push_back({Act::drop, {0, 0, 0}, {-7, "bl\"ue\\\n", std::string("sq\xff") + "are"}});
  trace.push_back({Act::move, {5, 6, -1}, {}});
  for (int dims : {2, 3}) {
    INFO("dims " << dims);
    CHECK(via_text(trace, dims) == via_tree(trace, dims));
  }
  CHECK(via_text({trace.front()}, 2) == R"([{"act":"move","to":[3,-4]}])");
  CHECK(via_text({trace.front()}, 3) == R"([{"act":"move","to":[3,-4,7]}])");
}

TEST_CASE("generated traces are written as their dumped trees", "[protocol][writer]") {
  using Act = sdk::TraceStep::Act;
  std::mt19937_64 rng(3);
  std::size_t picks = 0;
  for (int t = 0; t < 2000; ++t) {
    std::vector<sdk::TraceStep> trace(rng() % 12);
    for (auto& s : trace) {
      s.act = static_cast<Act>(rng() % 3);
      s.cell = {static_cast<std::int32_t>(rng()), static_cast<std::int32_t>(rng() % 21) - 10,
                static_cast<std::int32_t>(rng() % 5) - 2};
      if (s.act != Act::move) {
        ++picks;
        s.item = {static_cast<std::int64_t>(rng()), flipper::testsupport::random_string(rng),
                  flipper::testsupport::random_string(rng)};
      }
    }
    for (int dims : {2, 3}) {
      std::string text;
      protocol::append_trace_text(text, trace, dims);
      REQUIRE(text == via_tree(trace, dims));
    }
  }
  CHECK(picks > 1000);
}
