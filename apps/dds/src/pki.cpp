// The certificate-authority pieces of the keystore (pki.hpp), in the form Cyclone's plugins read
// (docs of cyclonedds-doc, security.html: "Creating certificates using OpenSSL"; `openssl smime
// -sign -text` for the documents).
#include "pki.hpp"

#include <openssl/pkcs7.h>
#include <openssl/rand.h>
#include <openssl/x509v3.h>
#include <sys/stat.h>

#include <ctime>
#include <fstream>
#include <sstream>

#include "flipper/dds/keystore.hpp"
#include "flipper/dds/names.hpp"

namespace flipper::dds::pki {

void refuse(const std::string& code, const std::string& message) {
  throw sdk::Error(code, message);
}

std::string read_text(const std::string& path) {
  std::ifstream in(path, std::ios::binary);
  if (!in) refuse(sdk::codes::kBadConfig, "cannot read '" + path + "'");
  std::ostringstream s;
  s << in.rdbuf();
  return s.str();
}

void write_text(const std::string& path, const std::string& text, bool secret, std::ostream& out) {
  {
    std::ofstream f(path, std::ios::binary | std::ios::trunc);
    if (!f) refuse("io_error", "cannot write '" + path + "'");
    if (secret && ::chmod(path.c_str(), 0600) != 0)
      refuse("io_error", "cannot make '" + path + "' private (mode 0600)");
    f << text;
    if (!f.flush()) refuse("io_error", "cannot write '" + path + "'");
  }
  out << "  " << path << "\n";
}

ossl::Key new_key() {
  ossl::Key key(EVP_EC_gen("P-256"));
  if (!key) ossl::fail("internal", "generating a P-256 key");
  return key;
}

std::string key_pem(EVP_PKEY* key) {
  ossl::Bio bio(BIO_new(BIO_s_mem()));
  if (!bio || PEM_write_bio_PrivateKey(bio.get(), key, nullptr, nullptr, 0, nullptr, nullptr) != 1)
    ossl::fail("internal", "writing a key");
  char* data = nullptr;
  const long n = BIO_get_mem_data(bio.get(), &data);
  return std::string(data, static_cast<std::size_t>(n));
}

ossl::Key read_key(const std::string& path) {
  const std::string pem = read_text(path);
  ossl::Bio bio(BIO_new_mem_buf(pem.data(), static_cast<int>(pem.size())));
  ossl::Key key(bio ? PEM_read_bio_PrivateKey(bio.get(), nullptr, nullptr, nullptr) : nullptr);
  if (!key) ossl::fail(sdk::codes::kBadConfig, "reading the key '" + path + "'");
  return key;
}

ossl::Cert read_cert(const std::string& path) {
  ossl::Cert cert = ossl::cert_from_pem(read_text(path));
  if (!cert) ossl::fail(sdk::codes::kBadConfig, "reading the certificate '" + path + "'");
  return cert;
}

namespace {

void add_extension(X509* cert, X509* issuer, int nid, const char* value) {
  X509V3_CTX ctx;
  X509V3_set_ctx_nodb(&ctx);
  X509V3_set_ctx(&ctx, issuer, cert, nullptr, nullptr, 0);
  X509_EXTENSION* ext = X509V3_EXT_conf_nid(nullptr, &ctx, nid, value);
  if (ext == nullptr || X509_add_ext(cert, ext, -1) != 1) ossl::fail("internal", "an extension");
  X509_EXTENSION_free(ext);
}

std::string iso_utc(std::chrono::system_clock::time_point t) {
  const std::time_t tt = std::chrono::system_clock::to_time_t(t);
  std::tm tm{};
  gmtime_r(&tt, &tm);
  char text[32];
  std::strftime(text, sizeof text, "%Y-%m-%dT%H:%M:%S", &tm);
  return text;
}

std::string validity_xml(long days) {
  const auto now = std::chrono::system_clock::now();
  return "<validity><not_before>" + iso_utc(now - std::chrono::hours(24)) +
         "</not_before><not_after>" + iso_utc(now + std::chrono::hours(24 * days)) +
         "</not_after></validity>";
}

std::string domains_xml() {
  return "<domains><id_range><min>0</min><max>" + std::to_string(kMaxSecureDomain) +
         "</max></id_range></domains>";
}

std::string topics_xml(const std::vector<std::string>& topics) {
  std::string out = "<topics>";
  for (const auto& t : topics) out += "<topic>" + t + "</topic>";
  return out + "</topics>";
}

}  // namespace

ossl::Cert make_cert(const std::string& subject_cn, EVP_PKEY* key, X509* issuer,
                     EVP_PKEY* issuer_key, long days) {
  ossl::Cert cert(X509_new());
  X509* c = cert.get();
  unsigned char serial[16];
  if (RAND_bytes(serial, sizeof serial) != 1) ossl::fail("internal", "a serial number");
  serial[0] &= 0x7f;  // positive
  serial[0] |= 0x01;  // and 16 bytes long, so serials print alike
  BIGNUM* bn = BN_bin2bn(serial, sizeof serial, nullptr);
  BN_to_ASN1_INTEGER(bn, X509_get_serialNumber(c));
  BN_free(bn);
  X509_set_version(c, 2);
  X509_gmtime_adj(X509_getm_notBefore(c), -24L * 3600);
  X509_time_adj_ex(X509_getm_notAfter(c), static_cast<int>(days), 0, nullptr);
  X509_NAME* name = X509_get_subject_name(c);
  X509_NAME_add_entry_by_txt(name, "CN", MBSTRING_UTF8,
                             reinterpret_cast<const unsigned char*>(subject_cn.c_str()), -1, -1, 0);
  X509_set_issuer_name(c, issuer != nullptr ? X509_get_subject_name(issuer) : name);
  X509_set_pubkey(c, key);
  X509* signer = issuer != nullptr ? issuer : c;
  add_extension(c, signer, NID_basic_constraints,
                issuer != nullptr ? "critical,CA:FALSE" : "critical,CA:TRUE");
  add_extension(c, signer, NID_key_usage,
                issuer != nullptr ? "critical,digitalSignature,keyAgreement"
                                  : "critical,keyCertSign,cRLSign,digitalSignature");
  add_extension(c, signer, NID_subject_key_identifier, "hash");
  if (issuer != nullptr) add_extension(c, signer, NID_authority_key_identifier, "keyid");
  if (X509_sign(c, issuer_key != nullptr ? issuer_key : key, EVP_sha256()) == 0)
    ossl::fail("internal", "signing a certificate");
  return cert;
}

std::string smime_signed(const std::string& document, X509* ca, EVP_PKEY* ca_key) {
  const int flags = PKCS7_DETACHED | PKCS7_TEXT | PKCS7_STREAM;
  ossl::Bio in(BIO_new_mem_buf(document.data(), static_cast<int>(document.size())));
  PKCS7* p7 = PKCS7_sign(ca, ca_key, nullptr, in.get(), flags);
  if (p7 == nullptr) ossl::fail("internal", "signing a document");
  ossl::Bio again(BIO_new_mem_buf(document.data(), static_cast<int>(document.size())));
  ossl::Bio out(BIO_new(BIO_s_mem()));
  const int ok = SMIME_write_PKCS7(out.get(), p7, again.get(), flags);
  PKCS7_free(p7);
  if (ok != 1) ossl::fail("internal", "writing a signed document");
  char* data = nullptr;
  const long n = BIO_get_mem_data(out.get(), &data);
  return std::string(data, static_cast<std::size_t>(n));
}

std::string governance_xml(bool encrypt) {
  // encrypt: SROS2's default governance (ros2 security create_keystore): RTPS messages,
  // discovery, liveliness, metadata and data encrypted (AES-GCM) and so authenticated; sign: the
  // same rules with every protection SIGN (GMAC: tamper-proof, readable on the wire).
  const std::string kind = encrypt ? "ENCRYPT" : "SIGN";
  return R"(<?xml version="1.0" encoding="UTF-8"?>
<dds xmlns:xsi="http://www.w3.org/2001/XMLSchema-instance" xsi:noNamespaceSchemaLocation="http://www.omg.org/spec/DDS-SECURITY/20170901/omg_shared_ca_governance.xsd">
  <domain_access_rules>
    <domain_rule>
      )" +
         domains_xml() +
         R"(
      <allow_unauthenticated_participants>false</allow_unauthenticated_participants>
      <enable_join_access_control>true</enable_join_access_control>
      <discovery_protection_kind>)" +
         kind + R"(</discovery_protection_kind>
      <liveliness_protection_kind>)" +
         kind + R"(</liveliness_protection_kind>
      <rtps_protection_kind>)" +
         kind + R"(</rtps_protection_kind>
      <topic_access_rules>
        <topic_rule>
          <topic_expression>*</topic_expression>
          <enable_discovery_protection>true</enable_discovery_protection>
          <enable_liveliness_protection>true</enable_liveliness_protection>
          <enable_read_access_control>true</enable_read_access_control>
          <enable_write_access_control>true</enable_write_access_control>
          <metadata_protection_kind>)" +
         kind + R"(</metadata_protection_kind>
          <data_protection_kind>)" +
         kind + R"(</data_protection_kind>
        </topic_rule>
      </topic_access_rules>
    </domain_rule>
  </domain_access_rules>
