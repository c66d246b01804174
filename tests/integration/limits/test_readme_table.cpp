// The bad-input table of docs/bad-input.md is generated from the test table (bad_input_cases.cpp):
// this test fails when they differ. FLIPPER_UPDATE_README=1 build/tests/test_limits "[readme]"
// rewrites it.
#include <catch2/catch.hpp>
#include <cstdlib>
#include <fstream>
#include <sstream>

#include "bad_input_cases.hpp"

namespace {

const std::string kBegin =
    "<!-- bad-input-table: generated from tests/integration/limits/bad_input_cases.cpp; do not "
    "edit -->\n";
const std::string kEnd = "<!-- end of bad-input-table -->\n";

}  // namespace

TEST_CASE("the README's bad-input table is the test table", "[readme]") {
  const std::string path = std::string(FLIPPER_SOURCE_DIR) + "/docs/bad-input.md";
  std::ifstream in(path);
  std::stringstream text;
  text << in.rdbuf();
  std::string readme = text.str();
  const auto begin = readme.find(kBegin);
  const auto end = readme.find(kEnd);
  REQUIRE(begin != std::string::npos);
  REQUIRE(end != std::string::npos);
  REQUIRE(begin < end);
  const std::size_t from = begin + kBegin.size();
  const std::string table = flipper::limitstest::render_table();
  if (const char* update = std::getenv("FLIPPER_UPDATE_README");
      update && std::string(update) == "1") {
    readme.replace(from, end - from, table);
    std::ofstream(path) << readme;
  }
  INFO("regenerate with: FLIPPER_UPDATE_README=1 build/tests/test_limits '[readme]'");
  CHECK(readme.substr(from, end - from) == table);
}
