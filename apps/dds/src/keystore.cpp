// The DDS Security keystore (keystore.hpp): keys, certificates and S/MIME-signed documents made
// with libcrypto, in the form Cyclone's plugins read (docs of cyclonedds-doc, security.html:
// "Creating certificates using OpenSSL"; `openssl smime -sign -text` for the documents).
#include "flipper/dds/keystore.hpp"

#include <dlfcn.h>
#include <openssl/pkcs7.h>
#include <openssl/rand.h>
#include <openssl/x509v3.h>
#include <sys/stat.h>

#include <dds/dds.h>
#include <chrono>
#include <ctime>
#include <filesystem>
#include <fstream>
#include <ostream>
#include <sstream>

#include "flipper/dds/config_keys.hpp"
#include "flipper/dds/names.hpp"
#include "flipper/kernel/config.hpp"
#include "flipper/naturalization/config_keys.hpp"
#include "openssl_util.hpp"

namespace flipper::dds {
namespace {

namespace fs = std::filesystem;
constexpr long kValidDays = 3650;

[[noreturn]] void refuse(const std::string& code, const std::string& message) {
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
    f << text;
    if (!f.flush()) refuse("io_error", "cannot write '" + path + "'");
  }
  if (secret) ::chmod(path.c_str(), 0600);
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

void add_extension(X509* cert, X509* issuer, int nid, const char* value) {
  X509V3_CTX ctx;
  X509V3_set_ctx_nodb(&ctx);
  X509V3_set_ctx(&ctx, issuer, cert, nullptr, nullptr, 0);
  X509_EXTENSION* ext = X509V3_EXT_conf_nid(nullptr, &ctx, nid, value);
  if (ext == nullptr || X509_add_ext(cert, ext, -1) != 1) ossl::fail("internal", "an extension");
  X509_EXTENSION_free(ext);
}

// A certificate for `subject_cn`'s `key`, issued by `issuer` (null: self-signed, a CA).
ossl::Cert make_cert(const std::string& subject_cn, EVP_PKEY* key, X509* issuer,
                     EVP_PKEY* issuer_key) {
  ossl::Cert cert(X509_new());
  X509* c = cert.get();
  unsigned char serial[16];
  if (RAND_bytes(serial, sizeof serial) != 1) ossl::fail("internal", "a serial number");
  serial[0] &= 0x7f;  // positive
  BIGNUM* bn = BN_bin2bn(serial, sizeof serial, nullptr);
  BN_to_ASN1_INTEGER(bn, X509_get_serialNumber(c));
  BN_free(bn);
  X509_set_version(c, 2);
  X509_gmtime_adj(X509_getm_notBefore(c), -24L * 3600);  // clocks of other machines may lag
  X509_time_adj_ex(X509_getm_notAfter(c), kValidDays, 0, nullptr);
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

// `openssl smime -sign -text`: multipart/signed, the CA's certificate included.
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

std::string iso_utc(std::chrono::system_clock::time_point t) {
  const std::time_t tt = std::chrono::system_clock::to_time_t(t);
  std::tm tm{};
  gmtime_r(&tt, &tm);
  char text[32];
  std::strftime(text, sizeof text, "%Y-%m-%dT%H:%M:%S", &tm);
  return text;
}

std::string domains_xml() {
  return "<domains><id_range><min>0</min><max>" + std::to_string(kMaxSecureDomain) +
         "</max></id_range></domains>";
}

std::string governance_xml() {
  return R"(<?xml version="1.0" encoding="UTF-8"?>
<dds xmlns:xsi="http://www.w3.org/2001/XMLSchema-instance" xsi:noNamespaceSchemaLocation="http://www.omg.org/spec/DDS-SECURITY/20170901/omg_shared_ca_governance.xsd">
  <domain_access_rules>
    <domain_rule>
      )" +
         domains_xml() +
         R"(
      <allow_unauthenticated_participants>false</allow_unauthenticated_participants>
      <enable_join_access_control>true</enable_join_access_control>
      <discovery_protection_kind>ENCRYPT</discovery_protection_kind>
      <liveliness_protection_kind>ENCRYPT</liveliness_protection_kind>
      <rtps_protection_kind>SIGN</rtps_protection_kind>
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
}

std::string topics_xml(const std::vector<std::string>& topics) {
  std::string out = "<topics>";
  for (const auto& t : topics) out += "<topic>" + t + "</topic>";
  return out + "</topics>";
}

std::string permissions_xml(const std::string& name, const std::vector<std::string>& namespaces) {
  std::vector<std::string> publish = {"rt/flipper/lexicon", "rt/*/flipper/request"};
  std::vector<std::string> subscribe = {"rt/flipper/lexicon", "rt/*/flipper/plan",
                                        "rt/*/flipper/actions", "rt/*/flipper/answer"};
  for (const auto& ns : namespaces) {
    for (const char* leaf : {"plan", "actions", "answer"}) publish.push_back(node_topic(ns, leaf));
    subscribe.push_back(node_topic(ns, "request"));
  }
  const auto now = std::chrono::system_clock::now();
  return R"(<?xml version="1.0" encoding="UTF-8"?>
<dds xmlns:xsi="http://www.w3.org/2001/XMLSchema-instance" xsi:noNamespaceSchemaLocation="http://www.omg.org/spec/DDS-SECURITY/20170901/omg_shared_ca_permissions.xsd">
  <permissions>
    <grant name=")" +
         name + R"(">
      <subject_name>CN=)" +
         name + R"(</subject_name>
      <validity><not_before>)" +
         iso_utc(now - std::chrono::hours(24)) + "</not_before><not_after>" +
         iso_utc(now + std::chrono::hours(24 * kValidDays)) + R"(</not_after></validity>
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

// The folder of a Cyclone security plugin: Debian keeps them in libddsc0debian/ next to
// libddsc.so, outside the loader's path; elsewhere they sit next to it or on the path.
std::string plugin_path(const std::string& plugin) {
  Dl_info info{};
  if (dladdr(reinterpret_cast<void*>(&dds_create_participant), &info) != 0 &&
      info.dli_fname != nullptr) {
    const fs::path dir = fs::path(info.dli_fname).parent_path();
    for (const fs::path& p :
         {dir / "libddsc0debian" / ("lib" + plugin + ".so"), dir / ("lib" + plugin + ".so")}) {
      std::error_code ec;
      if (fs::exists(p, ec)) return p.string();
    }
  }
  return plugin;  // Cyclone's own search: lib<plugin>.so on the loader's path
}

void require_file(const std::string& path, const std::string& hint) {
  std::error_code ec;
  if (!fs::is_regular_file(path, ec))
    refuse(sdk::codes::kBadConfig, "DDS Security: '" + path + "' is missing (" + hint + ")");
}

}  // namespace

