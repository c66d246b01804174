// DDS Security for sites and robots (apps/dds/keystore.hpp, event_signature.hpp): a keystore
// made by `flipper dds security`, checked with the openssl command as an independent reader;
// two secured sites replicate; a certified participant forging a deletion in another site's
// name is refused; a participant without a certificate cannot join; permissions keep one
// identity off another's robot topics.
#include <array>

#include "dds_test_support.hpp"
#include "flipper/dds/event_signature.hpp"
#include "flipper/dds/keystore.hpp"
#include "flipper/dds/lexicon_replicator.hpp"
#include "flipper/dds/names.hpp"
#include "flipper/msg/LexiconEvent.h"

using namespace flipper;
using namespace flipper::ddstest;

namespace {

int run(const std::vector<std::string>& args, std::string* out = nullptr) {
  testsupport::ChildProcess p(args);
  const std::string text = p.read_all();
  if (out != nullptr) *out = text;
  return p.finish();
}

std::string shell(const std::string& command) {
  std::string out;
  CHECK(run({"/bin/sh", "-c", command + " 2>&1"}, &out) == 0);
  return out;
}

std::shared_ptr<dds::Participant> secured(int domain, const std::string& keystore,
                                          const std::string& identity) {
  dds::Transport t;
  t.xml = dds::loopback_xml();
  t.interfaces = {"lo"};
  t.source = "test";
  static std::ostringstream sink;
  return std::make_shared<dds::Participant>(
      domain, t, sink, dds::security_properties(dds::Keystore{keystore}, identity));
}

std::uint32_t matched(dds_entity_t writer) {
  dds_publication_matched_status_t st{};
  dds_get_publication_matched_status(writer, &st);
  return st.current_count;
}

}  // namespace

TEST_CASE("flipper dds security makes a keystore openssl verifies", "[dds][security]") {
  const auto dir = scratch_dir("keystore");
  const std::string ks = (dir / "ks").string();
  const std::string flipper = flipper_bin();
  REQUIRE(run({flipper, "dds", "security", "init", ks}) == 0);
  REQUIRE(run({flipper, "dds", "security", "add", ks, "lab1"}) == 0);
  REQUIRE(run({flipper, "dds", "security", "add", ks, "robot_a", "--namespace", "robot_a",
               "--namespace", "robot_b"}) == 0);
  // Misuse exits 2 and names what is wrong; nothing is overwritten.
  CHECK(run({flipper, "dds", "security", "init", ks}) == 2);
  CHECK(run({flipper, "dds", "security", "add", ks, "lab1"}) == 2);
  CHECK(run({flipper, "dds", "security", "add", ks, "lab/1"}) == 2);
  CHECK(run({flipper, "dds", "security", "add", (dir / "none").string(), "lab1"}) == 2);

  const std::string ca = ks + "/ca.pem";
  CHECK(shell("openssl verify -CAfile " + ca + " " + ks + "/identities/lab1/cert.pem") ==
        ks + "/identities/lab1/cert.pem: OK\n");
  CHECK(shell("openssl x509 -noout -subject -nameopt RFC2253 -in " + ks +
              "/identities/lab1/cert.pem") == "subject=CN=lab1\n");
  CHECK(shell("openssl x509 -noout -subject -nameopt RFC2253 -in " + ca) ==
        "subject=CN=Flipper DDS CA\n");
  // The signed documents verify against the CA and carry exactly the plain documents.
  for (const std::string doc :
       {"governance", "governance_sign", "identities/robot_a/permissions"}) {
    const std::string verified = (dir / "verified.xml").string();
    CHECK(shell("openssl smime -verify -in " + ks + "/" + doc + ".p7s -CAfile " + ca +
                " -text -out " + verified) == "Verification successful\n");
    std::ifstream plain(ks + "/" + doc + ".xml"), got(verified);
    std::string signed_text(std::istreambuf_iterator<char>(got), {});
    std::erase(signed_text, '\r');  // S/MIME text is signed with CRLF line ends
    CHECK(signed_text == std::string(std::istreambuf_iterator<char>(plain), {}));
  }
  const std::string perms = shell("cat " + ks + "/identities/robot_a/permissions.xml");
  CHECK(perms.find("<subject_name>CN=robot_a</subject_name>") != std::string::npos);
  for (const char* topic : {"rt/robot_a/flipper/plan", "rt/robot_b/flipper/answer",
                            "rt/robot_b/flipper/request", "rt/flipper/lexicon"})
    CHECK(perms.find(std::string("<topic>") + topic + "</topic>") != std::string::npos);
  CHECK(perms.find("<topic>rt/robot_a/flipper/*</topic>") == std::string::npos);
  CHECK(shell("stat -c %a " + ks + "/private/ca.key " + ks + "/identities/lab1/key.pem") ==
        "600\n600\n");
  std::filesystem::remove_all(dir);
}

