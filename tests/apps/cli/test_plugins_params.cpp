// `flipper plugins --params` / `flipper plugins NAME`: each plugin's declared parameter schema.
#include "cli_test_support.hpp"

using namespace flipper::clitest;

TEST_CASE("flipper plugins --params prints every plugin's parameters", "[cli][plugins]") {
  const Run r = run_flipper("plugins --params");
  INFO(r.out);
  REQUIRE(r.status == 0);
  CHECK(contains(r.out, "STATUS"));  // the table comes first
  CHECK(contains(r.out, "astar (planner "));
  CHECK(contains(r.out, "grid2d (world "));
  CHECK(contains(r.out, "PARAM"));
  CHECK(contains(r.out, "DEFAULT"));
  CHECK(contains(r.out, "max_expansions"));
}

TEST_CASE("flipper plugins NAME prints only that plugin's schema", "[cli][plugins]") {
  const Run r = run_flipper("plugins astar");
  INFO(r.out);
  REQUIRE(r.status == 0);
  CHECK_FALSE(contains(r.out, "STATUS"));
  CHECK_FALSE(contains(r.out, "grid2d ("));
  CHECK(contains(r.out, "astar (planner "));
  // One row per declared parameter: name, type, default, allowed values, description.
  std::istringstream in(r.out);
  bool two_opt = false, max_expansions = false;
  for (std::string line; std::getline(in, line);) {
    if (contains(line, "two_opt"))
      two_opt = contains(line, "bool") && contains(line, "true") && contains(line, "2-opt");
    if (contains(line, "max_expansions"))
      max_expansions = contains(line, "int") && contains(line, " 0 ") && contains(line, ">= 0");
  }
  CHECK(two_opt);
  CHECK(max_expansions);

  const Run unknown = run_flipper("plugins astr");
  CHECK(unknown.status == 2);
  CHECK(contains(unknown.out, "no plugin named 'astr' (did you mean 'astar'?)"));
}
