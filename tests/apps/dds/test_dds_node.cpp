// Requests in: `flipper dds` answers session-protocol requests from rt/flipper/request on
// rt/flipper/answer, with the same answer lines as `flipper session` for the same script (the
// example of docs/protocol.md and more; only the timing field `ms` differs); malformed samples
// are answered with an error or dropped; an invalid plan of an untrusted planner is refused with
// the same error as in `flipper session` (docs/plugins-untrusted.md). Two nodes in two
// namespaces: each request gets one answer, from the node it names, and each robot's plans go to
// its own topics.
#include <fstream>
#include <map>
#include <string_view>
#include <thread>

#include "dds_session_ends.hpp"
#include "dds_test_support.hpp"
#include "flipper/dds/names.hpp"
#include "flipper/dds/plan_publisher.hpp"
#include "flipper/dds/request_node.hpp"
#include "flipper/msg/Actions.h"
#include "flipper/msg/SessionLine.h"
#include "nav_msgs/msg/Path.h"

using namespace flipper;
using namespace flipper::ddstest;

namespace {

/// Takes every answer `reader` has received: got(request id, session, line) for each.
template <class Got>
void take_answers(dds_entity_t reader, Got got) {
  void* samples[8] = {};
  dds_sample_info_t infos[8];
  dds_return_t n;
  while ((n = dds_take(reader, samples, infos, 8, 8)) > 0) {
    for (dds_return_t i = 0; i < n; ++i)
      if (infos[i].valid_data) {
        const auto* s = static_cast<const flipper_msg_dds__SessionLine_*>(samples[i]);
        got(s->request_id_, std::string(s->session_), std::string(s->line_));
      }
    dds_return_loan(reader, samples, n);
  }
}

/// Whether `writer` matches a reader within wait_until's bound.
bool writer_matched(dds_entity_t writer) {
  return wait_until([&] {
    dds_publication_matched_status_t st;
    return dds_get_publication_matched_status(writer, &st) == 0 && st.current_count > 0;
  });
}

struct Client {
  dds_entity_t writer = 0, reader = 0;
  explicit Client(dds::Participant& p, const std::string& ns = {}) {
    const SessionEnds ends = session_ends(p, ns);
    writer = ends.writer;
    reader = ends.reader;
  }
  void send(const std::string& session, std::uint64_t id, const std::string& line) {
    send_line(writer, session, id, line);
  }
  /// Answers received so far, by request id (session checked), and how many came per id.
  std::map<std::uint64_t, std::pair<std::string, std::string>> answers;
  std::map<std::uint64_t, int> count;
  void poll() {
    take_answers(reader, [&](std::uint64_t id, std::string session, std::string line) {
      answers[id] = {std::move(session), std::move(line)};
      ++count[id];
    });
  }
  bool wait_for(std::uint64_t id) {
    return wait_until([&] {
      poll();
      return answers.count(id) > 0;
    });
  }
  bool matched() { return writer_matched(writer); }
};

json without_ms(json a) {
  a.erase("ms");
  return a;
}

/// The request lines of docs/protocol.md's "Example" section.
std::vector<std::string> protocol_example() {
  std::ifstream doc(std::string(FLIPPER_SOURCE_DIR) + "/docs/protocol.md");
  std::vector<std::string> lines;
  bool section = false, block = false;
  for (std::string line; std::getline(doc, line);) {
    if (line.rfind("## ", 0) == 0)
      section = line == "## Example";
    else if (section && line.rfind("```", 0) == 0) {
      if (block) break;
      block = true;
    } else if (section && block && !line.empty())
      lines.push_back(line);
  }
  return lines;
}

}  // namespace

