// A certificate of another authority (docs/dds.md, "Security"): a site that makes its own CA and
// issues itself a certificate named `lab1` can sign events in lab1's name; Cyclone's handshake
// never sees that certificate when a participant of the project relays the event inside its own
// data, so EventVerifier is what refuses it. Checked on the verifier alone (with openssl as the
// independent reader of the certificates) and through a running site, which must log the reason.
#include "dds_test_support.hpp"
#include "flipper/dds/event_signature.hpp"
#include "flipper/dds/keystore.hpp"

using namespace flipper;
using namespace flipper::ddstest;

namespace {

int run(const std::vector<std::string>& args, std::string* out = nullptr) {
  testsupport::ChildProcess p(args);
  const std::string text = p.read_all();
  if (out != nullptr) *out = text;
  return p.finish();
}

std::string read_text(const std::string& path) {
  std::ifstream in(path);
  return {std::istreambuf_iterator<char>(in), {}};
}

std::uint32_t matched(dds_entity_t writer) {
  dds_publication_matched_status_t st{};
  dds_get_publication_matched_status(writer, &st);
  return st.current_count;
}

dds::LexiconEvent definition(const std::string& site, const std::string& head,
                             std::int64_t lamport) {
  dds::LexiconEvent e;
  e.site = site;
  e.version = 1;
  e.kind = "define";
  e.lamport = lamport;
  e.author = "ana";
  e.head = head;
  e.body = {"move right"};
  return e;
}

const std::string kForeignReason = "its certificate was not issued by the keystore's CA (";

}  // namespace

TEST_CASE("an event signed by a foreign CA's 'lab1' is refused, relayed or not, and logged",
          "[dds][security]") {
  const auto dir = scratch_dir("foreign-ca");
  const std::string ks = (dir / "ks").string(), foreign = (dir / "foreign").string();
  REQUIRE(run({flipper_bin(), "dds", "security", "init", ks}) == 0);
  for (const char* name : {"lab1", "lab2", "mallory"})
    REQUIRE(run({flipper_bin(), "dds", "security", "add", ks, name}) == 0);
  // The foreign authority: same tool, so the same CA subject ("Flipper DDS CA") and a
  // certificate whose subject is exactly lab1's.
  REQUIRE(run({flipper_bin(), "dds", "security", "init", foreign}) == 0);
  REQUIRE(run({flipper_bin(), "dds", "security", "add", foreign, "lab1"}) == 0);
  std::string out;
  run({"/bin/sh", "-c",
       "openssl x509 -noout -subject -nameopt RFC2253 -in " + foreign +
           "/identities/lab1/cert.pem; openssl verify -CAfile " + ks + "/ca.pem " + foreign +
           "/identities/lab1/cert.pem 2>&1"},
      &out);
  INFO(out);
  REQUIRE(out.rfind("subject=CN=lab1\n", 0) == 0);
  REQUIRE(out.find(": OK") == std::string::npos);  // openssl refuses it too

  dds::EventVerifier verifier(dds::Keystore{ks});
  dds::LexiconEvent genuine = definition("lab1", "lab task", 5);
  dds::EventSigner(dds::Keystore{ks}, "lab1").sign(genuine);
  CHECK_FALSE(verifier.why_not(genuine).has_value());  // the control: lab1's own certificate
  const dds::EventSigner impostor(dds::Keystore{foreign}, "lab1");
  dds::LexiconEvent forged = definition("lab1", "foreign task", 50);
  impostor.sign(forged);
  const auto why = verifier.why_not(forged);
  REQUIRE(why.has_value());
  CHECK(why->rfind(kForeignReason, 0) == 0);

  // Relayed: mallory, a participant of the project (so Cyclone's handshake admits it), writes
  // the forged event on the lexicon topic; site lab2 must refuse it and say why on stderr.
  const int domain = test_domain();
  ensure_loopback_env();
  const std::string log = (dir / "lab2.log").string();
  testsupport::ChildProcess lab2({"/bin/sh", "-c", "exec \"$0\" \"$@\" 2>" + log, flipper_bin(),
                                  "session", "--set", "lexicon.replication=dds", "--set",
                                  "lexicon.site=lab2", "--set",
                                  "lexicon.path=" + (dir / "lab2.sqlite").string(), "--set",
                                  "dds.domain=" + std::to_string(domain), "--set", "rewriter=null",
                                  "--set", "dds.security.keystore=" + ks});
  const auto call = [&](const json& request) {
    REQUIRE(lab2.write_line(request.dump()));
    const std::string line = lab2.read_line(std::chrono::seconds(30));
    REQUIRE_FALSE(line.empty());
    return json::parse(line);
  };
  const auto top = [&](const std::string& text) {
    const json a = call({{"op", "query"}, {"text", text}});
    return a["candidates"].empty() ? std::string()
                                   : a["candidates"][0]["formula"].get<std::string>();
  };
  call({{"op", "user"}, {"name", "bo"}});

  dds::Transport t;
  t.xml = dds::loopback_xml();
  t.interfaces = {"lo"};
  t.source = "test";
  std::ostringstream sink;
  auto mallory = std::make_shared<dds::Participant>(
      domain, t, sink, dds::security_properties(dds::Keystore{ks}, "mallory"));
  const dds_entity_t w = lexicon_writer(*mallory);
  // Bound: discovery between two secured participants on loopback takes about 1 s.
  REQUIRE(wait_until([&] { return matched(w) >= 1; }, std::chrono::seconds(60)));
  write_event(w, forged);
  // Then an event mallory may make, from the same reliable writer: once lab2 has applied it, the
  // forged one before it has been read and judged.
  dds::LexiconEvent own = definition("mallory", "mallory task", 51);
  dds::EventSigner(dds::Keystore{ks}, "mallory").sign(own);
  write_event(w, own);
  CHECK(
      wait_until([&] { return top("mallory task") == "{move right}"; }, std::chrono::seconds(60)));
  CHECK(top("foreign task").empty());
  const std::string logged = read_text(log);
  INFO(logged);
  CHECK(logged.find("flipper: lexicon replication: refused event lab1#1: " + kForeignReason) !=
        std::string::npos);
  CHECK(lab2.finish() == 0);
  std::filesystem::remove_all(dir);
}
