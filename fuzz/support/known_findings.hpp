#pragma once
/// @file known_findings.hpp
/// Input classes with a known, already filed defect that the `limits` helper is fixing
/// (issue 11, item 2). A fuzz target skips such inputs so that CI fails only on new findings;
/// each guard names its class and is deleted once the fix is on main (the class's reproducer
/// stays in fuzz/corpus/<target>/ as a seed, so the fixed code keeps being exercised).
///
/// FLIPPER_FUZZ_KNOWN=0 in the environment turns every guard off (to reproduce or to check a
/// fix). At exit the target prints how many inputs each guard skipped.
#include <string_view>

namespace flipper::fuzz::known {

enum class Class {
  /// session: non-ASCII bytes in a line that is not valid JSON: the bad_json answer quotes the
  /// text around the error (a bad byte, or a cut multi-byte sequence) and fails to serialise
  BadJsonUtf8,
  HugeNumber,   ///< session, world: a number beyond double range (1e999, 400 digits) ends the
                ///< session; in a world it escapes parse_world as out_of_range (plugin_error)
  DeepJson,     ///< session: `id` nested thousands deep (recursive copy when echoing)
  LongLine,     ///< session: a define head/body of >= 65,535 tokens (chart index wraps)
  ParseBudget,  ///< session: parse time is not bounded by the time budget ({ x990, not ... and)
  HugeWorld,    ///< world: bounds of millions of cells allocate GBs
  NonRegular,   ///< world/config/session: /dev/zero, FIFOs, directories as files
  kCount
};

/// Whether guards are on (FLIPPER_FUZZ_KNOWN is not "0").
bool enabled();

/// Counts a skipped input of class `c` and returns true, when guards are on; false otherwise.
bool skip(Class c);

/// Detectors used by the targets' guards.
bool has_invalid_utf8(std::string_view text);
bool has_non_ascii(std::string_view text);
/// A JSON-style number literal whose value overflows a double.
bool has_huge_number(std::string_view text);
/// Bracket nesting ([ and {) deeper than `limit`.
bool nesting_deeper_than(std::string_view text, int limit);
/// More than `limit` whitespace-separated words.
bool more_words_than(std::string_view text, int limit);
/// Mentions a path under /dev, /proc or /sys.
bool names_special_path(std::string_view text);

}  // namespace flipper::fuzz::known