void init_keystore(const std::string& dir, std::ostream& out) {
  const Keystore ks{dir};
  std::error_code ec;
  if (fs::exists(ks.ca_certificate(), ec))
    refuse(sdk::codes::kBadRequest, "'" + dir + "' already holds a keystore (ca.pem)");
  fs::create_directories(dir + "/private", ec);
  if (ec) refuse("io_error", "cannot create '" + dir + "/private': " + ec.message());
  fs::permissions(dir + "/private", fs::perms::owner_all, ec);
  const ossl::Key key = new_key();
  const ossl::Cert ca = make_cert("Flipper DDS CA", key.get(), nullptr, nullptr);
  out << "flipper dds security: a keystore in " << dir << ":\n";
  write_text(ks.ca_key(), key_pem(key.get()), true, out);
  write_text(ks.ca_certificate(), ossl::cert_to_pem(ca.get()), false, out);
  const std::string governance = governance_xml();
  write_text(dir + "/governance.xml", governance, false, out);
  write_text(ks.governance(), smime_signed(governance, ca.get(), key.get()), false, out);
}

void add_identity(const std::string& dir, const std::string& name,
                  const std::vector<std::string>& namespaces, std::ostream& out) {
  const Keystore ks{dir};
  check_namespace(name, "identity name");
  for (const auto& ns : namespaces) check_namespace(ns, "namespace");
  std::error_code ec;
  if (name.empty()) refuse(sdk::codes::kBadRequest, "an identity needs a name");
  if (!fs::exists(ks.ca_key(), ec))
    refuse(sdk::codes::kBadRequest, "no keystore in '" + dir + "' (flipper dds security init)");
  if (fs::exists(ks.identity_dir(name), ec))
    refuse(sdk::codes::kBadRequest, "the keystore already has identity '" + name + "'");
  const ossl::Cert ca = read_cert(ks.ca_certificate());
  const ossl::Key ca_key = read_key(ks.ca_key());
  fs::create_directories(ks.identity_dir(name), ec);
  if (ec) refuse("io_error", "cannot create '" + ks.identity_dir(name) + "': " + ec.message());
  const ossl::Key key = new_key();
  const ossl::Cert cert = make_cert(name, key.get(), ca.get(), ca_key.get());
  const std::string permissions =
      permissions_xml(name, namespaces.empty() ? std::vector<std::string>{name} : namespaces);
  out << "flipper dds security: identity '" << name << "' in " << dir << ":\n";
  write_text(ks.private_key(name), key_pem(key.get()), true, out);
  write_text(ks.certificate(name), ossl::cert_to_pem(cert.get()), false, out);
  write_text(ks.identity_dir(name) + "/permissions.xml", permissions, false, out);
  write_text(ks.permissions(name), smime_signed(permissions, ca.get(), ca_key.get()), false, out);
}