TEST_CASE("flipper dds answers requests exactly as flipper session does", "[dds]") {
  const int kDomain = test_domain();
  const auto dir = scratch_dir("node");
  std::vector<std::string> script = protocol_example();
  REQUIRE(script.size() == 6);
  REQUIRE(script[0] == R"({"op":"world","file":"configs/worlds/study2018.json"})");
  for (const char* more : {R"({"op":"query","text":"drop 2 items","id":"q"})", R"({"op":"rules"})",
                           R"({"op":"nonsense"})", R"({"op":"state"})"})
    script.push_back(more);
  // The reference: flipper session on its own lexicon.
  testsupport::ChildProcess reference(
      {flipper_bin(), "session", "--set", "lexicon.path=" + (dir / "ref.sqlite").string()});
  // (The example's world file exists and loads: its answer is checked to be ok below.)
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
  REQUIRE(client.matched());
  std::uint64_t id = 100;
  for (std::size_t i = 0; i < script.size(); ++i) {
    client.send("s1", ++id, script[i]);
    REQUIRE(client.wait_for(id));
    CHECK(client.answers[id].first == "s1");
    CHECK(without_ms(json::parse(client.answers[id].second)) == without_ms(expected[i]));
  }
  CHECK(expected[0]["ok"] == true);

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
    CHECK(json::parse(client.answers[506].second)["rules"].size() == expected[7]["rules"].size());
  }
  kill(node.pid(), SIGTERM);
  CHECK(node.finish() == 0);
  std::filesystem::remove_all(dir);
}

TEST_CASE("flipper dds refuses an invalid plan exactly as flipper session does", "[dds]") {
  // docs/plugins-untrusted.md: the evil planner's straight walk from [2,4] to room1's [9,0]
  // enters the wall [9,3] on step 8 (hand-checked: tests/integration/untrusted).
  const int kDomain = test_domain();
  const auto dir = scratch_dir("untrusted");
  const std::string evil = std::string(FLIPPER_BINARY_DIR) + "/tests/plugins/evil";
  const std::vector<std::string> sets{"plugin_paths=[" + evil + "]", "planner.plugin=evil_planner",
                                      "planner.params.mode=wall"};
  const std::string request = R"({"op":"query","text":"visit room1"})";
  std::vector<std::string> reference_args{flipper_bin(), "session", "--set",
                                          "lexicon.path=" + (dir / "ref.sqlite").string()};
  std::vector<std::string> node_args{
      flipper_bin(), "dds",
      "--set",       "dds.domain=" + std::to_string(kDomain),
      "--set",       "lexicon.path=" + (dir / "node.sqlite").string()};
  for (const auto& s : sets) {
    for (auto* args : {&reference_args, &node_args}) {
      args->push_back("--set");
      args->push_back(s);
    }
  }
  testsupport::ChildProcess reference(reference_args);
  REQUIRE(reference.write_line(request));
  const json expected = json::parse(reference.read_line());
  REQUIRE(reference.finish() == 0);

  auto participant = test_participant(kDomain);
  Client client(*participant);
  testsupport::ChildProcess node(node_args);
  REQUIRE(client.matched());
  client.send("s1", 1, request);
  REQUIRE(client.wait_for(1));
  const json answer = json::parse(client.answers[1].second);
  CHECK(without_ms(answer) == without_ms(expected));
  json error;
  for (const auto& c : answer["candidates"])
    if (c["formula"] == "{visit room1}") error = c["error"];
  CHECK(error == json{{"code", "invalid_plan"},
                      {"message", "plugin 'evil_planner' (" + evil +
                                      "/evil_planner.so): step 8 enters wall [9,3]"}});
  kill(node.pid(), SIGTERM);
  CHECK(node.finish() == 0);
  std::filesystem::remove_all(dir);
}