TEST_CASE("secured sites replicate while forged deletions and unsigned participants are refused",
          "[dds][security]") {
  const auto dir = scratch_dir("secured");
  const std::string ks = (dir / "ks").string();
  const int domain = test_domain();
  REQUIRE(run({flipper_bin(), "dds", "security", "init", ks}) == 0);
  for (const char* name : {"lab1", "lab2", "mallory"})
    REQUIRE(run({flipper_bin(), "dds", "security", "add", ks, name}) == 0);
  const std::vector<std::string> secure = {"--set", "dds.security.keystore=" + ks};

  Site lab1("lab1", dir, domain, secure), lab2("lab2", dir, domain, secure);
  for (Site* s : {&lab1, &lab2}) s->call({{"op", "user"}, {"name", "ana"}});
  REQUIRE(lab1.call({{"op", "define"},
                     {"head", "pick 3 items"},
                     {"body", {"repeat 3 times pick item"}}})["ok"] == true);
  const std::string drop2 = "{repeat 2 times {drop item }}";
  REQUIRE(wait_until([&] { return lab2.top("drop 2 items") == drop2; }, std::chrono::seconds(60)));
  const auto lab1_rules = rule_shapes(lab1);
  REQUIRE(rule_shapes(lab2) == lab1_rules);

  // A participant with no certificate, on the same domain: a flipper site claiming to be lab1.
  std::filesystem::create_directories(dir / "unsigned");
  Site unsigned_site("lab1", dir / "unsigned", domain);
  unsigned_site.call({{"op", "user"}, {"name", "eve"}});
  REQUIRE(unsigned_site.call(
              {{"op", "define"}, {"head", "unsigned task"}, {"body", {"move left"}}})["ok"] ==
          true);

  // mallory holds a certificate of the project: it may publish on the lexicon topic, but every
  // event in lab1's name is refused, however it is dressed up.
  auto mallory = secured(domain, ks, "mallory");
  const dds_entity_t w = lexicon_writer(*mallory);
  REQUIRE(wait_until([&] { return matched(w) >= 2; }, std::chrono::seconds(60)));
  dds::EventSigner mallory_key(dds::Keystore{ks}, "mallory");
  dds::LexiconEvent forged;
  forged.site = "lab1";
  forged.version = 2;
  forged.kind = "delete";
  forged.lamport = 99;
  forged.author = "ana";
  forged.target_site = "lab1";
  forged.target_version = 1;
  write_event(w, forged);  // unsigned
  dds::LexiconEvent signed_by_mallory = forged;
  signed_by_mallory.version = 3;
  mallory_key.sign(signed_by_mallory);  // mallory's certificate, claiming lab1
  write_event(w, signed_by_mallory);
  dds::LexiconEvent borrowed = signed_by_mallory;  // lab1's certificate, mallory's signature
  borrowed.version = 4;
  std::ifstream lab1_cert(ks + "/identities/lab1/cert.pem");
  borrowed.certificate = std::string(std::istreambuf_iterator<char>(lab1_cert), {});
  write_event(w, borrowed);
  // Then an event mallory may make, from the same writer: once it is applied at both sites, the
  // forged ones before it (reliable, in order) have been read and refused.
  dds::LexiconEvent own;
  own.site = "mallory";
  own.version = 1;
  own.kind = "define";
  own.lamport = 100;
  own.author = "mal";
  own.head = "mallory task";
  own.body = {"move right"};
  mallory_key.sign(own);
  write_event(w, own);
  for (Site* s : {&lab1, &lab2})
    CHECK(wait_until([&] { return s->top("mallory task") == "{move right}"; },
                     std::chrono::seconds(60)));
  for (Site* s : {&lab1, &lab2}) {
    CHECK(s->top("drop 2 items") == drop2);  // lab1's rules are still there
    CHECK(s->top("unsigned task").empty());  // the unsigned site never got in
  }
  CHECK(unsigned_site.rules().size() == 1);  // its own rule only: it received nothing
  CHECK(unsigned_site.top("drop 2 items") != drop2);

  // Permissions: mallory may serve its own robot's topics, not lab1's.
  dds::Qos qos;
  dds::ros_default_qos(qos);
  const auto writer_on = [&](const std::string& topic) {  // a topic no rule names: refused
    const dds_entity_t t = dds_create_topic(mallory->handle(), &flipper_msg_dds__LexiconEvent__desc,
                                            topic.c_str(), nullptr, nullptr);
    return t < 0 ? t : dds_create_writer(mallory->handle(), t, qos.q, nullptr);
  };
  CHECK(writer_on(dds::node_topic("mallory", "answer")) > 0);
  CHECK(writer_on(dds::node_topic("lab1", "answer")) == DDS_RETCODE_NOT_ALLOWED_BY_SECURITY);
  CHECK(writer_on(dds::node_topic("lab1", "plan")) == DDS_RETCODE_NOT_ALLOWED_BY_SECURITY);

  for (Site* s : {&lab1, &lab2, &unsigned_site}) CHECK(s->child->finish() == 0);
  std::filesystem::remove_all(dir);
}

TEST_CASE("security settings are checked before anything starts", "[dds][security]") {
  const auto dir = scratch_dir("secbad");
  const std::string ks = (dir / "ks").string();
  REQUIRE(run({flipper_bin(), "dds", "security", "init", ks}) == 0);
  REQUIRE(run({flipper_bin(), "dds", "security", "add", ks, "lab1"}) == 0);
  const auto session = [&](std::vector<std::string> sets) {
    std::vector<std::string> args = {
        flipper_bin(),           "session", "--set",
        "lexicon.path=:memory:", "--set",   "dds.security.keystore=" + ks};
    for (auto& s : sets) args.insert(args.end(), {"--set", s});
    testsupport::ChildProcess p(args);
    return p.finish();
  };
  // A site is its certificate: no identity for lab2 in the keystore, or another identity.
  CHECK(session({"lexicon.replication=dds", "lexicon.site=lab2"}) == 2);
  CHECK(session({"lexicon.replication=dds", "lexicon.site=lab2", "dds.security.identity=lab1"}) ==
        2);
  // Plans need a namespace the permissions name; domains above 230 are not covered.
  CHECK(session({"publish.plans=dds", "dds.security.identity=lab1"}) == 2);
  CHECK(session({"lexicon.replication=dds", "lexicon.site=lab1", "dds.domain=231"}) == 2);
  std::filesystem::remove_all(dir);
}
