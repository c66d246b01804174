// SROS2 keystores (docs/ros2.md, "SROS2 keystores"): Flipper reads an enclave laid out as
// `ros2 security create_keystore` / `create_enclave` write it
// (enclaves/<name>/{identity_ca.cert.pem, permissions_ca.cert.pem, governance.p7s, cert.pem,
// key.pem, permissions.p7s}), here made by the openssl command line (the independent maker: ROS 2
// is not installed), with SROS2's default governance (everything ENCRYPT); a `flipper dds` node in
// one enclave answers a participant of another. `export` writes Flipper's identities as enclaves;
// dds.security.protection: sign uses the keystore's governance_sign.p7s. Bad enclave settings exit
// 2 with the reason.
#include <signal.h>
#include <sys/wait.h>
#include <unistd.h>

#include "dds_test_support.hpp"
#include "flipper/dds/keystore.hpp"
#include "flipper/dds/names.hpp"
#include "flipper/msg/SessionLine.h"

using namespace flipper;
using namespace flipper::ddstest;

namespace {

void sh(const std::string& command) {
  const CommandRun r = run_command({"/bin/sh", "-c", "set -e; " + command});
  INFO(command << "\n" << r.out);
  REQUIRE(r.status == 0);
}

std::string topics(const std::vector<std::string>& names) {
  std::string out = "<topics>";
  for (const auto& n : names) out += "<topic>" + n + "</topic>";
  return out + "</topics>";
}

// An SROS2 keystore at `ks` with enclaves /lab1/robot1 (serves rt/robot1/flipper/...) and
// /lab1/operator (sends it requests), made with openssl as SROS2 makes them: a P-256 CA
// (public/ca.cert.pem, private/ca.key.pem), ENCRYPT governance, per enclave a P-256 key
// (PKCS#8), a certificate CN=<enclave> and permissions for subject CN=<enclave>, all
// S/MIME-signed by the CA (openssl smime -sign -text).
void make_sros2_keystore(const std::string& ks) {
  sh("mkdir -p " + ks + "/public " + ks + "/private " + ks + "/enclaves/lab1/robot1 " + ks +
     "/enclaves/lab1/operator");
  sh("cd " + ks +
     " && openssl genpkey -algorithm EC -pkeyopt ec_paramgen_curve:P-256 -out private/ca.key.pem"
     " && openssl req -new -x509 -key private/ca.key.pem -subj /CN=sros2testCA -days 30"
     " -out public/ca.cert.pem");
  std::ofstream(ks + "/enclaves/governance.xml") << R"(<?xml version="1.0" encoding="UTF-8"?>
<dds xmlns:xsi="http://www.w3.org/2001/XMLSchema-instance" xsi:noNamespaceSchemaLocation="http://www.omg.org/spec/DDS-SECURITY/20170901/omg_shared_ca_governance.xsd">
  <domain_access_rules>
    <domain_rule>
      <domains><id_range><min>0</min><max>230</max></id_range></domains>
      <allow_unauthenticated_participants>false</allow_unauthenticated_participants>
      <enable_join_access_control>true</enable_join_access_control>
      <discovery_protection_kind>ENCRYPT</discovery_protection_kind>
      <liveliness_protection_kind>ENCRYPT</liveliness_protection_kind>
      <rtps_protection_kind>ENCRYPT</rtps_protection_kind>
      <topic_access_rules>
        <topic_rule>
          <topic_expression>*</topic_expression>
          <enable_discovery_protection>true</enable_discovery_protection>
          <enable_liveliness_protection>true</enable_liveliness_protection>
          <enable_read_access_control>true</enable_read_access_control>
          <enable_write_access_control>true</enable_write_access_control>
          <metadata_protection_kind>ENCRYPT</metadata_protection_kind>
          <data_protection_kind>ENCRYPT</data_protection_kind>
        </topic_rule>
      </topic_access_rules>
    </domain_rule>
  </domain_access_rules>
</dds>
)";
  const std::string sign = " -signer public/ca.cert.pem -inkey private/ca.key.pem";
  sh("cd " + ks + " && openssl smime -sign -text -in enclaves/governance.xml" + sign +
     " -out enclaves/governance.p7s");
  const std::string rt = "rt/robot1/flipper/";
  for (const std::string who : {"robot1", "operator"}) {
    const std::string dir = "enclaves/lab1/" + who;
    const std::vector<std::string> served = {rt + "answer", rt + "plan", rt + "actions"};
    const bool robot = who == "robot1";
    std::ofstream(ks + "/" + dir + "/permissions.xml") << R"(<?xml version="1.0" encoding="UTF-8"?>
<dds xmlns:xsi="http://www.w3.org/2001/XMLSchema-instance" xsi:noNamespaceSchemaLocation="http://www.omg.org/spec/DDS-SECURITY/20170901/omg_shared_ca_permissions.xsd">
  <permissions>
    <grant name="/lab1/)" << who << R"(">
      <subject_name>CN=/lab1/)" << who << R"(</subject_name>
      <validity><not_before>2024-01-01T00:00:00</not_before><not_after>2036-01-01T00:00:00</not_after></validity>
      <allow_rule>
        <domains><id_range><min>0</min><max>230</max></id_range></domains>
        <publish>)" << topics(robot ? served : std::vector<std::string>{rt + "request"})
                                                       << R"(</publish>
        <subscribe>)" << topics(robot ? std::vector<std::string>{rt + "request"} : served)
                                                       << R"(</subscribe>
      </allow_rule>
      <default>DENY</default>
    </grant>
  </permissions>