TEST_CASE("two nodes give one answer each and each robot's plans go to its own topics", "[dds]") {
  const int domain = test_domain();
  const auto dir = scratch_dir("robots");
  auto participant = test_participant(domain);
  Client robot1(*participant, "robot1"), robot2(*participant, "robot2");
  SampleReader<nav_msgs_msg_dds__Path_> plans1(*participant, &nav_msgs_msg_dds__Path__desc,
                                               dds::node_topic("robot1", "plan"));
  SampleReader<nav_msgs_msg_dds__Path_> plans2(*participant, &nav_msgs_msg_dds__Path__desc,
                                               dds::node_topic("robot2", "plan"));
  SampleReader<flipper_msg_dds__ActionList_> actions1(
      *participant, &flipper_msg_dds__ActionList__desc, dds::node_topic("robot1", "actions"));
  std::vector<std::unique_ptr<testsupport::ChildProcess>> nodes;
  for (const char* ns : {"robot1", "robot2"})
    nodes.push_back(std::make_unique<testsupport::ChildProcess>(std::vector<std::string>{
        flipper_bin(), "dds", "--set", "dds.domain=" + std::to_string(domain), "--set",
        std::string("dds.namespace=") + ns, "--set", "publish.plans=dds", "--set",
        "lexicon.path=" + (dir / (std::string(ns) + ".sqlite")).string()}));
  REQUIRE(robot1.matched());
  REQUIRE(robot2.matched());

  // One request to each node, then one more to each as a barrier: each was read by one node.
  robot1.send("s1", 1, R"({"op":"user","name":"ana"})");
  robot2.send("s1", 2, R"({"op":"user","name":"bo"})");
  robot1.send("s1", 3, R"({"op":"state"})");
  robot2.send("s1", 4, R"({"op":"state"})");
  REQUIRE(robot1.wait_for(3));
  REQUIRE(robot2.wait_for(4));
  CHECK(robot1.count == std::map<std::uint64_t, int>{{1, 1}, {3, 1}});
  CHECK(robot2.count == std::map<std::uint64_t, int>{{2, 1}, {4, 1}});
  CHECK(json::parse(robot1.answers[1].second)["name"] == "ana");
  CHECK(json::parse(robot2.answers[2].second)["name"] == "bo");

  // Two sessions on two robots: robot1 visits room3 from (10,7) (4 poses, first at x=10),
  // robot2 moves up from (3,7) (2 poses, first at x=3); world.resolution is 1, origin 0.
  const auto accept = [](Client& c, std::uint64_t id, const json& world, const std::string& text) {
    c.send("s1", id, json{{"op", "world"}, {"world", world}}.dump());
    c.send("s1", id + 1, json{{"op", "query"}, {"text", text}}.dump());
    c.send("s1", id + 2, R"({"op":"accept","rank":0})");
    REQUIRE(c.wait_for(id + 2));
    CHECK(json::parse(c.answers[id + 2].second)["ok"] == true);
  };
  accept(robot1, 10, study_world_with_robot(10, 7), "visit room3");
  accept(robot2, 20, study_world_with_robot(3, 7), "move up");
  std::vector<std::pair<std::uint32_t, double>> got1, got2;  // (poses, first x)
  const auto record = [](auto& into) {
    return [&into](const nav_msgs_msg_dds__Path_& p) {
      into.emplace_back(p.poses_._length, p.poses_._buffer[0].pose_.position_.x_);
    };
  };
  CHECK(wait_until([&] {
    plans1.take(record(got1));
    plans2.take(record(got2));
    return !got1.empty() && !got2.empty();
  }));
  CHECK(got1 == std::vector<std::pair<std::uint32_t, double>>{{4, 10.0}});
  CHECK(got2 == std::vector<std::pair<std::uint32_t, double>>{{2, 3.0}});

  // A second session on robot1: plan_seq counts robot1's plans, whichever session made them.
  robot1.send("s2", 30, json{{"op", "world"}, {"world", study_world_with_robot(3, 7)}}.dump());
  robot1.send("s2", 31, R"({"op":"query","text":"move up"})");
  robot1.send("s2", 32, R"({"op":"accept","rank":0})");
  REQUIRE(robot1.wait_for(32));
  std::vector<std::uint64_t> seqs;
  CHECK(wait_until([&] {
    actions1.take([&](const flipper_msg_dds__ActionList_& a) { seqs.push_back(a.plan_seq_); });
    return !seqs.empty() && seqs.back() == 2;
  }));
  // Before this change every session started at 1: the two plans were both plan_seq 1.
  CHECK(seqs == std::vector<std::uint64_t>{1, 2});
  for (auto& n : nodes) {
    kill(n->pid(), SIGTERM);
    CHECK(n->finish() == 0);
  }
  std::filesystem::remove_all(dir);
}

