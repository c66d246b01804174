#pragma once
// A requester's two ends of a `flipper dds` node (docs/dds.md): the request writer and the answer
// reader of node namespace `ns`, reliable and keep-all, and one SessionLine sent on the writer.
#include <catch2/catch.hpp>
#include <cstdint>
#include <string>

#include "flipper/dds/names.hpp"
#include "flipper/dds/participant.hpp"
#include "flipper/msg/SessionLine.h"

namespace flipper::ddstest {

struct SessionEnds {
  dds_entity_t writer = 0, reader = 0;
};

inline SessionEnds session_ends(dds::Participant& p, const std::string& ns) {
  dds::Qos qos;
  dds_qset_reliability(qos.q, DDS_RELIABILITY_RELIABLE, DDS_SECS(10));
  dds_qset_history(qos.q, DDS_HISTORY_KEEP_ALL, DDS_LENGTH_UNLIMITED);
  SessionEnds e;
  e.writer = dds_create_writer(
      p.handle(), p.topic(&flipper_msg_dds__SessionLine__desc, dds::node_topic(ns, "request")),
      qos.q, nullptr);
  e.reader = dds_create_reader(
      p.handle(), p.topic(&flipper_msg_dds__SessionLine__desc, dds::node_topic(ns, "answer")),
      qos.q, nullptr);
  REQUIRE(e.writer > 0);
  REQUIRE(e.reader > 0);
  return e;
}

inline void send_line(dds_entity_t writer, const std::string& session, std::uint64_t id,
                      const std::string& line) {
  flipper_msg_dds__SessionLine_ s{};
  s.session_ = const_cast<char*>(session.c_str());
  s.request_id_ = id;
  s.line_ = const_cast<char*>(line.c_str());
  REQUIRE(dds_write(writer, &s) == DDS_RETCODE_OK);
}

}  // namespace flipper::ddstest
