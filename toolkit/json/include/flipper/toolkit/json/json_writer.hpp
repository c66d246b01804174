#pragma once
/// @file json_writer.hpp
/// A small streaming writer of compact JSON text, the way every protocol answer is written
/// (docs/protocol.md; toolkit/json: generic, it knows no protocol). It writes members in the order
/// the code writes them (the protocol's field order: "ok", "op", "id" first), and it embeds values
/// that are already JSON text (a world as the world plugin wrote it, a trace) without parsing them
/// again: a world is serialised once per distinct state, whatever the number of answers it appears
/// in.
///
/// Its bytes are nlohmann's `dump()` bytes for the same values (numbers, escapes, invalid UTF-8
/// replaced by U+FFFD), so answers written here equal the ones a JSON tree would give.
/// @code
///   std::string out;
///   JsonWriter w(out);
///   w.begin_object().key("ok").boolean(true).key("world").raw(world_text).end_object();
/// @endcode
/// The writer does not check the structure (a key outside an object, an unclosed array): the
/// session's byte-identity test (tests/kernel/session/test_session_golden.cpp) guards the answers,
/// tests/toolkit/json the values' bytes.

#include <cstdint>
#include <nlohmann/json_fwd.hpp>
#include <string>
#include <string_view>
#include <vector>

namespace flipper::toolkit::json {

class JsonWriter {
 public:
  explicit JsonWriter(std::string& out) : out_(out) {}

  JsonWriter& begin_object();
  JsonWriter& end_object();
  JsonWriter& begin_array();
  JsonWriter& end_array();
  /// The key of the next member (escaped like a string value).
  JsonWriter& key(std::string_view name);

  JsonWriter& string(std::string_view value);
  JsonWriter& boolean(bool value);
  JsonWriter& integer(std::int64_t value);
  JsonWriter& unsigned_integer(std::uint64_t value);
  /// Shortest round-trip form, as nlohmann writes a double (1.0, 0.25, 1e-05).
  JsonWriter& number(double value);
  JsonWriter& null();
  /// A value that is already compact JSON text (not checked).
  JsonWriter& raw(std::string_view json);
  /// A value from a JSON tree (objects in the tree's key order).
  JsonWriter& value(const nlohmann::json& json);
  /// The JSON text `json` again, compact, members in the order written there (no tree: an
  /// object's key order is kept); numbers as nlohmann writes their parsed values, except that a
  /// top-level floating-point number keeps its text (`raw_float`: an id such as 1.10 or a
  /// 25-digit integer comes back as sent). `json` must be valid JSON.
  JsonWriter& echo(std::string_view json, bool raw_float = false);

  /// Appends directly to the output: for a writer of an already known value shape (a trace).
  /// Call after the separator: `w.raw_begin()` writes it and returns the buffer.
  std::string& raw_begin();

  std::string& text() { return out_; }

  /// The writer's value texts, appended to `out` (for writers of a known shape, after
  /// raw_begin()): a string escaped as nlohmann escapes it, a double as nlohmann writes it (null
  /// for NaN and infinities), an integer.
  static void append_string(std::string& out, std::string_view value);
  static void append_number(std::string& out, double value);
  static void append_integer(std::string& out, std::int64_t value);

 private:
  void separate();

  std::string& out_;
  // Per open container: 1 while no member is written yet (a string: no allocation for the few
  // levels an answer has).
  std::string first_;
  bool after_key_ = false;
};

}  // namespace flipper::toolkit::json