</dds>
)";
    // The subject CN=/lab1/<who> ('/' in a -subj value would start a new attribute).
    std::ofstream(ks + "/" + dir + "/req.cnf")
        << "[req]\nprompt=no\ndistinguished_name=dn\n[dn]\nCN=/lab1/" << who << "\n";
    sh("cd " + ks + " && cp public/ca.cert.pem " + dir + "/identity_ca.cert.pem && cp " +
       "public/ca.cert.pem " + dir + "/permissions_ca.cert.pem && cp enclaves/governance.p7s " +
       dir + "/ && openssl genpkey -algorithm EC -pkeyopt ec_paramgen_curve:P-256 -out " + dir +
       "/key.pem && openssl req -new -key " + dir + "/key.pem -config " + dir + "/req.cnf -out " +
       dir + "/req.pem && openssl x509 -req -in " + dir +
       "/req.pem -CA public/ca.cert.pem -CAkey private/ca.key.pem -CAcreateserial -days 30" +
       " -out " + dir + "/cert.pem && openssl smime -sign -text -in " + dir + "/permissions.xml" +
       sign + " -out " + dir + "/permissions.p7s");
    // The subject as SROS2 writes it, read back by the openssl command.
    CHECK(shell_output("openssl x509 -noout -subject -nameopt RFC2253 -in " + ks + "/" + dir +
                       "/cert.pem") == "subject=CN=/lab1/" + who + "\n");
  }
}

// `flipper dds ARGS...` on `domain`, its stderr into `log`; killed (SIGTERM) when it goes.
struct Node {
  pid_t pid = -1;
  std::filesystem::path log;
  Node(std::vector<std::string> args, int domain, std::filesystem::path log_file)
      : log(std::move(log_file)) {
    args.insert(args.begin(),
                {flipper_bin(), "dds", "--set", "dds.domain=" + std::to_string(domain)});
    std::vector<char*> argv;
    for (auto& a : args) argv.push_back(a.data());
    argv.push_back(nullptr);
    const std::string log_path = log.string();
    pid = fork();
    REQUIRE(pid >= 0);
    if (pid == 0) {
      if (std::freopen(log_path.c_str(), "w", stderr) == nullptr) _exit(126);
      execv(argv[0], argv.data());
      _exit(127);
    }
  }
  std::string text() const { return file_text(log.string()); }
  bool serving() const {
    return wait_until([&] { return text().find("serving") != std::string::npos; },
                      std::chrono::seconds(60));
  }
  int stop() {
    int status = 0;
    kill(pid, SIGTERM);
    if (!wait_until([&] { return waitpid(pid, &status, WNOHANG) == pid; },
                    std::chrono::seconds(30))) {
      kill(pid, SIGKILL);
      waitpid(pid, &status, 0);
    }
    pid = -1;
    return WIFEXITED(status) ? WEXITSTATUS(status) : -1;
  }
  ~Node() {
    if (pid > 0) stop();
  }
  Node(const Node&) = delete;
  Node& operator=(const Node&) = delete;
};

