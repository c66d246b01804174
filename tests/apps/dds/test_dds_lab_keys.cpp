// Labs that own their keys (apps/dds/lab_keys.hpp; docs/ros2.md, "Labs that keep their keys"):
// a lab's request signed by the CA and installed at the lab, checked with the openssl command as
// the independent reader; lifetimes; renew; requests refused (tampered, bad names, weak keys) with
// exit 2 and the reason; a lab with its own key replicating with a site made by `add`.
#include <openssl/pem.h>
#include <openssl/x509.h>

#include "dds_test_support.hpp"
#include "flipper/dds/keystore.hpp"
#include "flipper/dds/lab_keys.hpp"
#include "flipper/dds/nav2_executor.hpp"
#include "flipper/dds/plan_frame.hpp"
#include "flipper/sdk/errors.hpp"

using namespace flipper;
using namespace flipper::ddstest;

namespace {

bool exists(const std::string& path) {
  return std::filesystem::exists(path);
}

// Days and seconds from notBefore to notAfter of a PEM certificate (ASN1_TIME_diff).
std::pair<int, int> lifetime(const std::string& pem_path) {
  const std::string pem = file_text(pem_path);
  BIO* bio = BIO_new_mem_buf(pem.data(), static_cast<int>(pem.size()));
  X509* cert = PEM_read_bio_X509(bio, nullptr, nullptr, nullptr);
  BIO_free(bio);
  REQUIRE(cert != nullptr);
  int days = -1, secs = -1;
  REQUIRE(ASN1_TIME_diff(&days, &secs, X509_get0_notBefore(cert), X509_get0_notAfter(cert)) == 1);
  X509_free(cert);
  return {days, secs};
}

// A CSR made by the openssl command (the independent maker) for `subject`, key `key_spec`.
std::string openssl_request(const std::filesystem::path& dir, const std::string& file,
                            const std::string& subject,
                            const std::string& key_spec = "ec -pkeyopt ec_paramgen_curve:P-256") {
  const std::string csr = (dir / file).string();
  shell_output("openssl req -new -newkey " + key_spec + " -nodes -keyout " + csr + ".key -subj '" +
               subject + "' -out " + csr);
  REQUIRE(exists(csr));
  return csr;
}

}  // namespace

