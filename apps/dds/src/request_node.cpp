#include "flipper/dds/request_node.hpp"

#include <algorithm>
#include <cstring>
#include <nlohmann/json.hpp>
#include <ostream>
#include <thread>
#include <vector>

#include "flipper/dds/names.hpp"
#include "flipper/msg/SessionLine.h"

namespace flipper::dds {
namespace {

void keep_all_reliable(Qos& qos) {
  dds_qset_reliability(qos.q, DDS_RELIABILITY_RELIABLE, DDS_SECS(10));
  dds_qset_durability(qos.q, DDS_DURABILITY_VOLATILE);
  dds_qset_history(qos.q, DDS_HISTORY_KEEP_ALL, DDS_LENGTH_UNLIMITED);
}

std::string error_line(std::uint64_t id, const char* code, const std::string& message) {
  kernel::Json a;
  a["ok"] = false;
  a["op"] = nullptr;
  a["error"] = kernel::Json{{"code", code}, {"message", message}};
  (void)id;
  return a.dump(-1, ' ', false, kernel::Json::error_handler_t::replace);
}

// Printable name for logs (hostile names are shown escaped and cut).
std::string shown(const std::string& s) {
  std::string out;
  for (unsigned char c : s.substr(0, 64))
    out += (c < 0x20 || c == 0x7f)
               ? std::string("\\x") + "0123456789abcdef"[c >> 4] + "0123456789abcdef"[c & 15]
               : std::string(1, static_cast<char>(c));
  return s.size() > 64 ? out + "..." : out;
}

}  // namespace

RequestNode::RequestNode(std::shared_ptr<Participant> participant, SessionMaker make_session,
                         std::ostream& log, const std::string& ns, std::size_t max_sessions)
    : participant_(std::move(participant)),
      make_session_(std::move(make_session)),
      log_(log),
      max_sessions_(max_sessions),
      request_topic_(node_topic(ns, "request")),
      answer_topic_(node_topic(ns, "answer")) {
  Qos qos;
  keep_all_reliable(qos);
  auto& p = *participant_;
  reader_ = check(
      dds_create_reader(p.handle(), p.topic(&flipper_msg_dds__SessionLine__desc, request_topic_),
                        qos.q, nullptr),
      "creating the request reader");
  writer_ = check(
      dds_create_writer(p.handle(), p.topic(&flipper_msg_dds__SessionLine__desc, answer_topic_),
                        qos.q, nullptr),
      "creating the answer writer");
  waitset_ = check(dds_create_waitset(p.handle()), "creating a waitset");
  check(dds_set_status_mask(reader_, DDS_DATA_AVAILABLE_STATUS), "reader status mask");
  check(dds_waitset_attach(waitset_, reader_, reader_), "attaching the request reader");
}

RequestNode::~RequestNode() {
  for (dds_entity_t e : {waitset_, reader_, writer_})
    if (e > 0) dds_delete(e);
}

std::optional<std::string> RequestNode::answer(const std::string& name, std::uint64_t id,
                                               const std::string& line) {
  const bool bad_name = name.empty() || name.size() > kMaxSessionName ||
                        std::any_of(name.begin(), name.end(), [](char c) {
                          return static_cast<unsigned char>(c) < 0x20 || c == 0x7f;
                        });
  if (bad_name) {
    ++dropped_;
    log_ << "flipper dds: dropped request " << id << ": session name '" << shown(name)
         << "' must be 1.." << kMaxSessionName << " printable bytes" << std::endl;
    return std::nullopt;
  }
  if (line.size() > kMaxLine)
    return error_line(id, "input_too_long",
                      "the request line has " + std::to_string(line.size()) + " bytes; at most " +
                          std::to_string(kMaxLine) + " are accepted");
  auto it = sessions_.find(name);
  if (it == sessions_.end()) {
    if (sessions_.size() >= max_sessions_)
      return error_line(id, "too_many_sessions",
                        "this node serves at most " + std::to_string(max_sessions_) +
                            " sessions; reuse a session name");
    try {
      it = sessions_.emplace(name, make_session_()).first;
    } catch (const std::exception& e) {
      return error_line(id, "internal", std::string("cannot open a session: ") + e.what());
    }
  }
  try {
    return it->second->handle_line(line);  // never throws by contract; guarded anyway
  } catch (const std::exception& e) {
    return error_line(id, "internal", std::string("internal error: ") + e.what());
  }
}

void RequestNode::serve_available(const std::atomic<bool>& stop) {
  constexpr int kBatch = 16;
  void* samples[kBatch] = {};
  dds_sample_info_t infos[kBatch];
  while (!stop.load()) {
    const dds_return_t n = dds_take(reader_, samples, infos, kBatch, kBatch);
    if (n <= 0) {
      if (n < 0) log_ << "flipper dds: take failed: " << dds_strretcode(n) << std::endl;
      return;
    }
    for (dds_return_t i = 0; i < n; ++i) {
      if (!infos[i].valid_data) continue;  // dispose/unregister notices carry no request
      if (stop.load()) continue;  // stopping: taken but never answered, so never acknowledged
      const auto* s = static_cast<const flipper_msg_dds__SessionLine_*>(samples[i]);
      const std::string name = s->session_ ? s->session_ : "";
      const std::string line = s->line_ ? s->line_ : "";
      const std::uint64_t id = s->request_id_;
      std::optional<std::string> answer_line = answer(name, id, line);
      if (!answer_line || answer_line->empty()) continue;  // dropped, or a blank line
      await_answer_reader(infos[i].publication_handle, id, stop);
      flipper_msg_dds__SessionLine_ out{};
      out.session_ = const_cast<char*>(name.c_str());
      out.request_id_ = id;
      out.line_ = answer_line->data();
      if (const dds_return_t rc = dds_write(writer_, &out); rc < 0)
        log_ << "flipper dds: answer " << id << " not sent: " << dds_strretcode(rc) << std::endl;
      else
        ++answered_;
    }
    dds_return_loan(reader_, samples, n);
  }
}

void RequestNode::await_answer_reader(dds_instance_handle_t request_writer, std::uint64_t id,
                                      const std::atomic<bool>& stop) {
  dds_builtintopic_endpoint_t* writer = dds_get_matched_publication_data(reader_, request_writer);
  if (writer == nullptr) return;  // the requester's writer is gone: no participant to wait for
  Guid who;
  std::memcpy(who.data(), writer->participant_key.v, who.size());
  dds_builtintopic_free_endpoint(writer);
  if (readerless_.count(who) != 0) return;
  const auto end = std::chrono::steady_clock::now() + kAwaitReader;
  while (!answer_reader_matched(who)) {
    if (stop.load()) return;
    if (std::chrono::steady_clock::now() >= end) {
      log_ << "flipper dds: answer " << id << ": no answer reader of the requesting participant "
           << "matched within " << kAwaitReader.count()
           << " ms; written anyway, and its later answers at once" << std::endl;
      if (readerless_.size() >= kMaxReaderless) readerless_.clear();
      readerless_.insert(who);
      return;
    }
    std::this_thread::sleep_for(std::chrono::milliseconds(2));
  }
}

bool RequestNode::answer_reader_matched(const Guid& participant) {
  std::vector<dds_instance_handle_t> handles(reader_participants_.size() + 16);
  dds_return_t n = dds_get_matched_subscriptions(writer_, handles.data(), handles.size());
  if (n > 0 && static_cast<std::size_t>(n) > handles.size()) {  // more readers came meanwhile
    handles.resize(static_cast<std::size_t>(n) + 16);
    n = dds_get_matched_subscriptions(writer_, handles.data(), handles.size());
  }
  if (n < 0) return true;  // cannot tell: do not hold the answer back
  handles.resize(std::min(handles.size(), static_cast<std::size_t>(n)));
  bool found = false;
  std::size_t matched = 0;  // of the handles, those still matched (in the cache now)
  for (const dds_instance_handle_t h : handles) {
    auto known = reader_participants_.find(h);
    if (known == reader_participants_.end()) {
      dds_builtintopic_endpoint_t* r = dds_get_matched_subscription_data(writer_, h);
      if (r == nullptr) continue;  // unmatched since the list was taken
      Guid g;
      std::memcpy(g.data(), r->participant_key.v, g.size());
      dds_builtintopic_free_endpoint(r);
      known = reader_participants_.emplace(h, g).first;
    }
    ++matched;
    found = found || known->second == participant;
  }
  // Readers no longer matched are forgotten; only then is there work (usually none per answer).
  if (reader_participants_.size() > matched) {
    std::sort(handles.begin(), handles.end());
    std::erase_if(reader_participants_, [&](const auto& entry) {
      return !std::binary_search(handles.begin(), handles.end(), entry.first);
    });
  }
  return found;
}

void RequestNode::run(const std::atomic<bool>& stop) {
  while (!stop.load()) {
    dds_attach_t triggered = 0;
    const dds_return_t rc = dds_waitset_wait(waitset_, &triggered, 1, DDS_MSECS(100));
    if (rc < 0) {
      log_ << "flipper dds: wait failed: " << dds_strretcode(rc) << std::endl;
      return;
    }
    serve_available(stop);
  }
}

bool RequestNode::flush(std::chrono::milliseconds timeout) {
  const dds_return_t rc = dds_wait_for_acks(writer_, DDS_MSECS(timeout.count()));
  if (rc == DDS_RETCODE_OK) return true;
  log_ << "flipper dds: not every answer was acknowledged within " << timeout.count()
       << " ms: " << dds_strretcode(rc) << std::endl;
  return false;
}

}  // namespace flipper::dds