</dds>
)";
}

void check_role(const std::string& role) {
  if (role != "site" && role != "robot" && role != "operator")
    refuse(sdk::codes::kBadRequest, "--role '" + role + "' is not one of site, robot, operator");
}

std::string permissions_xml(const std::string& name, const std::string& role,
                            const std::vector<std::string>& namespaces, long days) {
  // The roles' grants (docs/ros2.md, "Roles"): a site replicates the lexicon and serves its
  // namespaces; a robot serves its namespaces only; an operator sends requests to the robots of
  // its namespaces (every robot when none is named) and reads their answers, plans and actions.
  check_role(role);
  std::vector<std::string> publish, subscribe;
  if (role == "site") {
    publish.emplace_back("rt/flipper/lexicon");
    subscribe.emplace_back("rt/flipper/lexicon");
  }
  const std::vector<std::string> served =
      !namespaces.empty() ? namespaces
                          : std::vector<std::string>{role == "operator" ? std::string("*") : name};
  for (const auto& ns : served) {
    const bool serves = role != "operator";
    for (const char* leaf : {"plan", "actions", "answer"})
      (serves ? publish : subscribe).push_back(node_topic(ns, leaf));
    (serves ? subscribe : publish).push_back(node_topic(ns, "request"));
    // Nav2's NavigateThroughPoses action (nav2.action's default name): a robot's node is its
    // client (nav2.execute), sending goals, results and cancels and reading the replies,
    // feedback and status; an operator may watch feedback and status; a site has no part in it.
    const std::string action = action_prefix(ns, std::string(keys::kNav2Action.def));
    if (role == "robot")
      for (const char* service : {"send_goal", "get_result", "cancel_goal"}) {
        publish.push_back("rq/" + action + service + "Request");
        subscribe.push_back("rr/" + action + service + "Reply");
      }
    if (role != "site")
      for (const char* topic : {"feedback", "status"}) subscribe.push_back("rt/" + action + topic);
  }
  return R"(<?xml version="1.0" encoding="UTF-8"?>
<dds xmlns:xsi="http://www.w3.org/2001/XMLSchema-instance" xsi:noNamespaceSchemaLocation="http://www.omg.org/spec/DDS-SECURITY/20170901/omg_shared_ca_permissions.xsd">
  <permissions>
    <grant name=")" +
         name + R"(">
      <subject_name>CN=)" +
         name + R"(</subject_name>
      )" +
         validity_xml(days) +
         R"(
      <allow_rule>
        )" +
         domains_xml() +
         R"(
        <publish>)" +
         topics_xml(publish) + R"(</publish>
        <subscribe>)" +
         topics_xml(subscribe) + R"(</subscribe>
      </allow_rule>
      <default>DENY</default>
    </grant>
  </permissions>
