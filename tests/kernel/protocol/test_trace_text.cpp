// append_trace_text must write exactly what dumping trace_json writes (the session splices it
// into answers in place of the tree).
#include <catch2/catch.hpp>
#include <nlohmann/json.hpp>
#include <string>
#include <vector>

#include "flipper/kernel/protocol.hpp"

namespace protocol = flipper::kernel::protocol;
namespace sdk = flipper::sdk;

namespace {
std::string via_tree(const std::vector<sdk::TraceStep>& trace, int dims) {
  return protocol::trace_json(trace, dims)
      .dump(-1, ' ', false, protocol::Json::error_handler_t::replace);
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
