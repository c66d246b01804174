#pragma once
/// @file parser_conformance.hpp
/// Conformance checks for parser plugins (header-only, Catch2 v2). A plugin's test gives a parser
/// (with the core grammar set), a scorer and some core-language utterances; it checks that
/// - each utterance parses, its top candidate is core-only, and that program's canonical text
///   reads back (read_canonical) to an equal program that is also among the candidates of
///   parsing the canonical text itself;
/// - candidates are distinct programs, ordered core first, then by score (desc), and every
///   candidate's derivations yield its program and span the whole utterance;
/// - unparsable input (gibberish, empty) gives no candidates and does not throw;
/// - results depend on the inputs only: parsing twice gives the same programs in the same order
///   with the same scores, and so do two instances parsing at once on two threads (the threading
///   rule of flipper/sdk/plugin.hpp; `check_concurrent_parsers`).
/// Candidates are also judged by the kernel's own check (flipper/sdk/answer_check.hpp), and
/// every failure names its scenario: the utterance, the candidate and what is wrong.

#include <catch2/catch.hpp>
#include <latch>
#include <optional>
#include <sstream>
#include <string>
#include <thread>
#include <vector>

#include "flipper/sdk/answer_check.hpp"
#include "flipper/sdk/canonical.hpp"
#include "flipper/sdk/parser.hpp"