</dds>
)";
}

std::string with_validity(const std::string& permissions, long days) {
  const std::string open = "<validity>", close = "</validity>";
  const auto from = permissions.find(open);
  const auto to = permissions.find(close, from == std::string::npos ? 0 : from);
  if (from == std::string::npos || to == std::string::npos)
    refuse(sdk::codes::kBadConfig, "the permissions document has no <validity>");
  return permissions.substr(0, from) + validity_xml(days) + permissions.substr(to + close.size());
}

ossl::Crl read_crl(const std::string& path, X509* ca) {
  const std::string pem = read_text(path);
  ossl::Bio bio(BIO_new_mem_buf(pem.data(), static_cast<int>(pem.size())));
  ossl::Crl crl(bio ? PEM_read_bio_X509_CRL(bio.get(), nullptr, nullptr, nullptr) : nullptr);
  ERR_clear_error();
  if (!crl)
    refuse(sdk::codes::kBadConfig, "DDS Security: '" + path +
                                       "' is not a certificate revocation list (PEM, from "
                                       "`flipper dds security revoke`)");
  const int signed_by_ca = X509_CRL_verify(crl.get(), X509_get0_pubkey(ca));
  ERR_clear_error();
  if (signed_by_ca != 1)
    refuse(sdk::codes::kBadConfig,
           "DDS Security: the revocation list '" + path + "' is not signed by the keystore's CA");
  return crl;
}

std::string serial_hex(X509* cert) {
  BIGNUM* bn = ASN1_INTEGER_to_BN(X509_get_serialNumber(cert), nullptr);
  char* hex = bn != nullptr ? BN_bn2hex(bn) : nullptr;
  std::string out = hex != nullptr ? hex : "";
  ossl::free_memory(hex);
  BN_free(bn);
  return out;
}

}  // namespace flipper::dds::pki