TEST_CASE("a lab's request, signed at the CA, installs at the lab, the key never leaving it",
          "[dds][security][lab_keys]") {
  const auto dir = scratch_dir("lab-keys");
  const std::string ca = (dir / "ca").string(), lab = (dir / "lab").string();
  REQUIRE(security_command({"init", ca}).status == 0);
  const CommandRun req = security_command({"request", lab, "lab3"});
  INFO(req.out);
  REQUIRE(req.status == 0);
  const std::string key = lab + "/identities/lab3/key.pem", csr = lab + "/identities/lab3/lab3.csr";
  CHECK(shell_output("stat -c %a " + key + " " + lab + "/identities/lab3") == "600\n700\n");
  // The request as openssl reads it: its own signature verifies, its subject is CN=lab3.
  CHECK(shell_output("openssl req -in " + csr + " -noout -verify -subject -nameopt RFC2253 2>&1") ==
        "Certificate request self-signature verify OK\nsubject=CN=lab3\n");

  const CommandRun signed_ = security_command({"sign", ca, csr});
  INFO(signed_.out);
  REQUIRE(signed_.status == 0);
  const std::string outbox = ca + "/outbox/lab3";
  // The CA never had the key: not in its identity folder, not in the outbox.
  CHECK_FALSE(exists(ca + "/identities/lab3/key.pem"));
  CHECK_FALSE(exists(outbox + "/key.pem"));
  CHECK(shell_output("ls " + outbox) ==
        "ca.pem\ncert.pem\ngovernance.p7s\ngovernance_sign.p7s\npermissions.p7s\n");
  CHECK(shell_output("openssl verify -CAfile " + ca + "/ca.pem " + outbox + "/cert.pem") ==
        outbox + "/cert.pem: OK\n");
  // The certificate holds the lab's public key.
  CHECK(shell_output("openssl x509 -in " + outbox + "/cert.pem -noout -pubkey") ==
        shell_output("openssl pkey -in " + key + " -pubout"));
  // Default lifetime: 365 days from a day ago (clocks of other machines may lag).
  const auto [days, secs] = lifetime(outbox + "/cert.pem");
  CHECK(days == 366);
  CHECK(secs <= 1);  // the two times are set one call apart
  const std::string perms = file_text(ca + "/identities/lab3/permissions.xml");
  CHECK(perms.find("<subject_name>CN=lab3</subject_name>") != std::string::npos);
  CHECK(perms.find("<topic>rt/lab3/flipper/plan</topic>") != std::string::npos);

  const CommandRun installed = security_command({"install", lab, "lab3", outbox});
  INFO(installed.out);
  REQUIRE(installed.status == 0);
  for (const char* f : {"ca.pem", "governance.p7s", "governance_sign.p7s",
                        "identities/lab3/cert.pem", "identities/lab3/permissions.p7s"})
    CHECK(exists(lab + "/" + f));
  CHECK(shell_output("openssl smime -verify -in " + lab +
                     "/identities/lab3/permissions.p7s -CAfile " + lab +
                     "/ca.pem -text -out /dev/null 2>&1") == "Verification successful\n");
  CHECK_FALSE(exists(lab + "/private/ca.key"));

  // Renew: a new certificate (new serial) for the same key, the old one kept in previous/.
  const std::string serial1 =
      shell_output("openssl x509 -in " + outbox + "/cert.pem -noout -serial");
  const CommandRun renewed = security_command({"renew", ca, "lab3", "--days", "30"});
  INFO(renewed.out);
  REQUIRE(renewed.status == 0);
  const std::string serial2 =
      shell_output("openssl x509 -in " + outbox + "/cert.pem -noout -serial");
  CHECK(serial2 != serial1);
  CHECK(exists(ca + "/identities/lab3/previous/" + serial1.substr(7, serial1.size() - 8) + ".pem"));
  CHECK(shell_output("openssl x509 -in " + outbox + "/cert.pem -noout -pubkey") ==
        shell_output("openssl pkey -in " + key + " -pubout"));
  CHECK(lifetime(outbox + "/cert.pem").first == 31);
  const std::string renewed_perms = file_text(ca + "/identities/lab3/permissions.xml");
  CHECK(renewed_perms != perms);  // a new validity, the same grants
  CHECK(renewed_perms.substr(renewed_perms.find("<allow_rule>")) ==
        perms.substr(perms.find("<allow_rule>")));
  REQUIRE(security_command({"install", lab, "lab3", outbox}).status == 0);
  CHECK(shell_output("openssl x509 -in " + lab + "/identities/lab3/cert.pem -noout -serial") ==
        serial2);
  // `add` takes --days too; its default is the same year.
  REQUIRE(security_command({"add", ca, "robot1", "--days", "7"}).status == 0);
  CHECK(lifetime(ca + "/identities/robot1/cert.pem").first == 8);
  std::filesystem::remove_all(dir);
}

