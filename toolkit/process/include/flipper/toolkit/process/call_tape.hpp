#pragma once
/// @file call_tape.hpp
/// Record and replay of a series of calls across a fork (docs/architecture.md §1 "The toolkit"):
/// a child makes the calls and records each one (what it was asked, as a key its caller computes;
/// what it cost; how it ended; its answer's bytes), sending each record as it is made
/// (send_to_parent), so that a tape cut short by the child's death reads to its last whole
/// record; its parent then makes the same series again and takes each call's answer from the
/// tape, in order, for as long as the calls are the recorded ones. Each call is announced before
/// it is made (a begun record: its key, tag kBegun), so that a tape whose child died in a call
/// says which: that call's take gives the begun record, and its caller gives the call the end
/// the child met (end()). A tape's bytes are what a child sent, and the child may have run
/// anything: every length is checked, and a record that is not whole ends the tape. Generic: it
/// knows no plugin and no budget; the kernel runs an execution's planner calls this way
/// (docs/plugins-untrusted.md §6, "One child per execution").

#include <chrono>
#include <cstddef>
#include <cstdint>
#include <exception>
#include <optional>
#include <string>

namespace flipper::toolkit::process {

/// One recorded call.
struct TapeRecord {
  std::uint64_t key = 0;            ///< what the call was asked (the caller's fingerprint)
  std::chrono::nanoseconds cpu{0};  ///< the CPU time it took
  char tag = 0;                     ///< how it ended (the caller's: an answer, a failure)
  std::string bytes;                ///< its answer or failure
};

/// The tag of a call's begun record (sent before the call; its answer's record follows).
inline constexpr char kBegun = 'B';

/// A thread's tape: while one is alive, it is the thread's current() tape (an earlier one comes
/// back when it ends). Not copyable.
class CallTape {
 public:
  enum class Mode {
    probe,   ///< the first call is made as without a tape; the second is noted (missed) and
             ///< its caller gives up (probe_call)
    record,  ///< in the child: the calls are made and each record sent (bytes_of)
    replay,  ///< in the parent: the calls take their answers from `tape` (take)
  };
  /// `end`: how the recording child ended when it did not finish (its caller's error), or null.
  explicit CallTape(Mode mode, std::string tape = {}, std::exception_ptr end = nullptr);
  ~CallTape();
  CallTape(const CallTape&) = delete;
  CallTape& operator=(const CallTape&) = delete;

  /// The calling thread's tape, or null.
  static CallTape* current();
  Mode mode() const { return mode_; }
  /// probe: whether this call may be made (the first); false from the second on, which is
  /// noted (missed()).
  bool probe_call() {
    missed_ = missed_ || calls_ > 0;
    return calls_++ == 0;
  }
  bool missed() const { return missed_; }
  /// replay: the answer's record of the call `key` when it is the next one on the tape (after
  /// its begun record); its begun record (tag kBegun) when no whole record follows that (the
  /// child died in that call: end()); nullopt when the tape has no whole record left or its
  /// next one is another call's, and then for every later call too (the series has left the
  /// recorded one: missed()).
  std::optional<TapeRecord> take(std::uint64_t key);
  const std::exception_ptr& end() const { return end_; }
  /// record: the bytes of the records sent so far (their sender counts them here).
  std::size_t sent() const { return sent_; }
  void count_sent(std::size_t bytes) { sent_ += bytes; }
  /// A record's bytes on the tape: its length first, then the key, the CPU time, the tag and the
  /// answer (numbers in this machine's byte order: the child is a fork of the same program).
  static std::string bytes_of(const TapeRecord& record);

 private:
  Mode mode_;
  std::string tape_;
  std::size_t at_ = 0;
  bool missed_ = false;
  std::size_t calls_ = 0, sent_ = 0;
  std::exception_ptr end_;
  CallTape* outer_;
  std::optional<TapeRecord> next();
  std::optional<TapeRecord> miss_now();
};

}  // namespace flipper::toolkit::process