namespace flipper::testing {

inline sdk::ParseResult conformance_parse(const sdk::Parser& parser, const sdk::Scorer& scorer,
                                          const std::string& text) {
  sdk::ParseRequest req;
  req.tokens = sdk::tokenize(text);
  req.scorer = &scorer;
  req.context.user = "conformance";
  return parser.parse(req);
}

/// A candidate in words: "candidate 2: visit room1 (score 1.5, core)".
inline std::string describe_candidate(const sdk::ParseResult& r, std::size_t i) {
  const auto& c = r.candidates[i];
  std::ostringstream s;
  s << "candidate " << i << ": " << (c.program ? sdk::render(c.program) : std::string("(null)"))
    << " (score " << c.score << ", " << (c.core_only ? "core" : "induced") << ", "
    << c.derivations.size() << " derivations)";
  return s.str();
}

inline void check_candidate_list(const sdk::ParseResult& r, std::size_t n_tokens) {
  sdk::ParseRequest asked;
  asked.tokens.resize(n_tokens);  // the check reads the number of tokens only
  const std::optional<sdk::Violation> wrong = sdk::parse_violation(asked, r);
  INFO("what is wrong (the kernel's check): " << (wrong ? wrong->what : std::string("nothing")));
  REQUIRE_FALSE(wrong.has_value());
  for (std::size_t i = 0; i < r.candidates.size(); ++i) {
    const auto& c = r.candidates[i];
    INFO(describe_candidate(r, i));
    REQUIRE(c.program != nullptr);
    REQUIRE_FALSE(c.derivations.empty());
    for (const auto& d : c.derivations) {
      INFO("a derivation over tokens [" << d->start << ", " << d->end << ") of the " << n_tokens
                                        << " yields " << sdk::render(d->sem));
      CHECK(sdk::equal(d->sem, c.program));
      CHECK(d->start == 0);
      CHECK(d->end == static_cast<int>(n_tokens));
    }
    for (std::size_t k = 0; k < i; ++k) {
      INFO("the same program as candidate " << k);
      CHECK_FALSE(sdk::equal(r.candidates[k].program, c.program));
    }
    if (i > 0) {
      INFO("ordered after " << describe_candidate(r, i - 1)
                            << "; want core first, then by score (desc)");
      const auto& p = r.candidates[i - 1];
      CHECK((p.core_only > c.core_only || (p.core_only == c.core_only && p.score >= c.score)));
    }
  }
}

inline void check_parser_conformance(const sdk::Parser& parser, const sdk::Scorer& scorer,
                                     const std::vector<std::string>& core_utterances) {
  for (const auto& u : core_utterances) {
    INFO("utterance: " << u);
    sdk::ParseResult r;
    REQUIRE_NOTHROW(r = conformance_parse(parser, scorer, u));
    INFO("answered " << r.candidates.size() << " candidates; want at least one");
    REQUIRE_FALSE(r.candidates.empty());
    check_candidate_list(r, sdk::tokenize(u).size());
    const auto& top = r.candidates.front();
    INFO("the top " << describe_candidate(r, 0) << "; want a core-only program");
    CHECK(top.core_only);
    const std::string text = sdk::render(top.program);
    INFO("canonical: " << text);
    sdk::Program back;
    REQUIRE_NOTHROW(back = sdk::read_canonical(text));
    CHECK(sdk::equal(back, top.program));
    const auto again = conformance_parse(parser, scorer, text);
    bool found = false;
    for (const auto& c : again.candidates) found = found || sdk::equal(c.program, top.program);
    INFO("parsing the canonical text gave " << again.candidates.size()
                                            << " candidates; want the top program among them");
    CHECK(found);
    const auto twice = conformance_parse(parser, scorer, u);
    INFO("parsed twice: " << r.candidates.size() << " then " << twice.candidates.size()
                          << " candidates; want the same answer");
    REQUIRE(twice.candidates.size() == r.candidates.size());
    for (std::size_t i = 0; i < r.candidates.size(); ++i) {
      INFO("first " << describe_candidate(r, i) << "; second " << describe_candidate(twice, i));
      CHECK(sdk::equal(twice.candidates[i].program, r.candidates[i].program));
      CHECK(twice.candidates[i].score == r.candidates[i].score);
    }
  }
  for (const std::string bad : {"", "flibber the gnorp", "move", "visit [1,", "} move left {"}) {
    INFO("unparsable: '" << bad << "'");
    sdk::ParseResult r;
    REQUIRE_NOTHROW(r = conformance_parse(parser, scorer, bad));
    INFO("answered " << r.candidates.size() << " candidates"
                     << (r.candidates.empty() ? "" : ", the first " + describe_candidate(r, 0))
                     << "; want none");
    CHECK(r.candidates.empty());
  }
}

/// The threading rule (flipper/sdk/plugin.hpp: one request at a time per instance, instances
/// concurrently): two parser instances, each with a scorer of its own and the same grammar,
/// parse the utterances at once on two threads, started together; each must answer as `alone`
/// answered them one by one (the same programs in the same order, the same scores).
inline void check_concurrent_parsers(const sdk::Parser& alone, const sdk::Parser& first,
                                     const sdk::Scorer& first_scorer, const sdk::Parser& second,
                                     const sdk::Scorer& second_scorer,
                                     const std::vector<std::string>& utterances) {
  struct Answers {
    std::vector<sdk::ParseResult> results;
    std::string error;  // what a parse threw (Catch2's checks are not for other threads)
  };
  auto answer = [&](const sdk::Parser& parser, const sdk::Scorer& scorer, Answers& out) {
    try {
      for (int round = 0; round < 3; ++round)
        for (const auto& u : utterances)
          out.results.push_back(conformance_parse(parser, scorer, u));
    } catch (const std::exception& e) {
      out.error = e.what();
    }
  };
  Answers reference;
  answer(alone, first_scorer, reference);
  REQUIRE(reference.error.empty());
  Answers a;
  Answers b;
  std::latch start(2);
  auto run = [&](const sdk::Parser& parser, const sdk::Scorer& scorer, Answers& out) {
    start.arrive_and_wait();
    answer(parser, scorer, out);
  };
  std::thread ta(run, std::cref(first), std::cref(first_scorer), std::ref(a));
  std::thread tb(run, std::cref(second), std::cref(second_scorer), std::ref(b));
  ta.join();
  tb.join();
  for (const Answers* got : {&a, &b}) {
    INFO((got == &a ? "the first" : "the second")
         << " of two instances parsing at once on two threads");
    REQUIRE(got->error.empty());
    REQUIRE(got->results.size() == reference.results.size());
    for (std::size_t k = 0; k < got->results.size(); ++k) {
      const auto& r = got->results[k];
      const auto& want = reference.results[k];
      INFO("utterance: " << utterances[k % utterances.size()] << "; " << r.candidates.size()
                         << " candidates, alone " << want.candidates.size());
      REQUIRE(r.candidates.size() == want.candidates.size());
      for (std::size_t i = 0; i < r.candidates.size(); ++i) {
        INFO(describe_candidate(r, i) << "; alone " << describe_candidate(want, i));
        CHECK(sdk::equal(r.candidates[i].program, want.candidates[i].program));
        CHECK(r.candidates[i].score == want.candidates[i].score);
      }
    }
  }
}

}  // namespace flipper::testing
