#pragma once
/// @file request_node.hpp
/// `flipper dds`: session-protocol requests in on rt/<dds.namespace>/flipper/request, answers
/// out on rt/<dds.namespace>/flipper/answer (names.hpp; rt/flipper/... in the root namespace;
/// type flipper::msg::dds_::SessionLine_: session, request_id, line). The namespace addresses
/// the node, as ROS 2 addresses nodes: a request reaches only the node of its namespace, so one
/// node answers it (give each node its own namespace). Each
/// session name is its own Flipper session (world, user, last query), made on first use, all
/// sharing one runtime and lexicon; the answer line is exactly what `flipper session` writes for
/// the same request line. QoS of both topics: reliable, volatile, keep-all.
///
/// The answer topic is volatile, so an answer written before the node's answer writer has
/// matched the requester's answer reader would be lost (discovery runs each way on its own: a
/// client that sees the node's endpoints may not be seen yet). The node therefore writes an
/// answer once its answer writer has matched a reader of the requesting participant, waiting
/// up to kAwaitReader (a wall-clock bound on a runaway only: the answer is the same either way);
/// past it the answer is written anyway, logged, and that participant's later answers are
/// written at once (docs/ros2.md, "Requests over DDS").
///
/// Bad samples never stop the node: a session name that is empty, longer than 256 bytes or
/// holds control characters, is logged and dropped (no answer: there is no safe name to answer
/// to); a line longer than kMaxLine bytes, or a new session beyond the limit, gets an error
/// answer (codes input_too_long, too_many_sessions); a line that is not JSON gets the session's
/// own bad_json answer.

#include <array>
#include <atomic>
#include <chrono>
#include <cstdint>
#include <functional>
#include <iosfwd>
#include <map>
#include <memory>
#include <optional>
#include <set>
#include <string>

#include "flipper/dds/participant.hpp"
#include "flipper/kernel/session.hpp"

namespace flipper::dds {

inline constexpr const char* kRequestTopic = "rt/flipper/request";
inline constexpr const char* kAnswerTopic = "rt/flipper/answer";

class RequestNode {
 public:
  using SessionMaker = std::function<std::unique_ptr<kernel::Session>()>;
  static constexpr std::size_t kMaxLine = 1 << 20;
  static constexpr std::size_t kMaxSessionName = 256;
  static constexpr std::chrono::milliseconds kAwaitReader{5000};

  RequestNode(std::shared_ptr<Participant> participant, SessionMaker make_session,
              std::ostream& log, const std::string& ns = {}, std::size_t max_sessions = 64);
  ~RequestNode();
  RequestNode(const RequestNode&) = delete;
  RequestNode& operator=(const RequestNode&) = delete;

  /// Serves until `stop` becomes true (checked at least every 100 ms and before each request:
  /// once it is true no further request is answered).
  void run(const std::atomic<bool>& stop);
  /// Waits up to `timeout` until every answer written is acknowledged by the readers matched
  /// (the answers a requester was sent reach it before the node exits); whether they all were.
  bool flush(std::chrono::milliseconds timeout);
  /// One request -> the answer line, or nothing when the sample is dropped. Never throws.
  std::optional<std::string> answer(const std::string& session, std::uint64_t request_id,
                                    const std::string& line);
  std::uint64_t answered() const { return answered_; }
  std::uint64_t dropped() const { return dropped_; }
  const std::string& request_topic() const { return request_topic_; }
  const std::string& answer_topic() const { return answer_topic_; }

 private:
  using Guid = std::array<std::uint8_t, 16>;
  void serve_available(const std::atomic<bool>& stop);
  /// Waits (up to kAwaitReader, or until `stop`) until the answer writer has matched a reader of
  /// the participant whose writer `request_writer` sent request `id`.
  void await_answer_reader(dds_instance_handle_t request_writer, std::uint64_t id,
                           const std::atomic<bool>& stop);
  bool answer_reader_matched(const Guid& participant);

  std::shared_ptr<Participant> participant_;
  SessionMaker make_session_;
  std::ostream& log_;
  std::size_t max_sessions_;
  std::string request_topic_, answer_topic_;
  std::map<std::string, std::unique_ptr<kernel::Session>, std::less<>> sessions_;
  dds_entity_t reader_ = 0;
  dds_entity_t writer_ = 0;
  dds_entity_t waitset_ = 0;
  std::uint64_t answered_ = 0;
  std::uint64_t dropped_ = 0;
  /// The participant of each reader the answer writer has matched (pruned to those matched now
  /// whenever it holds more).
  std::map<dds_instance_handle_t, Guid> reader_participants_;
  /// Participants whose answer reader did not match within kAwaitReader (not waited for again;
  /// at most kMaxReaderless, then forgotten).
  std::set<Guid> readerless_;
  static constexpr std::size_t kMaxReaderless = 4096;
};

}  // namespace flipper::dds
