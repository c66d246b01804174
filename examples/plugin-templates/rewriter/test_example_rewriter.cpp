// example_rewriter's own tests, beside the conformance kits: the plugin created as the kernel
// creates it (testing::load_plugin validates its parameters).
#include <catch2/catch.hpp>
#include <flipper/sdk/canonical.hpp>
#include <flipper/sdk/rewriter.hpp>
#include <flipper/testing/plugin_factory.hpp>

namespace {

namespace sdk = flipper::sdk;

std::vector<std::string> proposals(const sdk::Rewriter& rewriter, const std::string& body) {
  std::vector<std::string> out;
  for (const auto& c : rewriter.propose({sdk::read_canonical(body), {}, nullptr, {}}))
    out.push_back(c.rewriting + " " + sdk::render(c.program));
  return out;
}

}  // namespace

TEST_CASE("example_rewriter: repeat 3 times is written out 3 times, up to max_unroll") {
  using flipper::testing::load_plugin;
  const std::string thrice = "{repeat 3 times {move left}}";
  const std::string written =
      sdk::render(sdk::read_canonical("{{move left};{move left};{move left}}"));
  CHECK(proposals(*load_plugin<sdk::Rewriter>("example_rewriter"), thrice) ==
        std::vector<std::string>{"unroll " + written});
  CHECK(
      proposals(*load_plugin<sdk::Rewriter>("example_rewriter", {{"max_unroll", std::int64_t{3}}}),
                thrice)
          .size() == 1);
  CHECK(
      proposals(*load_plugin<sdk::Rewriter>("example_rewriter", {{"max_unroll", std::int64_t{2}}}),
                thrice)
          .empty());
  CHECK(proposals(*load_plugin<sdk::Rewriter>("example_rewriter"), "{move left}").empty());
}
