// Requests in: `flipper dds` answers session-protocol requests from rt/flipper/request on
// rt/flipper/answer, with the same answer lines as `flipper session` for the same script (only
// the timing field `ms` differs); malformed samples are answered with an error or dropped.
#include <map>

#include "dds_test_support.hpp"
#include "flipper/dds/request_node.hpp"
#include "flipper/msg/SessionLine.h"

using namespace flipper;
using namespace flipper::ddstest;

namespace {

constexpr int kDomain = 162;

struct Client {
  dds_entity_t writer = 0, reader = 0;
  explicit Client(dds::Participant& p) {
    dds::Qos qos;
    dds_qset_reliability(qos.q, DDS_RELIABILITY_RELIABLE, DDS_SECS(10));
    dds_qset_history(qos.q, DDS_HISTORY_KEEP_ALL, DDS_LENGTH_UNLIMITED);
    writer = dds_create_writer(p.handle(),
                               p.topic(&flipper_msg_dds__SessionLine__desc, dds::kRequestTopic),
                               qos.q, nullptr);
    reader = dds_create_reader(p.handle(),
                               p.topic(&flipper_msg_dds__SessionLine__desc, dds::kAnswerTopic),
                               qos.q, nullptr);
    REQUIRE(writer > 0);
    REQUIRE(reader > 0);
  }
  void send(const std::string& session, std::uint64_t id, const std::string& line) {
    flipper_msg_dds__SessionLine_ s{};
    s.session_ = const_cast<char*>(session.c_str());
    s.request_id_ = id;
    s.line_ = const_cast<char*>(line.c_str());
    REQUIRE(dds_write(writer, &s) == DDS_RETCODE_OK);
  }
  /// Answers received so far, by request id (session checked).
  std::map<std::uint64_t, std::pair<std::string, std::string>> answers;
  void poll() {
    void* samples[8] = {};
    dds_sample_info_t infos[8];
    dds_return_t n;
    while ((n = dds_take(reader, samples, infos, 8, 8)) > 0) {
      for (dds_return_t i = 0; i < n; ++i)
        if (infos[i].valid_data) {
          const auto* s = static_cast<const flipper_msg_dds__SessionLine_*>(samples[i]);
          answers[s->request_id_] = {s->session_, s->line_};
        }
      dds_return_loan(reader, samples, n);
    }
  }
  bool wait_for(std::uint64_t id) {
    return wait_until([&] {
      poll();
      return answers.count(id) > 0;
    });
  }
};

json without_ms(json a) {
  a.erase("ms");
  return a;
}

}  // namespace

TEST_CASE("flipper dds answers requests exactly as flipper session does", "[dds]") {
  const auto dir = scratch_dir("node");
  const std::vector<std::string> script = {
      R"({"op":"user","name":"ana","id":1})",
      R"({"op":"query","text":"pick 3 items"})",
      R"({"op":"define","head":"pick 3 items","body":["repeat 3 times pick item"]})",
      R"({"op":"query","text":"drop 2 items","id":"q"})",
      R"({"op":"accept","rank":0})",
      R"({"op":"rules"})",
      R"({"op":"nonsense"})",
      R"({"op":"state"})"};
  // The reference: flipper session on its own lexicon.
  testsupport::ChildProcess reference(
      {flipper_bin(), "session", "--set", "lexicon.path=" + (dir / "ref.sqlite").string()});
  std::vector<json> expected;
  for (const auto& line : script) {
    REQUIRE(reference.write_line(line));
    expected.push_back(json::parse(reference.read_line()));
  }
  REQUIRE(reference.finish() == 0);

  auto participant = test_participant(kDomain);
  Client client(*participant);
  testsupport::ChildProcess node({flipper_bin(), "dds", "--set",
                                  "dds.domain=" + std::to_string(kDomain), "--set",
                                  "lexicon.path=" + (dir / "node.sqlite").string()});
  // Discovery: the first request goes out once the node's reader has matched ours.
  REQUIRE(wait_until([&] {
    dds_publication_matched_status_t st;
    return dds_get_publication_matched_status(client.writer, &st) == 0 && st.current_count > 0;
  }));
  std::uint64_t id = 100;
  for (std::size_t i = 0; i < script.size(); ++i) {
    client.send("s1", ++id, script[i]);
    REQUIRE(client.wait_for(id));
    CHECK(client.answers[id].first == "s1");
    CHECK(without_ms(json::parse(client.answers[id].second)) == without_ms(expected[i]));
  }

  SECTION("malformed samples are answered with an error or dropped, never a crash") {
    client.send("s1", 500, "{not json");
    REQUIRE(client.wait_for(500));
    CHECK(json::parse(client.answers[500].second)["error"]["code"] == "bad_json");
    client.send("s1", 501, std::string("{\"op\":\"query\",\"text\":\"\xff\xfe\"}"));
    REQUIRE(client.wait_for(501));
    CHECK(json::parse(client.answers[501].second)["ok"] == false);
    client.send("s1", 502, std::string(2 << 20, 'x'));
    REQUIRE(client.wait_for(502));
    CHECK(json::parse(client.answers[502].second)["error"]["code"] == "input_too_long");
    client.send("", 503, R"({"op":"state"})");           // no session name: dropped
    client.send("bad\nname", 504, R"({"op":"state"})");  // control characters: dropped
    client.send("s2", 505, R"({"op":"user","name":"bo"})");
    REQUIRE(client.wait_for(505));  // the node is alive and a new session works
    CHECK(json::parse(client.answers[505].second)["name"] == "bo");
    CHECK(client.answers.count(503) == 0);
    CHECK(client.answers.count(504) == 0);
    // Session s1 still has its state: the user from the script.
    client.send("s1", 506, R"({"op":"rules","author":"ana"})");
    REQUIRE(client.wait_for(506));
    CHECK(json::parse(client.answers[506].second)["rules"].size() == expected[5]["rules"].size());
  }
  kill(node.pid(), SIGTERM);
  CHECK(node.finish() == 0);
  std::filesystem::remove_all(dir);
}
