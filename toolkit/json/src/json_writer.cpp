#include "flipper/toolkit/json/json_writer.hpp"

#include <array>
#include <charconv>
#include <cmath>
#include <nlohmann/json.hpp>

namespace flipper::toolkit::json {
namespace {

using nlohmann::json;

template <typename Int>
void append_int(std::string& out, Int value) {
  std::array<char, 24> buf{};
  const auto r = std::to_chars(buf.data(), buf.data() + buf.size(), value);
  out.append(buf.data(), r.ptr);
}

// The index of the first byte that is not printable ASCII other than '"' and '\\' (s.size() if
// none: the string is written as it is).
std::size_t first_special(std::string_view s) {
  for (std::size_t i = 0; i < s.size(); ++i) {
    const auto u = static_cast<unsigned char>(s[i]);
    if (u < 0x20 || u >= 0x80 || u == '"' || u == '\\') return i;
  }
  return s.size();
}

bool ascii(std::string_view s) {
  for (char c : s)
    if (static_cast<unsigned char>(c) >= 0x80) return false;
  return true;
}

// ASCII is escaped here as nlohmann escapes it (ensure_ascii off: '"', '\\', the short escapes,
// other control characters as \u00xx in lower case, everything else as is); a string with a byte
// of 0x80 or more (UTF-8 sequences that may be invalid) goes through nlohmann's escaping, so the
// bytes stay nlohmann's.
void append_escaped(std::string& out, std::string_view s) {
  const std::size_t special = first_special(s);
  if (special == s.size()) {  // most keys and strings: nothing to escape
    out += '"';
    out.append(s);
    out += '"';
    return;
  }
  if (!ascii(s.substr(special))) {
    out += json(std::string(s)).dump(-1, ' ', false, json::error_handler_t::replace);
    return;
  }
  static constexpr char kHex[] = "0123456789abcdef";
  out += '"';
  out.append(s.substr(0, special));
  std::size_t plain_from = special;
  for (std::size_t i = special; i < s.size(); ++i) {
    const auto u = static_cast<unsigned char>(s[i]);
    if (u >= 0x20 && u != '"' && u != '\\') continue;
    out.append(s.data() + plain_from, i - plain_from);
    plain_from = i + 1;
    switch (u) {
      case '"':
        out += "\\\"";
        break;
      case '\\':
        out += "\\\\";
        break;
      case '\b':
        out += "\\b";
        break;
      case '\t':
        out += "\\t";
        break;
      case '\n':
        out += "\\n";
        break;
      case '\f':
        out += "\\f";
        break;
      case '\r':
        out += "\\r";
        break;
      default:
        out += "\\u00";
        out += kHex[u >> 4];
        out += kHex[u & 0xF];
    }
  }
  out.append(s.data() + plain_from, s.size() - plain_from);
  out += '"';
}

// Writes the events of a SAX parse through a JsonWriter: the text again, compact, in order.
class EchoSax : public nlohmann::json_sax<json> {
 public:
  EchoSax(JsonWriter& w, bool raw_float) : w_(w), raw_float_(raw_float) {}
  bool null() override { return w_.null(), true; }
  bool boolean(bool v) override { return w_.boolean(v), true; }
  bool number_integer(number_integer_t v) override { return w_.integer(v), true; }
  bool number_unsigned(number_unsigned_t v) override { return w_.unsigned_integer(v), true; }
  bool number_float(number_float_t v, const string_t& text) override {
    if (raw_float_ && depth_ == 0)
      w_.raw(text);
    else
      w_.number(v);
    return true;
  }
  bool string(string_t& v) override { return w_.string(v), true; }
  bool binary(binary_t&) override { return false; }
  bool start_object(std::size_t) override { return ++depth_, w_.begin_object(), true; }
  bool key(string_t& k) override { return w_.key(k), true; }
  bool end_object() override { return --depth_, w_.end_object(), true; }
  bool start_array(std::size_t) override { return ++depth_, w_.begin_array(), true; }
  bool end_array() override { return --depth_, w_.end_array(), true; }
  bool parse_error(std::size_t, const std::string&, const nlohmann::detail::exception&) override {
    return false;
  }

 private:
  JsonWriter& w_;
  bool raw_float_;
  int depth_ = 0;
};

}  // namespace

void JsonWriter::separate() {
  if (after_key_) {
    after_key_ = false;
    return;
  }
  if (first_.empty()) return;
  if (first_.back() != 0)
    first_.back() = 0;
  else
    out_ += ',';
}

JsonWriter& JsonWriter::begin_object() {
  separate();
  out_ += '{';
  first_.push_back(1);
  return *this;
}

JsonWriter& JsonWriter::end_object() {
  out_ += '}';
  first_.pop_back();
  return *this;
}

JsonWriter& JsonWriter::begin_array() {
  separate();
  out_ += '[';
  first_.push_back(1);
  return *this;
}

JsonWriter& JsonWriter::end_array() {
  out_ += ']';
  first_.pop_back();
  return *this;
}

JsonWriter& JsonWriter::key(std::string_view name) {
  separate();
  append_escaped(out_, name);
  out_ += ':';
  after_key_ = true;
  return *this;
}

JsonWriter& JsonWriter::string(std::string_view value) {
  separate();
  append_escaped(out_, value);
  return *this;
}

JsonWriter& JsonWriter::boolean(bool value) {
  separate();
  out_ += value ? "true" : "false";
  return *this;
}

JsonWriter& JsonWriter::integer(std::int64_t value) {
  separate();
  append_int(out_, value);
  return *this;
}

JsonWriter& JsonWriter::unsigned_integer(std::uint64_t value) {
  separate();
  append_int(out_, value);
  return *this;
}

JsonWriter& JsonWriter::number(double value) {
  separate();
  append_number(out_, value);
  return *this;
}

void JsonWriter::append_number(std::string& out, double value) {
  // What nlohmann's serializer does for a double (dump_float): null for NaN and infinities, else
  // its shortest round-trip form (Grisu2, "1.0" for integral values), without a tree or a string.
  if (!std::isfinite(value)) {
    out += "null";
    return;
  }
  std::array<char, 64> buf{};
  char* end = nlohmann::detail::to_chars(buf.data(), buf.data() + buf.size(), value);
  out.append(buf.data(), end);
}

void JsonWriter::append_string(std::string& out, std::string_view value) {
  append_escaped(out, value);
}

void JsonWriter::append_integer(std::string& out, std::int64_t value) {
  append_int(out, value);
}

JsonWriter& JsonWriter::null() {
  separate();
  out_ += "null";
  return *this;
}

JsonWriter& JsonWriter::raw(std::string_view text) {
  separate();
  out_ += text;
  return *this;
}

JsonWriter& JsonWriter::value(const json& j) {
  separate();
  out_ += j.dump(-1, ' ', false, json::error_handler_t::replace);
  return *this;
}

JsonWriter& JsonWriter::echo(std::string_view text, bool raw_float) {
  EchoSax sax(*this, raw_float);
  json::sax_parse(text, &sax);
  return *this;
}

std::string& JsonWriter::raw_begin() {
  separate();
  return out_;
}

}  // namespace flipper::toolkit::json
