// toolkit/process: a series of calls recorded in a child and replayed in its parent
// (flipper/toolkit/process/call_tape.hpp).
#include <catch2/catch.hpp>
#include <chrono>
#include <cstdint>
#include <cstdlib>
#include <exception>
#include <random>
#include <stdexcept>
#include <string>

#include "flipper/toolkit/process/call_tape.hpp"
#include "flipper/toolkit/process/child_call.hpp"

namespace process = flipper::toolkit::process;
using process::CallTape;
using process::TapeRecord;
using std::chrono::nanoseconds;

namespace {

// The tape of calls that answered `records`: each call's begun record, then its answer's.
std::string tape_of(std::initializer_list<TapeRecord> records) {
  std::string tape;
  for (const TapeRecord& r : records)
    tape += CallTape::bytes_of({r.key, {}, process::kBegun, {}}) + CallTape::bytes_of(r);
  return tape;
}

std::string begun(std::uint64_t key) {
  return CallTape::bytes_of({key, {}, process::kBegun, {}});
}

}  // namespace

TEST_CASE("a tape's records come back in order, each field as recorded", "[process][tape]") {
  const std::string big(70000, 'x');  // more than a pipe holds at once
  CallTape tape(CallTape::Mode::replay, tape_of({{7, nanoseconds(1500), 'A', "first"},
                                                 {0xffffffffffffffffU, nanoseconds(0), 'E', ""},
                                                 {7, nanoseconds(123456789012), 'A', big}}));
  const auto a = tape.take(7);
  REQUIRE(a);
  CHECK(a->cpu == nanoseconds(1500));
  CHECK(a->tag == 'A');
  CHECK(a->bytes == "first");
  const auto b = tape.take(0xffffffffffffffffU);
  REQUIRE(b);
  CHECK(b->tag == 'E');
  CHECK(b->bytes.empty());
  const auto c = tape.take(7);
  REQUIRE(c);
  CHECK(c->cpu == nanoseconds(123456789012));
  CHECK(c->bytes == big);
  CHECK_FALSE(tape.missed());
  CHECK_FALSE(tape.take(7));  // past the last record
  CHECK(tape.missed());
}

TEST_CASE("a call that is not the tape's next one leaves the recording for good",
          "[process][tape]") {
  CallTape tape(CallTape::Mode::replay, tape_of({{1, {}, 'A', "one"}, {2, {}, 'A', "two"}}));
  CHECK_FALSE(tape.take(2));  // the next record is call 1's
  CHECK(tape.missed());
  CHECK_FALSE(tape.take(1));  // and no call is answered from it afterwards
}

TEST_CASE("a tape cut short reads to its last whole record, and cut in a call names that call",
          "[process][tape]") {
  const std::string whole = tape_of({{1, {}, 'A', "one"}, {2, {}, 'A', "two"}});
  const std::size_t second = tape_of({{1, {}, 'A', "one"}}).size();
  const std::size_t second_answer = second + begun(2).size();
  // Every cut in the second call's begun record: no record of it, the call is not the tape's.
  for (std::size_t cut = second; cut < second_answer; ++cut) {
    CallTape tape(CallTape::Mode::replay, whole.substr(0, cut));
    CHECK(tape.take(1)->bytes == "one");
    CHECK_FALSE(tape.take(2));
    CHECK(tape.missed());
  }
  // Every cut after it (none of its answer, or part): the child died in call 2.
  for (std::size_t cut = second_answer; cut < whole.size(); ++cut) {
    CallTape tape(CallTape::Mode::replay, whole.substr(0, cut));
    CHECK(tape.take(1)->bytes == "one");
    const auto died = tape.take(2);
    REQUIRE(died);
    CHECK(died->tag == process::kBegun);
    CHECK(died->key == 2);
    CHECK(tape.missed());
    CHECK_FALSE(tape.take(2));
  }
  CallTape all(CallTape::Mode::replay, whole);
  CHECK(all.take(1)->bytes == "one");
  CHECK(all.take(2)->bytes == "two");
}

TEST_CASE("a tape whose records are not begun-then-answered is left at once", "[process][tape]") {
  SECTION("an answer without its begun record") {
    CallTape tape(CallTape::Mode::replay, CallTape::bytes_of({1, {}, 'A', "one"}));
    CHECK_FALSE(tape.take(1));
  }
  SECTION("two begun records") {
    CallTape tape(CallTape::Mode::replay, begun(1) + begun(1) + tape_of({{1, {}, 'A', "x"}}));
    CHECK_FALSE(tape.take(1));
  }
  SECTION("a begun record and another call's answer") {
    CallTape tape(CallTape::Mode::replay, begun(1) + CallTape::bytes_of({2, {}, 'A', "two"}));
    CHECK_FALSE(tape.take(1));
  }
}

