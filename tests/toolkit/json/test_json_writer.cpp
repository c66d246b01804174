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

#include "flipper/toolkit/json/json_writer.hpp"
#include "json_strings.hpp"

namespace {

using flipper::testsupport::random_string;
using flipper::toolkit::json::JsonWriter;
using nlohmann::json;

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

}  // namespace

TEST_CASE("numbers are written as nlohmann writes a double", "[json][writer]") {
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

TEST_CASE("integers are written as nlohmann writes them", "[json][writer]") {
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

TEST_CASE("strings are escaped as nlohmann escapes them", "[json][writer]") {
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