// A secured requester of namespace `ns`: sends `line`, returns the answer line ("" when none
// came within 60 s: discovery and the handshake take about a second).
std::string ask(const std::vector<std::pair<std::string, std::string>>& security, int domain,
                const std::string& ns, const std::string& line,
                std::chrono::seconds wait = std::chrono::seconds(60)) {
  ensure_loopback_env();
  dds::Transport t;
  t.xml = dds::loopback_xml();
  t.interfaces = {"lo"};
  t.source = "test";
  std::ostringstream sink;
  dds::Participant p(domain, t, sink, security);
  dds::Qos qos;
  dds_qset_reliability(qos.q, DDS_RELIABILITY_RELIABLE, DDS_SECS(10));
  dds_qset_history(qos.q, DDS_HISTORY_KEEP_ALL, DDS_LENGTH_UNLIMITED);
  const dds_entity_t writer = dds_create_writer(
      p.handle(), p.topic(&flipper_msg_dds__SessionLine__desc, dds::node_topic(ns, "request")),
      qos.q, nullptr);
  const dds_entity_t reader = dds_create_reader(
      p.handle(), p.topic(&flipper_msg_dds__SessionLine__desc, dds::node_topic(ns, "answer")),
      qos.q, nullptr);
  REQUIRE(writer > 0);
  REQUIRE(reader > 0);
  const bool matched = wait_until(
      [&] {
        dds_publication_matched_status_t st;
        return dds_get_publication_matched_status(writer, &st) == 0 && st.current_count > 0;
      },
      wait);
  if (!matched) return "";
  flipper_msg_dds__SessionLine_ s{};
  s.session_ = const_cast<char*>("sros2");
  s.request_id_ = 7;
  s.line_ = const_cast<char*>(line.c_str());
  REQUIRE(dds_write(writer, &s) == DDS_RETCODE_OK);
  std::string answer;
  wait_until(
      [&] {
        void* samples[1] = {nullptr};
        dds_sample_info_t info;
        while (answer.empty() && dds_take(reader, samples, &info, 1, 1) > 0) {
          const auto* a = static_cast<const flipper_msg_dds__SessionLine_*>(samples[0]);
          if (info.valid_data && a->request_id_ == 7) answer = a->line_;
          dds_return_loan(reader, samples, 1);
        }
        return !answer.empty();
      },
      std::chrono::seconds(60));
  return answer;
}

}  // namespace

TEST_CASE("a flipper dds node in an SROS2 enclave made by openssl answers another enclave",
          "[dds][security][sros2]") {
  const auto dir = scratch_dir("sros2");
  const std::string ks = (dir / "keystore").string();
  make_sros2_keystore(ks);
  const int domain = test_domain();
  Node node({"--set", "dds.security.keystore=" + ks, "--set", "dds.security.enclave=/lab1/robot1",
             "--set", "dds.namespace=robot1"},
            domain, dir / "node.log");
  INFO(node.text());
  REQUIRE(node.serving());
  CHECK(node.text().find("DDS Security on") != std::string::npos);
  const dds::Keystore operator_enclave{ks, {}, "/lab1/operator"};
  const std::string answer = ask(dds::security_properties(operator_enclave, "operator"), domain,
                                 "robot1", R"({"op":"user","name":"ana"})");
  INFO(node.text());
  REQUIRE_FALSE(answer.empty());
  const json a = json::parse(answer);
  CHECK(a["ok"] == true);
  CHECK(a["op"] == "user");
  CHECK(node.stop() == 0);
  std::filesystem::remove_all(dir);
}