namespace {

/// A participant's request writer or answer reader on the root namespace, with the session
/// protocol's QoS (dds_session_ends.hpp).
dds_entity_t session_endpoint(dds::Participant& p, const char* kind) {
  dds::Qos qos;
  dds_qset_reliability(qos.q, DDS_RELIABILITY_RELIABLE, DDS_SECS(10));
  dds_qset_history(qos.q, DDS_HISTORY_KEEP_ALL, DDS_LENGTH_UNLIMITED);
  const dds_entity_t topic =
      p.topic(&flipper_msg_dds__SessionLine__desc, dds::node_topic("", kind));
  const dds_entity_t e = std::string_view(kind) == "request"
                             ? dds_create_writer(p.handle(), topic, qos.q, nullptr)
                             : dds_create_reader(p.handle(), topic, qos.q, nullptr);
  REQUIRE(e > 0);
  return e;
}

}  // namespace

TEST_CASE("an answer waits for its requester's answer reader, within a bound", "[dds]") {
  // docs/ros2.md, "Requests over DDS": the answer topic is volatile, and discovery runs each way
  // on its own, so a client's first request can reach the node before the node's answer writer
  // has matched the client's answer reader. Made certain here: the client makes its answer
  // reader only once the node has acknowledged the request. The answer must still come.
  const int kDomain = test_domain();
  const auto dir = scratch_dir("late-reader");
  const std::string log = (dir / "node.log").string();
  testsupport::ChildProcess node({"/bin/sh", "-c",
                                  "log=$1; shift; exec \"$0\" dds \"$@\" 2>\"$log\"", flipper_bin(),
                                  log, "--set", "dds.domain=" + std::to_string(kDomain), "--set",
                                  "lexicon.path=" + (dir / "node.sqlite").string()});
  auto late = test_participant(kDomain);
  const dds_entity_t late_writer = session_endpoint(*late, "request");
  REQUIRE(writer_matched(late_writer));
  send_line(late_writer, "s1", 1, R"({"op":"user","name":"ana"})");
  REQUIRE(dds_wait_for_acks(late_writer, DDS_SECS(20)) == DDS_RETCODE_OK);  // the node has it
  std::this_thread::sleep_for(std::chrono::milliseconds(300));  // and, unwaited, answered it
  const dds_entity_t late_reader = session_endpoint(*late, "answer");
  std::map<std::uint64_t, std::string> answers;  // every answer on the topic, by request id
  const auto keep = [&](std::uint64_t id, const std::string&, std::string line) {
    answers[id] = std::move(line);
  };
  const auto answered = [&](std::uint64_t id) {  // within wait_until's 20 s
    return wait_until([&] {
      take_answers(late_reader, keep);
      return answers.count(id) > 0;
    });
  };
  REQUIRE(answered(1));
  CHECK(json::parse(answers[1])["name"] == "ana");

  SECTION("a requester with no answer reader holds its first answer back at most the bound") {
    // `mute` writes requests and never reads answers. The node waits for its reader up to
    // RequestNode::kAwaitReader (5 s) once, says so in its log, then answers at once: late's
    // requests, queued behind mute's, are answered (within wait_until's 20 s), and mute's second
    // request is not waited for.
    auto mute = test_participant(kDomain);
    const dds_entity_t mute_writer = session_endpoint(*mute, "request");
    REQUIRE(writer_matched(mute_writer));
    send_line(mute_writer, "m", 2, R"({"op":"state"})");
    REQUIRE(dds_wait_for_acks(mute_writer, DDS_SECS(20)) == DDS_RETCODE_OK);
    send_line(late_writer, "s1", 3, R"({"op":"state"})");
    REQUIRE(answered(3));
    send_line(mute_writer, "m", 4, R"({"op":"state"})");
    REQUIRE(dds_wait_for_acks(mute_writer, DDS_SECS(20)) == DDS_RETCODE_OK);
    send_line(late_writer, "s1", 5, R"({"op":"state"})");
    REQUIRE(answered(5));
    const std::string text = file_text(log);
    INFO(text);
    CHECK(text.find("flipper dds: answer 2: no answer reader of the requesting participant "
                    "matched within 5000 ms; written anyway, and its later answers at once") !=
          std::string::npos);
    CHECK(text.find("answer 4:") == std::string::npos);
    // The answer topic is one for every requester: late's reader has mute's answers too, so
    // answer 2 was written (after the wait), and answer 4 before 5.
    CHECK(answers.count(2) == 1);
    CHECK(answers.count(4) == 1);
  }
  kill(node.pid(), SIGTERM);
  CHECK(node.finish() == 0);
  std::filesystem::remove_all(dir);
}