TEST_CASE("bad requests and installs are refused with exit 2 and the reason, writing nothing",
          "[dds][security][lab_keys]") {
  const auto dir = scratch_dir("lab-keys-bad");
  const std::string ca = (dir / "ca").string(), lab = (dir / "lab").string();
  REQUIRE(security_command({"init", ca}).status == 0);
  REQUIRE(security_command({"request", lab, "lab6"}).status == 0);
  const std::string csr = lab + "/identities/lab6/lab6.csr";
  const auto refused = [&](const std::vector<std::string>& args, const std::string& reason) {
    const CommandRun r = security_command(args);
    INFO(r.out);
    CHECK(r.status == 2);
    CHECK(r.out.find(reason) != std::string::npos);
  };

  // Tampered: the name in the signed content changed from lab6 to lab7 (same length, DER intact).
  const std::string tampered = (dir / "tampered.csr").string();
  shell_output("openssl req -in " + csr +
               " -outform DER | sed 's/lab6/lab7/' | openssl req -inform DER -out " + tampered);
  REQUIRE(shell_output("openssl req -in " + tampered + " -noout -subject") ==
          "subject=CN = lab7\n");
  refused({"sign", ca, tampered}, "[bad_request] the request '" + tampered +
                                      "' is not signed by its own key (its content was changed "
                                      "after it was made)");
  // Names: more than a CN; not a ROS 2 name token; a key Cyclone does not take; not a CSR.
  const std::string two = openssl_request(dir, "two.csr", "/O=acme/CN=lab4");
  refused({"sign", ca, two},
          "must name exactly one common name (CN=NAME); its subject is "
          "'/O=acme/CN=lab4'");
  refused({"sign", ca, openssl_request(dir, "dash.csr", "/CN=lab-4")},
          "[bad_config] the request's identity name 'lab-4' is not a ROS 2 name token");
  refused({"sign", ca, openssl_request(dir, "digit.csr", "/CN=4lab")},
          "the request's identity name '4lab' is not a ROS 2 name token");
  refused({"sign", ca, openssl_request(dir, "rsa.csr", "/CN=lab5", "rsa:1024")},
          "holds a 1024-bit RSA key; DDS Security takes EC P-256 or 2048-bit RSA keys");
  refused({"sign", ca, lab + "/identities/lab6/key.pem"}, "is not a certificate signing request");
  refused({"sign", ca, csr, "--days", "0"}, "--days: Value 0 not in range 1 to 3650");
  refused({"sign", ca, csr, "--days", "3651"}, "--days: Value 3651 not in range 1 to 3650");
  refused({"sign", lab, csr}, "no CA in '" + lab + "'");
  refused({"request", lab, "lab6"}, "identity 'lab6' has a key already");
  refused({"request", lab, "lab/6"}, "identity name 'lab/6' is not a ROS 2 name token");
  CHECK_FALSE(exists(ca + "/identities"));  // nothing signed so far
  // The boundary: a one-letter name (the shortest) and 3650 days (the longest) are taken.
  REQUIRE(security_command({"sign", ca, openssl_request(dir, "x.csr", "/CN=x"), "--days", "3650"})
              .status == 0);
  REQUIRE(security_command({"sign", ca, csr}).status == 0);
  refused({"sign", ca, csr}, "the keystore already has identity 'lab6'");

  // Installs: another lab's certificate; another CA's; for a name with no key here.
  refused({"install", lab, "lab6", ca + "/outbox/x"}, "cert.pem' is for 'x', not 'lab6'");
  const std::string other = (dir / "other").string();
  REQUIRE(security_command({"init", other}).status == 0);
  REQUIRE(security_command({"sign", other, csr}).status == 0);
  REQUIRE(security_command({"install", lab, "lab6", ca + "/outbox/lab6"}).status == 0);
  // A lab bound to one CA (its ca.pem) refuses another CA's certificate.
  refused({"install", lab, "lab6", other + "/outbox/lab6"},
          "'" + lab + "/ca.pem' is another CA's than '" + other + "/outbox/lab6/ca.pem'");
  const std::string renewed_key = (dir / "second").string();
  REQUIRE(security_command({"request", renewed_key, "lab6"}).status == 0);
  refused({"install", renewed_key, "lab6", ca + "/outbox/lab6"},
          "cert.pem' is not for this lab's key");
  refused({"install", lab, "nobody", ca + "/outbox/lab6"}, "identities/nobody/key.pem' is missing");
  refused({"renew", ca, "nobody"}, "the keystore has no identity 'nobody'");
  std::filesystem::remove_all(dir);
}

// The command line's range check (CLI11) stands in front of the library's own; a caller of the
// library (a tool, a test) meets the same bounds: 1 and 3,650 days are taken, 0 and 3,651 not.
TEST_CASE("the library refuses a lifetime outside [1, 3650] days as the command does",
          "[dds][security][lab_keys]") {
  const auto dir = scratch_dir("lab-keys-days");
  const std::string ca = (dir / "ca").string(), lab = (dir / "lab").string();
  REQUIRE(security_command({"init", ca}).status == 0);
  std::ostringstream out;
  const auto refusal = [&](const std::function<void()>& call) -> std::string {
    try {
      call();
    } catch (const sdk::Error& e) {
      CHECK(e.code() == "bad_request");
      return e.what();
    }
    return "(taken)";
  };
  const std::string csr = dds::request_identity(lab, "lab8", out);
  CHECK(refusal([&] { dds::sign_request(ca, csr, "site", {}, 0, out); }) ==
        "--days 0 is not in [1, 3650]");
  CHECK(refusal([&] { dds::sign_request(ca, csr, "site", {}, 3651, out); }) ==
        "--days 3651 is not in [1, 3650]");
  CHECK_FALSE(exists(ca + "/identities/lab8"));  // nothing written by a refusal
  CHECK(refusal([&] { dds::sign_request(ca, csr, "site", {}, 1, out); }) == "(taken)");
  CHECK(refusal([&] { dds::renew_identity(ca, "lab8", 0, out); }) ==
        "--days 0 is not in [1, 3650]");
  CHECK(refusal([&] { dds::renew_identity(ca, "lab8", 3650, out); }) == "(taken)");
  std::filesystem::remove_all(dir);
}

