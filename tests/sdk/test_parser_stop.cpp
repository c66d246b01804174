// Parser::parse honours ParseRequest::stop even for a plugin that never polls it.
#include <catch2/catch.hpp>
#include <chrono>
#include <thread>

#include "flipper/sdk/parser.hpp"

namespace sdk = flipper::sdk;

namespace {

// A parser that ignores the stop condition and takes `delay` per parse.
class SlowParser : public sdk::Parser {
 public:
  std::chrono::milliseconds delay{0};
  mutable int calls = 0;

 protected:
  void do_set_grammar(std::shared_ptr<const sdk::Grammar>) override {}
  void do_add_rule(sdk::RulePtr) override {}
  void do_remove_rule(const std::string&) override {}
  sdk::ParseResult do_parse(const sdk::ParseRequest&) const override {
    ++calls;
    std::this_thread::sleep_for(delay);
    return {};
  }
};

}  // namespace

TEST_CASE("parse: a stop that already fired does not call the plugin") {
  SlowParser p;
  sdk::ParseRequest req;
  req.stop.deadline = std::chrono::steady_clock::now() - std::chrono::milliseconds(1);
  CHECK(p.parse(req).stopped);
  CHECK(p.calls == 0);
  std::atomic<bool> cancel{true};
  sdk::ParseRequest cancelled;
  cancelled.stop.cancel = &cancel;
  CHECK(p.parse(cancelled).stopped);
  CHECK(p.calls == 0);
}

TEST_CASE("parse: a deadline passed during the parse marks the result stopped") {
  SlowParser p;
  p.delay = std::chrono::milliseconds(30);
  sdk::ParseRequest req;
  req.stop = sdk::StopCondition::within(std::chrono::milliseconds(5));
  CHECK(p.parse(req).stopped);
  CHECK(p.calls == 1);
  sdk::ParseRequest unlimited;
  CHECK_FALSE(p.parse(unlimited).stopped);
  sdk::ParseRequest generous;
  generous.stop = sdk::StopCondition::within(std::chrono::seconds(60));
  CHECK_FALSE(p.parse(generous).stopped);
}
