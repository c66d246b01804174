// The answer writer's values are nlohmann's dump() bytes (docs/protocol.md: answers are written
// without a tree, byte-identical to the tree's dump). Each writer path is compared with the
// nlohmann tree it replaced, on fixed odd values and on many generated ones.
#include <catch2/catch.hpp>
#include <cmath>
#include <cstdint>
#include <cstring>
#include <limits>
#include <nlohmann/json.hpp>
#include <random>
#include <string>
#include <vector>

#include "flipper/kernel/json_writer.hpp"
#include "flipper/kernel/protocol.hpp"

namespace {

using flipper::kernel::JsonWriter;
using nlohmann::json;
namespace protocol = flipper::kernel::protocol;
namespace sdk = flipper::sdk;

std::string tree_dump(const json& j) {
  return j.dump(-1, ' ', false, json::error_handler_t::replace);
}

std::string written_number(double v) {
  std::string out;
  JsonWriter w(out);
  w.number(v);
  return out;
}

std::string written_string(const std::string& s) {
  std::string out;
  JsonWriter::append_string(out, s);
  return out;
}

double from_bits(std::uint64_t bits) {
  double d = 0;
  std::memcpy(&d, &bits, sizeof d);
  return d;
}

// Strings of every kind of byte: ASCII, the escaped ones, control characters, valid multi-byte
// UTF-8, and bytes that are not UTF-8 (replaced by U+FFFD).
std::string random_string(std::mt19937_64& rng) {
  static const std::vector<std::string> pieces = {
      "a",    "Z",     " ",    "\"",       "\\",       "/",
      "\n",   "\t",    "\r",   "\b",       "\f",       std::string(1, '\0'),
      "\x01", "\x1f",  "\x7f", "é",        "ünï",      "€",
      "😀",    "\xff",  "\xc3", "\xe2\x82", "\xf0\x9f", "\xed\xa0\x80",
      "red",  "circle"};
  std::string s;
  const auto n = rng() % 8;
  for (std::uint64_t i = 0; i < n; ++i) s += pieces[rng() % pieces.size()];
  return s;
}

}  // namespace

TEST_CASE("numbers are written as nlohmann writes a double", "[protocol][writer]") {
  const double inf = std::numeric_limits<double>::infinity();
  // NaN and the infinities: null, as the tree writes them (a plugin's NaN score is refused before
  // an answer is written, docs/plugins-untrusted.md; the writer still never writes "nan").
  CHECK(written_number(std::nan("")) == "null");
  CHECK(written_number(inf) == "null");
  CHECK(written_number(-inf) == "null");
  CHECK(written_number(0.0) == "0.0");
  CHECK(written_number(-0.0) == "-0.0");
  CHECK(written_number(1.0) == "1.0");
  CHECK(written_number(0.25) == "0.25");
  CHECK(written_number(1e-05) == "1e-05");
  CHECK(written_number(-2.5e300) == "-2.5e+300");
  const std::vector<double> fixed = {0.0,
                                     -0.0,
                                     1.0,
                                     -1.0,
                                     0.1,
                                     1.0 / 3.0,
                                     123456789.0,
                                     1e15,
                                     1e16,
                                     1e17,
                                     1e21,
                                     1e-4,
                                     1e-5,
                                     0.000123,
                                     std::numeric_limits<double>::min(),
                                     std::numeric_limits<double>::denorm_min(),
                                     std::numeric_limits<double>::max(),
                                     std::numeric_limits<double>::lowest(),
                                     std::numeric_limits<double>::epsilon(),
                                     std::nan(""),
                                     inf,
                                     -inf};
  for (double v : fixed) {
    INFO(v);
    CHECK(written_number(v) == json(v).dump());
  }
  std::mt19937_64 rng(20261129);
  std::uniform_real_distribution<double> unit(0.0, 1.0);
  std::size_t compared = 0;
  for (int i = 0; i < 20000; ++i) {
    const double by_bits = from_bits(rng());  // every exponent, NaNs included
    const double score = (unit(rng) - 0.5) * 40.0;
    const double prob = unit(rng);
    for (double v : {by_bits, score, prob, std::exp(score)}) {
      const std::string want = json(v).dump();
      if (written_number(v) != want)
        FAIL("bits of " << want << " written as " << written_number(v));
      ++compared;
    }
  }
  CHECK(compared == 80000);
}

TEST_CASE("integers are written as nlohmann writes them", "[protocol][writer]") {
  std::mt19937_64 rng(7);
  std::vector<std::int64_t> values = {0,
                                      -1,
                                      1,
                                      9,
                                      10,
                                      -10,
                                      std::numeric_limits<std::int64_t>::min(),
                                      std::numeric_limits<std::int64_t>::max()};
  for (int i = 0; i < 5000; ++i)
    values.push_back(static_cast<std::int64_t>(rng() >> (rng() % 64)) * (i % 2 == 0 ? 1 : -1));
  for (std::int64_t v : values) {
    std::string a, b, c;
    JsonWriter(a).integer(v);
    JsonWriter::append_integer(b, v);
    JsonWriter(c).unsigned_integer(static_cast<std::uint64_t>(v));
    REQUIRE(a == json(v).dump());
    REQUIRE(b == json(v).dump());
    REQUIRE(c == json(static_cast<std::uint64_t>(v)).dump());
  }
}

TEST_CASE("strings are escaped as nlohmann escapes them", "[protocol][writer]") {
  for (const std::string& s : {std::string(), std::string("plain ascii"), std::string("q\"uote\\d"),
                               std::string("ünïcödé 😀"), std::string("bad \xff utf8"),
                               std::string("ctl \x01\x07\x1f\x7f"), std::string("nul \0 x", 7)})
    CHECK(written_string(s) == tree_dump(json(s)));
  CHECK(written_string("a\"b") == R"("a\"b")");
  CHECK(written_string("\xff") == "\"\xef\xbf\xbd\"");  // U+FFFD
  std::mt19937_64 rng(11);
  for (int i = 0; i < 20000; ++i) {
    const std::string s = random_string(rng);
    REQUIRE(written_string(s) == tree_dump(json(s)));
  }
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
        s.item = {static_cast<std::int64_t>(rng()), random_string(rng), random_string(rng)};
      }
    }
    for (int dims : {2, 3}) {
      std::string text;
      protocol::append_trace_text(text, trace, dims);
      REQUIRE(text == tree_dump(protocol::trace_json(trace, dims)));
    }
  }
  CHECK(picks > 1000);
}
