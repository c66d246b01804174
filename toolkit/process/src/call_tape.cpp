// Record and replay of a series of calls across a fork (call_tape.hpp).
#include "flipper/toolkit/process/call_tape.hpp"

#include <cstring>
#include <utility>

namespace flipper::toolkit::process {
namespace {

thread_local CallTape* t_current = nullptr;

// A record's fixed part after its length: the key, the CPU time (ns) and the tag.
constexpr std::size_t kHead = sizeof(std::uint64_t) + sizeof(std::int64_t) + 1;

}  // namespace

CallTape::CallTape(Mode mode, std::string tape, std::exception_ptr end)
    : mode_(mode), tape_(std::move(tape)), end_(std::move(end)), outer_(t_current) {
  t_current = this;
}

CallTape::~CallTape() {
  t_current = outer_;
}

CallTape* CallTape::current() {
  return t_current;
}

std::optional<TapeRecord> CallTape::take(std::uint64_t key) {
  std::optional<TapeRecord> begun = next();
  if (!begun || begun->key != key || begun->tag != kBegun) return miss_now();
  std::optional<TapeRecord> answer = next();
  if (!answer) {  // the tape ends in this call: the child died in it
    missed_ = true;
    return begun;
  }
  if (answer->key != key || answer->tag == kBegun) return miss_now();
  return answer;
}

std::optional<TapeRecord> CallTape::miss_now() {
  missed_ = true;
  return std::nullopt;
}

// The next whole record, or nullopt (and the tape is done) when there is none.
std::optional<TapeRecord> CallTape::next() {
  std::uint64_t length = 0;
  if (missed_ || tape_.size() - at_ < sizeof length) return std::nullopt;
  std::memcpy(&length, tape_.data() + at_, sizeof length);
  const std::size_t body = at_ + sizeof length;
  if (length < kHead || length > tape_.size() - body) return std::nullopt;  // cut short
  TapeRecord r;
  std::memcpy(&r.key, tape_.data() + body, sizeof r.key);
  std::int64_t cpu = 0;
  std::memcpy(&cpu, tape_.data() + body + sizeof r.key, sizeof cpu);
  if (cpu < 0) return std::nullopt;
  r.cpu = std::chrono::nanoseconds(cpu);
  r.tag = tape_[body + kHead - 1];
  r.bytes.assign(tape_, body + kHead, length - kHead);
  at_ = body + length;
  return r;
}

std::string CallTape::bytes_of(const TapeRecord& record) {
  const std::uint64_t length = kHead + record.bytes.size();
  const std::int64_t cpu = record.cpu.count();
  std::string out(sizeof length + kHead, '\0');
  std::memcpy(out.data(), &length, sizeof length);
  std::memcpy(out.data() + sizeof length, &record.key, sizeof record.key);
  std::memcpy(out.data() + sizeof length + sizeof record.key, &cpu, sizeof cpu);
  out[sizeof length + kHead - 1] = record.tag;
  out += record.bytes;
  return out;
}

}  // namespace flipper::toolkit::process