TEST_CASE("flipper's identities exported as SROS2 enclaves, and protection sign, talk",
          "[dds][security][sros2]") {
  const auto dir = scratch_dir("sros2-export");
  const std::string ca = (dir / "ca").string(), ks = (dir / "ros2").string();
  REQUIRE(security_command({"init", ca}).status == 0);
  REQUIRE(security_command({"add", ca, "robo", "--role", "robot", "--namespace", "r1"}).status ==
          0);
  REQUIRE(security_command({"add", ca, "op", "--role", "operator", "--namespace", "r1"}).status ==
          0);
  const CommandRun exported =
      security_command({"export", ca, "robo", ks, "--enclave", "/lab1/robo"});
  INFO(exported.out);
  REQUIRE(exported.status == 0);
  const std::string enclave = ks + "/enclaves/lab1/robo/";
  for (const char* f : {"identity_ca.cert.pem", "permissions_ca.cert.pem", "governance.p7s",
                        "cert.pem", "key.pem", "permissions.p7s"})
    CHECK(std::filesystem::is_regular_file(enclave + f));
  CHECK(file_text(enclave + "key.pem") == file_text(ca + "/identities/robo/key.pem"));
  CHECK((std::filesystem::status(enclave + "key.pem").permissions() &
         std::filesystem::perms::group_all) == std::filesystem::perms::none);
  // The governance documents init writes: SROS2's ENCRYPT (default) and SIGN, both verified
  // against the CA by the openssl command.
  const std::string verify = "openssl smime -verify -text -CAfile " + ca + "/ca.pem -in ";
  const std::string encrypt_doc = shell_output(verify + ca + "/governance.p7s 2>/dev/null");
  const std::string sign_doc = shell_output(verify + ca + "/governance_sign.p7s 2>/dev/null");
  CHECK(encrypt_doc.find("<rtps_protection_kind>ENCRYPT</rtps_protection_kind>") !=
        std::string::npos);
  CHECK(encrypt_doc.find("<data_protection_kind>ENCRYPT</data_protection_kind>") !=
        std::string::npos);
  CHECK(encrypt_doc.find("SIGN") == std::string::npos);
  CHECK(sign_doc.find("<rtps_protection_kind>SIGN</rtps_protection_kind>") != std::string::npos);
  CHECK(sign_doc.find("<data_protection_kind>SIGN</data_protection_kind>") != std::string::npos);
  CHECK(sign_doc.find("ENCRYPT") == std::string::npos);
  const int domain = test_domain();
  {
    // The exported enclave serving; an operator of Flipper's own layout asking.
    Node node({"--set", "dds.security.keystore=" + ks, "--set", "dds.security.enclave=/lab1/robo",
               "--set", "dds.namespace=r1"},
              domain, dir / "enclave.log");
    REQUIRE(node.serving());
    const std::string answer = ask(dds::security_properties(dds::Keystore{ca}, "op"), domain, "r1",
                                   R"({"op":"user","name":"ana"})");
    INFO(node.text());
    CHECK(json::parse(answer.empty() ? "{}" : answer)["op"] == "user");
  }
  {
    // Protection sign on both sides.
    Node node({"--set", "dds.security.keystore=" + ca, "--set", "dds.security.identity=robo",
               "--set", "dds.namespace=r1", "--set", "dds.security.protection=sign"},
              domain, dir / "sign.log");
    REQUIRE(node.serving());
    dds::Keystore op{ca};
    op.sign_only = true;
    const auto props = dds::security_properties(op, "op");
    CHECK(std::find(props.begin(), props.end(),
                    std::pair<std::string, std::string>(
                        "dds.sec.access.governance",
                        "file:" + std::filesystem::absolute(ca + "/governance_sign.p7s")
                                      .lexically_normal()
                                      .string())) != props.end());
    const std::string answer = ask(props, domain, "r1", R"({"op":"user","name":"ana"})");
    INFO(node.text());
    CHECK(json::parse(answer.empty() ? "{}" : answer)["op"] == "user");
    // A participant of the same CA with the other governance (encrypt) never matches it:
    // watched for 5 s, while the matching one above took about a second.
    const auto start = std::chrono::steady_clock::now();
    CHECK(ask(dds::security_properties(dds::Keystore{ca}, "op"), domain, "r1",
              R"({"op":"user","name":"ana"})", std::chrono::seconds(5))
              .empty());
    CHECK(std::chrono::steady_clock::now() - start < std::chrono::seconds(15));
  }
  std::filesystem::remove_all(dir);
}

TEST_CASE("bad SROS2 settings are refused before anything starts, with exit 2 and the reason",
          "[dds][security][sros2]") {
  const auto dir = scratch_dir("sros2-bad");
  const std::string ca = (dir / "ca").string();
  REQUIRE(security_command({"init", ca}).status == 0);
  REQUIRE(security_command({"add", ca, "robo", "--role", "robot"}).status == 0);
  const auto refused = [&](const std::vector<std::string>& sets, const std::string& reason) {
    std::vector<std::string> args = {flipper_bin(),        "dds",   "--set",
                                     "dds.namespace=robo", "--set", "dds.security.keystore=" + ca};
    for (const auto& s : sets) args.insert(args.end(), {"--set", s});
    const auto start = std::chrono::steady_clock::now();
    const CommandRun r = run_command(args);
    INFO(r.out);
    CHECK(r.status == 2);
    CHECK(r.out.find(reason) != std::string::npos);
    // Refused at the config check: no participant, no discovery wait.
    CHECK(std::chrono::steady_clock::now() - start < std::chrono::seconds(10));
  };
  refused({"dds.security.enclave=lab1/robo"},
          "dds.security.enclave 'lab1/robo' is not an SROS2 enclave name");
  refused({"dds.security.enclave=/lab1//robo"}, "has an empty part");
  refused({"dds.security.enclave=/lab1/ro-bo"}, "is not a ROS 2 name token");
  refused({"dds.security.enclave=/lab1/robo"},
          "enclaves/lab1/robo/identity_ca.cert.pem' is missing (an SROS2 enclave: ros2 security "
          "create_enclave");
  refused({"dds.security.enclave=/lab1/robo", "dds.security.protection=sign"},
          "dds.security.protection: sign is for Flipper's keystore layout");
  refused({"dds.security.protection=none"}, "dds.security.protection");
  std::filesystem::remove_all(dir);
}
