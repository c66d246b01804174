#pragma once
/// @file rule_snapshot.hpp
/// The compact rule snapshot (docs/naturalization.md §5 "Start-up at scale"): every live rule of a
/// lexicon at one ChangeMark, encoded back to back in one blob, so a process starts by reading one
/// row instead of building a StoredRule per SQLite row. A derived cache: the rows stay the truth.
///
/// Encoding (little-endian, no alignment): "FLXS", u32 format, u64 rule count, then per rule
/// i64 created, i64 definition, and the strings id, lhs, semantics, author, head, how and
/// decode_error (empty unless the row does not decode: such a rule is kept, to be quarantined at
/// every start, docs/naturalization.md §5 "Quarantine"), each as u32 length + bytes, then the rhs
/// and body lists as u32 count + strings. Use counters are not in it (they change on every accept,
/// without moving the mark).
#include <cstdint>
#include <functional>
#include <string>
#include <string_view>
#include <vector>

#include "flipper/naturalization/lexicon_store.hpp"

namespace flipper::naturalization {

/// Version of the encoding above; a snapshot of another format is ignored (rebuilt). Format 1 had
/// no decode_error.
inline constexpr std::uint32_t kRuleSnapshotFormat = 2;

/// Appends rules to a snapshot blob.
class RuleSnapshotWriter {
 public:
  RuleSnapshotWriter();
  void add(const StoredRule& rule);
  std::size_t size() const { return count_; }
  /// The finished blob (the writer is left empty).
  std::string finish();

 private:
  std::string out_;
  std::size_t count_ = 0;
};

/// One rule as it lies in a blob: views into it, valid during the callback only (decoding
/// allocates nothing per rule; the reader keeps the lists' capacity).
struct StoredRuleView {
  std::string_view id, lhs, semantics, author, head, how, decode_error;
  std::vector<std::string_view> rhs, body;
  std::int64_t created = 0;
  std::int64_t definition = 0;
  StoredRule materialize() const;  ///< an owning copy (use counters zero)
};

/// Reads a blob written by RuleSnapshotWriter. The whole blob is checked (bounds, counts, no
/// trailing bytes) before the first rule is handed out, so a damaged blob yields nothing and
/// returns false. `each` gets the rules in the order they were added.
bool read_rule_snapshot(std::string_view blob,
                        const std::function<void(const StoredRuleView&)>& each);

/// 64-bit checksum of a blob (not cryptographic: it catches damage, not forgery).
std::uint64_t snapshot_checksum(std::string_view blob);

}  // namespace flipper::naturalization