TEST_CASE("a record whose length or CPU time cannot be one is no record", "[process][tape]") {
  std::string tape = CallTape::bytes_of({1, nanoseconds(5), process::kBegun, ""}) +
                     CallTape::bytes_of({1, nanoseconds(5), 'A', "one"});
  CHECK(CallTape(CallTape::Mode::replay, tape).take(1));
  SECTION("a length shorter than a record's head") {
    tape[0] = 2;
    CHECK_FALSE(CallTape(CallTape::Mode::replay, tape).take(1));
  }
  SECTION("a length past the tape's end") {
    tape[7] = 1;
    CHECK_FALSE(CallTape(CallTape::Mode::replay, tape).take(1));
  }
  SECTION("a negative CPU time") {
    tape[8 + 8 + 7] = static_cast<char>(0x80);  // the top byte of the CPU time
    CHECK_FALSE(CallTape(CallTape::Mode::replay, tape).take(1));
  }
}

TEST_CASE("a probe lets the first call be made and notes the second", "[process][tape]") {
  CallTape probe(CallTape::Mode::probe);
  CHECK_FALSE(probe.missed());
  CHECK(probe.probe_call());
  CHECK_FALSE(probe.missed());
  CHECK_FALSE(probe.probe_call());
  CHECK(probe.missed());
  CHECK_FALSE(probe.probe_call());
  CHECK(probe.missed());
}

TEST_CASE("the thread's tape is the innermost alive", "[process][tape]") {
  CHECK(CallTape::current() == nullptr);
  {
    CallTape outer(CallTape::Mode::probe);
    CHECK(CallTape::current() == &outer);
    {
      CallTape inner(CallTape::Mode::record);
      CHECK(CallTape::current() == &inner);
    }
    CHECK(CallTape::current() == &outer);
  }
  CHECK(CallTape::current() == nullptr);
}

TEST_CASE("records sent by a child that then dies are replayed to the call it died in",
          "[process][tape]") {
  auto call = process::run_in_child({}, [] {
    process::send_to_parent(tape_of({{1, nanoseconds(10), 'A', "one"}}));
    process::send_to_parent(begun(2));
    process::send_to_parent(CallTape::bytes_of({2, nanoseconds(20), 'A', "two"}).substr(0, 20));
    ::abort();
  });
  REQUIRE(call);
  CHECK(call->end == process::ChildEnd::signalled);
  CallTape tape(CallTape::Mode::replay, call->bytes,
                std::make_exception_ptr(std::runtime_error("x")));
  const auto one = tape.take(1);
  REQUIRE(one);
  CHECK(one->bytes == "one");
  CHECK(one->cpu == nanoseconds(10));
  CHECK(tape.take(2)->tag == process::kBegun);
  CHECK(tape.end() != nullptr);
}

TEST_CASE("any bytes on a tape are read within their bounds, a call at a time", "[process][tape]") {
  // A tape is what a child sent, and a child runs a plugin's code: its bytes may be anything.
  // Every mutation of a valid tape (a byte changed, cut, grown) and random bytes: take() returns
  // only records whose bytes lie inside the tape (ASan in the instrumented tree), in order, and
  // once it misses it answers nothing more.
  const std::string valid = tape_of({{1, nanoseconds(10), 'A', "one"},
                                     {2, nanoseconds(20), 'E', std::string(40, 'e')},
                                     {3, nanoseconds(30), 'A', ""}});
  std::mt19937_64 random(20261203);
  for (int round = 0; round < 20000; ++round) {
    std::string tape = valid;
    switch (round % 4) {
      case 0:
        tape[random() % tape.size()] = static_cast<char>(random());
        break;
      case 1:
        tape.resize(random() % tape.size());
        break;
      case 2:
        tape.insert(random() % tape.size(), 1 + random() % 9, static_cast<char>(random()));
        break;
      default:
        tape.assign(random() % 200, '\0');
        for (char& c : tape) c = static_cast<char>(random());
    }
    CallTape replay(CallTape::Mode::replay, tape);
    std::size_t taken = 0;
    for (std::uint64_t key = 1; key <= 4; ++key) {
      const auto r = replay.take(random() % 8 == 0 ? key + 1 : key);
      if (!r) break;
      ++taken;
      CHECK(r->bytes.size() < tape.size());
      CHECK(r->cpu >= nanoseconds(0));
      if (r->tag == process::kBegun) break;  // the tape ends in this call
    }
    CHECK(taken <= 3);
    if (replay.missed()) CHECK_FALSE(replay.take(4));
  }
}