TEST_CASE("a lab with its own key joins and replicates with a site the CA made",
          "[dds][security][lab_keys]") {
  const auto dir = scratch_dir("lab-keys-join");
  const std::string ca = (dir / "ca").string(), lab = (dir / "lab").string();
  REQUIRE(security_command({"init", ca}).status == 0);
  REQUIRE(security_command({"add", ca, "lab1"}).status == 0);
  REQUIRE(security_command({"request", lab, "lab2"}).status == 0);
  REQUIRE(security_command({"sign", ca, lab + "/identities/lab2/lab2.csr"}).status == 0);
  REQUIRE(security_command({"install", lab, "lab2", ca + "/outbox/lab2"}).status == 0);

  const int domain = test_domain();
  Site lab1("lab1", dir, domain, {"--set", "dds.security.keystore=" + ca});
  Site lab2("lab2", dir, domain, {"--set", "dds.security.keystore=" + lab});
  for (Site* s : {&lab1, &lab2}) s->call({{"op", "user"}, {"name", "ana"}});
  REQUIRE(lab1.call({{"op", "define"},
                     {"head", "pick 3 items"},
                     {"body", {"repeat 3 times pick item"}}})["ok"] == true);
  REQUIRE(lab2.call({{"op", "define"},
                     {"head", "fetch 2 items"},
                     {"body", {"repeat 2 times pick item"}}})["ok"] == true);
  // Bound: discovery and the handshake between two secured participants take about 1 s.
  CHECK(wait_until([&] { return lab2.top("drop 2 items") == "{repeat 2 times {drop item }}"; },
                   std::chrono::seconds(60)));
  CHECK(wait_until([&] { return lab1.top("fetch 4 items") == "{repeat 4 times {pick item }}"; },
                   std::chrono::seconds(60)));
  for (Site* s : {&lab1, &lab2}) CHECK(s->child->finish() == 0);
  std::filesystem::remove_all(dir);
}

namespace {

// Whether a participant of identity `name` (keystore `ks`) may create a writer (`publish`) or a
// reader on `topic`: Cyclone's access control decides locally, from the signed permissions.
bool allowed(dds::Participant& p, const std::string& topic, bool publish) {
  dds::Qos qos;
  dds::ros_default_qos(qos);
  // A topic no rule names is refused at its creation; one the other direction names, at the
  // writer's or the reader's.
  const dds_entity_t t = dds_create_topic(p.handle(), &flipper_msg_dds__LexiconEvent__desc,
                                          topic.c_str(), nullptr, nullptr);
  const dds_entity_t e = t < 0     ? t
                         : publish ? dds_create_writer(p.handle(), t, qos.q, nullptr)
                                   : dds_create_reader(p.handle(), t, qos.q, nullptr);
  if (e > 0) return true;
  REQUIRE(e == DDS_RETCODE_NOT_ALLOWED_BY_SECURITY);  // nothing else may fail here
  return false;
}

}  // namespace

