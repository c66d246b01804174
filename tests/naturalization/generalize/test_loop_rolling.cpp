// Rewriting 1 (loop rolling): what rolls, and that no statement is ever dropped.
#include <catch2/catch.hpp>

#include "flipper/sdk/ast.hpp"
#include "flipper/sdk/canonical.hpp"
#include "flipper/sdk/errors.hpp"
#include "flipper/sdk/rewriter.hpp"
#include "flipper/testing/rewriter_conformance.hpp"
#include "plugin_fixture.hpp"

using namespace flipper;
using sdk::Kind;
using sdk::Program;

namespace {

Program P(const std::string& text) {
  return sdk::read_canonical(text);
}

std::shared_ptr<sdk::Rewriter> rewriter(std::int64_t max_block = 10) {
  return testsupport::load_plugin<sdk::Rewriter>(
      "rewrites",
      sdk::Params({{"max_block", max_block}, {"rewritings", std::vector<std::string>{"loop"}}}));
}

// The rolled program of `body` ("" when the rewriter proposes none).
std::string rolled(const sdk::Rewriter& r, const std::string& body) {
  auto out = r.propose({P(body), {}, nullptr, {}});
  if (out.empty()) return "";
  REQUIRE(out.size() == 1);
  CHECK(out[0].rewriting == "loop");
  return sdk::render(out[0].program);
}

// Expands every `repeat n times S` with a literal n into n copies of S, flattening sequences:
// the statement list a rolled program stands for.
void unroll(const Program& p, std::vector<Program>& out) {
  if (p->kind == Kind::Seq) {
    for (const auto& k : p->kids) unroll(k, out);
  } else if (p->kind == Kind::Repeat && p->kids[0]->kind == Kind::Num) {
    for (int i = 0; i < static_cast<int>(p->kids[0]->number); ++i) unroll(p->kids[1], out);
  } else if (p->kind == Kind::If || p->kind == Kind::While || p->kind == Kind::ForeachPoint ||
             p->kind == Kind::ForeachArea) {
    std::vector<Program> body;
    unroll(p->kids[1], body);
    out.push_back(sdk::make(p->kind, {p->kids[0], sdk::make_seq(body)}));
  } else {
    out.push_back(p);
  }
}

std::string unrolled(const Program& p) {
  std::vector<Program> s;
  unroll(p, s);
  return sdk::render(sdk::make_seq(s));
}

}  // namespace

TEST_CASE("loop rolling: repeated statements become repeat n times", "[rewrites][loop]") {
  auto r = rewriter();
  CHECK(rolled(*r, "{{drop item};{drop item};{drop item}}") ==
        sdk::render(P("{repeat 3 times {drop item}}")));
  CHECK(rolled(*r, "{{move left};{move up};{move left};{move up}}") ==
        sdk::render(P("{repeat 2 times {{move left};{move up}}}")));
  // Nothing repeats: no proposal.
  CHECK(rolled(*r, "{{move left};{move up}}").empty());
  CHECK(rolled(*r, "{drop item}").empty());
}

TEST_CASE("loop rolling keeps every other statement, in place", "[rewrites][loop]") {
  auto r = rewriter();
  CHECK(rolled(
            *r,
            "{{move up};{drop item};{drop item};{if {robot has item } {move left}};{move down}}") ==
        sdk::render(P("{{move up};{repeat 2 times {drop item}};{if {robot has item } {move left}};"
                      "{move down}}")));
  // The longest run wins at each position; rolled blocks are rolled inside.
  CHECK(rolled(*r,
               "{{move up};{move up};{pick item };{move up};{move up};{pick item };{move left}}") ==
        sdk::render(P("{{repeat 2 times {{repeat 2 times {move up}};{pick item }}};{move left}}")));
  // Loops inside loop bodies and if bodies roll too.
  CHECK(rolled(*r, "{foreach point in world {{visit point};{drop item};{drop item}}}") ==
        sdk::render(P("{foreach point in world {{visit point};{repeat 2 times {drop item}}}}")));
}

TEST_CASE("loop rolling never drops a statement", "[rewrites][loop]") {
  auto r = rewriter();
  const char* bodies[] = {
      "{{drop item};{drop item};{drop item}}",
      "{{move left};{move up};{move left};{move up};{move left}}",
      "{{move up};{move up};{pick item };{move up};{move up};{pick item };{move left}}",
      ("{{if {robot has item } {drop item}};{if {robot has item } {drop item}};{move left};"
       "{while {robot has item } {drop item}};{while {robot has item } {drop item}};{move left}}"),
      "{{repeat 2 times {move up}};{repeat 2 times {move up}};{strict {move left}};{move left}}",
      "{{pick item };{move up};{pick item };{move up};{pick item };{drop item};{drop item}}",
      "{{move up};{move down};{move up};{move down};{move up};{move up};{move up}}",
  };
  for (const char* body : bodies) {
    INFO(body);
    auto out = r->propose({P(body), {}, nullptr, {}});
    REQUIRE(out.size() == 1);
    CHECK(out[0].program->size < P(body)->size);
    CHECK(unrolled(out[0].program) == unrolled(P(body)));
  }
}

TEST_CASE("loop rolling respects max_block", "[rewrites][loop]") {
  auto r = rewriter(1);
  CHECK(rolled(*r, "{{move left};{move up};{move left};{move up}}").empty());
  CHECK(rolled(*rewriter(2), "{{move left};{move up};{move left};{move up}}") ==
        sdk::render(P("{repeat 2 times {{move left};{move up}}}")));
}

TEST_CASE("rewrites: unknown rewriting names are config errors", "[rewrites]") {
  try {
    testsupport::load_plugin<sdk::Rewriter>(
        "rewrites", sdk::Params({{"rewritings", std::vector<std::string>{"loop", "magic"}}}));
    FAIL("expected an error");
  } catch (const sdk::Error& e) {
    CHECK(e.code() == "bad_config");
    CHECK_THAT(e.what(), Catch::Contains("magic"));
  }
}

TEST_CASE("rewrites: rewriter conformance without a world", "[rewrites][conformance]") {
  auto r = testsupport::load_plugin<sdk::Rewriter>("rewrites");
  testing::check_rewriter_conformance(*r, {P("{{drop item};{drop item}}"), {}, nullptr, {}});
  testing::check_rewriter_conformance(*r, {P("{move left}"), {}, nullptr, {}});
}