std::vector<std::pair<std::string, std::string>> security_properties(const Keystore& ks,
                                                                     const std::string& name) {
  const std::string hint = "flipper dds security init DIR; flipper dds security add DIR " + name;
  for (const auto& f : {ks.ca_certificate(), ks.governance(), ks.certificate(name),
                        ks.private_key(name), ks.permissions(name)})
    require_file(f, hint);
  const auto file = [](const std::string& path) {
    return "file:" + fs::absolute(path).lexically_normal().string();
  };
  return {{"dds.sec.auth.library.path", plugin_path("dds_security_auth")},
          {"dds.sec.auth.library.init", "init_authentication"},
          {"dds.sec.auth.library.finalize", "finalize_authentication"},
          {"dds.sec.auth.identity_ca", file(ks.ca_certificate())},
          {"dds.sec.auth.identity_certificate", file(ks.certificate(name))},
          {"dds.sec.auth.private_key", file(ks.private_key(name))},
          {"dds.sec.crypto.library.path", plugin_path("dds_security_crypto")},
          {"dds.sec.crypto.library.init", "init_crypto"},
          {"dds.sec.crypto.library.finalize", "finalize_crypto"},
          {"dds.sec.access.library.path", plugin_path("dds_security_ac")},
          {"dds.sec.access.library.init", "init_access_control"},
          {"dds.sec.access.library.finalize", "finalize_access_control"},
          {"dds.sec.access.permissions_ca", file(ks.ca_certificate())},
          {"dds.sec.access.governance", file(ks.governance())},
          {"dds.sec.access.permissions", file(ks.permissions(name))}};
}

std::optional<SecurityConfig> security_config(const kernel::Config& config) {
  const std::string dir = config.get(keys::kKeystore);
  if (dir.empty()) return std::nullopt;
  SecurityConfig sc{Keystore{dir}, config.get(keys::kIdentity)};
  if (sc.identity.empty()) sc.identity = config.get(naturalization::keys::kSite);
  if (sc.identity.empty()) sc.identity = config.get(keys::kNamespace);
  if (sc.identity.empty())
    refuse(sdk::codes::kBadConfig,
           "dds.security.keystore is set but no identity is named: set dds.security.identity "
           "(or lexicon.site, or dds.namespace)");
  if (config.get(keys::kDomain) > kMaxSecureDomain)
    refuse(sdk::codes::kBadConfig, "with DDS Security, dds.domain must be at most " +
                                       std::to_string(kMaxSecureDomain) +
                                       " (the governance and permissions cover 0.." +
                                       std::to_string(kMaxSecureDomain) + ")");
  return sc;
}

std::string certificate_common_name(const std::string& pem_path) {
  return ossl::common_name(read_cert(pem_path).get());
}

}  // namespace flipper::dds