TEST_CASE("each role is granted only what it needs (docs/ros2.md, Roles)",
          "[dds][security][lab_keys]") {
  const auto dir = scratch_dir("roles");
  const std::string ca = (dir / "ca").string(), lab = (dir / "lab").string();
  REQUIRE(security_command({"init", ca}).status == 0);
  REQUIRE(security_command({"add", ca, "lab1"}).status == 0);  // site, the default
  REQUIRE(security_command({"add", ca, "robo", "--role", "robot", "--namespace", "r1"}).status ==
          0);
  REQUIRE(security_command({"add", ca, "op", "--role", "operator", "--namespace", "r1"}).status ==
          0);
  REQUIRE(security_command({"add", ca, "op_all", "--role", "operator"}).status == 0);
  // sign takes --role too: a lab's operator with its own key.
  REQUIRE(security_command({"request", lab, "op_lab"}).status == 0);
  REQUIRE(security_command({"sign", ca, lab + "/identities/op_lab/op_lab.csr", "--role", "operator",
                            "--namespace", "r2"})
              .status == 0);
  const CommandRun bad = security_command({"add", ca, "x", "--role", "admin"});
  CHECK(bad.status == 2);
  CHECK(bad.out.find("--role: admin not in {site,robot,operator}") != std::string::npos);

  const std::string lexicon = "rt/flipper/lexicon";
  const auto topic = [](const std::string& ns, const std::string& leaf) {
    return "rt/" + ns + "/flipper/" + leaf;
  };
  // {identity, topic, publish?, allowed?}: the table of docs/ros2.md, both sides of each line.
  struct Case {
    std::string identity, topic;
    bool publish, allowed;
  };
  const std::vector<Case> cases = {
      {"lab1", lexicon, true, true},
      {"lab1", lexicon, false, true},
      {"lab1", topic("lab1", "answer"), true, true},
      {"lab1", topic("lab1", "plan"), true, true},
      {"lab1", topic("lab1", "request"), false, true},
      {"lab1", topic("r1", "request"), true, false},  // a site sends no requests
      {"lab1", topic("r1", "answer"), false, false},  // nor reads other namespaces' answers
      {"lab1", topic("r1", "plan"), true, false},
      {"robo", topic("r1", "plan"), true, true},
      {"robo", topic("r1", "actions"), true, true},
      {"robo", topic("r1", "answer"), true, true},
      {"robo", topic("r1", "request"), false, true},
      {"robo", lexicon, true, false},  // a robot does not replicate the lexicon
      {"robo", lexicon, false, false},
      {"robo", topic("r1", "request"), true, false},
      {"robo", topic("robo", "plan"), true, false},  // only the namespaces named
      {"op", topic("r1", "request"), true, true},
      {"op", topic("r1", "answer"), false, true},
      {"op", topic("r1", "plan"), false, true},
      {"op", topic("r1", "actions"), false, true},
      {"op", topic("r2", "request"), true, false},
      {"op", topic("r2", "answer"), false, false},
      {"op", topic("r1", "answer"), true, false},  // it never answers
      {"op", lexicon, true, false},
      {"op", lexicon, false, false},
      {"op_all", topic("r2", "request"), true, true},
      {"op_all", topic("r9", "answer"), false, true},
      {"op_all", topic("r2", "answer"), true, false},
      {"op_all", lexicon, true, false},
      {"op_lab", topic("r2", "request"), true, true},
      {"op_lab", topic("r1", "request"), true, false},
  };
  ensure_loopback_env();
  dds::Transport t;
  t.xml = dds::loopback_xml();
  t.interfaces = {"lo"};
  t.source = "test";
  std::ostringstream sink;
  const int domain = test_domain();
  for (const std::string name : {"lab1", "robo", "op", "op_all", "op_lab"}) {
    const dds::Keystore ks{name == "op_lab" ? lab : ca};
    if (name == "op_lab")
      REQUIRE(security_command({"install", lab, "op_lab", ca + "/outbox/op_lab"}).status == 0);
    dds::Participant p(domain, t, sink, dds::security_properties(ks, name));
    for (const auto& c : cases) {
      if (c.identity != name) continue;
      INFO(c.identity << (c.publish ? " publishes " : " subscribes ") << c.topic);
      CHECK(allowed(p, c.topic, c.publish) == c.allowed);
    }
  }
  std::filesystem::remove_all(dir);
}

TEST_CASE("renew takes a certificate an hour before it expires, not an hour after",
          "[dds][security][lab_keys]") {
  const auto dir = scratch_dir("renew-expiry");
  const std::string ca = (dir / "ca").string(), lab = (dir / "lab").string();
  REQUIRE(security_command({"init", ca}).status == 0);
  REQUIRE(security_command({"request", lab, "lab9"}).status == 0);
  REQUIRE(security_command({"sign", ca, lab + "/identities/lab9/lab9.csr"}).status == 0);
  const std::string cert_path = ca + "/identities/lab9/cert.pem";
  // The CA's certificate of lab9 re-dated to end `hours` from now and signed again by the CA.
  const auto end_in = [&](long hours) {
    const std::string pem = file_text(cert_path), key_pem = file_text(ca + "/private/ca.key");
    BIO* bio = BIO_new_mem_buf(pem.data(), static_cast<int>(pem.size()));
    X509* cert = PEM_read_bio_X509(bio, nullptr, nullptr, nullptr);
    BIO_free(bio);
    bio = BIO_new_mem_buf(key_pem.data(), static_cast<int>(key_pem.size()));
    EVP_PKEY* key = PEM_read_bio_PrivateKey(bio, nullptr, nullptr, nullptr);
    BIO_free(bio);
    REQUIRE((cert != nullptr && key != nullptr));
    X509_gmtime_adj(X509_getm_notAfter(cert), hours * 3600);
    REQUIRE(X509_sign(cert, key, EVP_sha256()) > 0);
    FILE* out = std::fopen(cert_path.c_str(), "w");
    REQUIRE(out != nullptr);
    REQUIRE(PEM_write_X509(out, cert) == 1);
    std::fclose(out);
    X509_free(cert);
    EVP_PKEY_free(key);
  };
  end_in(-1);
  const CommandRun expired = security_command({"renew", ca, "lab9"});
  CHECK(expired.status == 2);
  CHECK(expired.out ==
        "flipper dds security renew: [bad_request] the certificate of 'lab9' has "
        "expired: the lab makes a new request (revoke 'lab9' first)\n");
  end_in(1);
  const CommandRun renewed = security_command({"renew", ca, "lab9"});
  INFO(renewed.out);
  CHECK(renewed.status == 0);
  CHECK(lifetime(cert_path).first == 366);
  std::filesystem::remove_all(dir);
}

TEST_CASE("only the robot role drives Nav2: its action topics are refused to the other roles",
          "[dds][security][lab_keys][nav2]") {
  const auto dir = scratch_dir("roles-nav2");
  const std::string ca = (dir / "ca").string();
  REQUIRE(security_command({"init", ca}).status == 0);
  REQUIRE(security_command({"add", ca, "lab1", "--namespace", "r1"}).status == 0);  // a site
  REQUIRE(security_command({"add", ca, "robo", "--role", "robot", "--namespace", "r1"}).status ==
          0);
  REQUIRE(security_command({"add", ca, "op", "--role", "operator", "--namespace", "r1"}).status ==
          0);
  // The names ROS 2 gives the action /r1/navigate_through_poses on DDS (docs/ros2/interfaces:
  // rq/...Request and rr/...Reply per service, rt/... for feedback and status), spelled out here
  // rather than taken from Flipper's code.
  const std::string a = "/r1/navigate_through_poses/_action/";
  const auto rq = [&](const char* s) { return "rq" + a + s + "Request"; };
  const auto rr = [&](const char* s) { return "rr" + a + s + "Reply"; };
  const auto rt = [&](const char* s) { return "rt" + a + s; };
  struct Case {
    std::string identity, topic;
    bool publish, allowed;
  };
  std::vector<Case> cases;
  for (const char* service : {"send_goal", "get_result", "cancel_goal"}) {
    // The robot's node is the action's client: it sends requests and reads replies...
    cases.push_back({"robo", rq(service), true, true});
    cases.push_back({"robo", rr(service), false, true});
    cases.push_back({"robo", rr(service), true, false});  // ...and never serves the action
    cases.push_back({"robo", rq(service), false, false});
    cases.push_back({"robo",
                     "rq/r2/navigate_through_poses/_action/" + std::string(service) + "Request",
                     true, false});                      // only its namespaces
    for (const std::string identity : {"lab1", "op"}) {  // nobody else sends goals or cancels
      cases.push_back({identity, rq(service), true, false});
      cases.push_back({identity, rr(service), false, false});
    }
  }
  for (const char* topic : {"feedback", "status"}) {
    cases.push_back({"robo", rt(topic), false, true});
    cases.push_back({"robo", rt(topic), true, false});
    cases.push_back({"op", rt(topic), false, true});  // an operator may watch the robot
    cases.push_back({"op", rt(topic), true, false});
    cases.push_back({"lab1", rt(topic), false, false});  // a site has no part in it
  }
  ensure_loopback_env();
  dds::Transport t;
  t.xml = dds::loopback_xml();
  t.interfaces = {"lo"};
  t.source = "test";
  std::ostringstream sink;
  const int domain = test_domain();
  for (const std::string name : {"lab1", "robo", "op"}) {
    auto p = std::make_shared<dds::Participant>(domain, t, sink,
                                                dds::security_properties(dds::Keystore{ca}, name));
    for (const auto& c : cases) {
      if (c.identity != name) continue;
      INFO(c.identity << (c.publish ? " publishes " : " subscribes ") << c.topic);
      CHECK(allowed(*p, c.topic, c.publish) == c.allowed);
    }
    // Flipper's own Nav2 client (nav2.execute) starts only under the robot's identity, and only
    // for the robot's namespace.
    const auto executor = [&](const std::string& ns) {
      dds::Nav2Executor::Options o;
      o.ns = ns;
      return std::make_shared<dds::Nav2Executor>(p, dds::PlanFrame(Eigen::Affine3d::Identity()), o,
                                                 sink);
    };
    INFO(name);
    if (name == "robo") {
      CHECK_NOTHROW(executor("r1"));
      CHECK_THROWS_WITH(executor("r2"), Catch::Contains("not allowed by security") ||
                                            Catch::Contains("creating DDS topic"));
    } else {
      CHECK_THROWS(executor("r1"));
    }
  }
  std::filesystem::remove_all(dir);
}
