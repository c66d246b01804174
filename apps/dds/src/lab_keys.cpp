// Labs that own their keys (lab_keys.hpp): the CSR at the lab, its checks and the certificate at
// the CA, renewal, and the checked install at the lab; with libcrypto.
#include "flipper/dds/lab_keys.hpp"

#include <openssl/core_names.h>
#include <openssl/pkcs7.h>
#include <openssl/x509_vfy.h>

#include <filesystem>

#include "flipper/dds/keystore.hpp"
#include "flipper/dds/names.hpp"
#include "pki.hpp"

namespace flipper::dds {
namespace {

namespace fs = std::filesystem;
using pki::refuse;
using Req = std::unique_ptr<X509_REQ, ossl::Deleter<X509_REQ, X509_REQ_free>>;
using Store = std::unique_ptr<X509_STORE, ossl::Deleter<X509_STORE, X509_STORE_free>>;
using StoreCtx =
    std::unique_ptr<X509_STORE_CTX, ossl::Deleter<X509_STORE_CTX, X509_STORE_CTX_free>>;
using Pkcs7 = std::unique_ptr<PKCS7, ossl::Deleter<PKCS7, PKCS7_free>>;

void check_days(long days) {
  if (days < 1 || days > pki::kMaxIdentityDays)
    refuse(sdk::codes::kBadRequest, "--days " + std::to_string(days) + " is not in [1, " +
                                        std::to_string(pki::kMaxIdentityDays) + "]");
}

bool exists(const std::string& path) {
  std::error_code ec;
  return fs::exists(path, ec);
}

void make_dir(const std::string& path, bool private_dir) {
  std::error_code ec;
  fs::create_directories(path, ec);
  if (ec) refuse("io_error", "cannot create '" + path + "': " + ec.message());
  if (private_dir) fs::permissions(path, fs::perms::owner_all, fs::perm_options::replace, ec);
  if (ec) refuse("io_error", "cannot make '" + path + "' private: " + ec.message());
}

void copy_file(const std::string& from, const std::string& to, std::ostream& out) {
  pki::write_text(to, pki::read_text(from), false, out);
}

std::string subject_text(X509_NAME* name) {
  char text[256] = {};
  X509_NAME_oneline(name, text, sizeof text);
  return text;
}

// The key kinds Cyclone's authentication plugin takes (its validate_local_identity): EC P-256
// (prime256v1) or 2048-bit RSA. Empty when `key` is one of them, else what it is.
std::string unsupported_key(EVP_PKEY* key) {
  if (EVP_PKEY_is_a(key, "EC")) {
    char group[64] = {};
    std::size_t n = 0;
    if (EVP_PKEY_get_utf8_string_param(key, OSSL_PKEY_PARAM_GROUP_NAME, group, sizeof group, &n) ==
            1 &&
        std::string(group) == "prime256v1")
      return {};
    return std::string("an EC key on curve '") + group + "'";
  }
  if (EVP_PKEY_is_a(key, "RSA")) {
    if (EVP_PKEY_get_bits(key) == 2048) return {};
    return "a " + std::to_string(EVP_PKEY_get_bits(key)) + "-bit RSA key";
  }
  return std::string("a key of type '") + EVP_PKEY_get0_type_name(key) + "'";
}

Req read_request(const std::string& path) {
  const std::string pem = pki::read_text(path);
  ossl::Bio bio(BIO_new_mem_buf(pem.data(), static_cast<int>(pem.size())));
  Req req(bio ? PEM_read_bio_X509_REQ(bio.get(), nullptr, nullptr, nullptr) : nullptr);
  ERR_clear_error();
  if (!req)
    refuse(sdk::codes::kBadRequest,
           "'" + path +
               "' is not a certificate signing request (PEM, from `flipper dds security "
               "request`)");
  return req;
}

// The request's identity name, once its signature, key and subject pass (docs/ros2.md, "Labs
// that keep their keys": the same name rule as `add`).
std::string checked_request_name(X509_REQ* req, const std::string& path) {
  EVP_PKEY* key = X509_REQ_get0_pubkey(req);
  if (key == nullptr) refuse(sdk::codes::kBadRequest, "the request '" + path + "' has no key");
  const int verified = X509_REQ_verify(req, key);
  ERR_clear_error();
  if (verified != 1)
    refuse(sdk::codes::kBadRequest,
           "the request '" + path +
               "' is not signed by its own key (its content was changed after it was made)");
  if (const std::string bad = unsupported_key(key); !bad.empty())
    refuse(sdk::codes::kBadRequest, "the request '" + path + "' holds " + bad +
                                        "; DDS Security takes EC P-256 or 2048-bit RSA keys");
  X509_NAME* subject = X509_REQ_get_subject_name(req);
  const X509_NAME_ENTRY* only =
      X509_NAME_entry_count(subject) == 1 ? X509_NAME_get_entry(subject, 0) : nullptr;
  if (only == nullptr ||
      OBJ_obj2nid(X509_NAME_ENTRY_get_object(const_cast<X509_NAME_ENTRY*>(only))) != NID_commonName)
    refuse(sdk::codes::kBadRequest, "the request '" + path +
                                        "' must name exactly one common name (CN=NAME); its "
                                        "subject is '" +
                                        subject_text(subject) + "'");
  const unsigned char* data =
      ASN1_STRING_get0_data(X509_NAME_ENTRY_get_data(const_cast<X509_NAME_ENTRY*>(only)));
  const int size = ASN1_STRING_length(X509_NAME_ENTRY_get_data(const_cast<X509_NAME_ENTRY*>(only)));
  std::string name(reinterpret_cast<const char*>(data), static_cast<std::size_t>(size));
  if (name.empty()) refuse(sdk::codes::kBadRequest, "the request '" + path + "' names no one");
  check_namespace(name, "the request's identity name");
  return name;
}

// Writes identity `name`'s certificate and signed permissions at the CA, and the outbox.
void issue(const Keystore& ks, const std::string& name, X509* cert, const std::string& permissions,
           X509* ca, EVP_PKEY* ca_key, std::ostream& out) {
  pki::write_text(ks.certificate(name), ossl::cert_to_pem(cert), false, out);
  pki::write_text(ks.identity_dir(name) + "/permissions.xml", permissions, false, out);
  pki::write_text(ks.permissions(name), pki::smime_signed(permissions, ca, ca_key), false, out);
  const std::string box = ks.outbox(name);
  make_dir(box, false);
  out << "send to the lab (the folder " << box << "):\n";
  copy_file(ks.ca_certificate(), box + "/ca.pem", out);
  copy_file(ks.governance(), box + "/governance.p7s", out);
  if (exists(ks.governance_sign()))
    copy_file(ks.governance_sign(), box + "/governance_sign.p7s", out);
  copy_file(ks.certificate(name), box + "/cert.pem", out);
  copy_file(ks.permissions(name), box + "/permissions.p7s", out);
  if (exists(ks.crl_file())) copy_file(ks.crl_file(), box + "/crl.pem", out);
}

struct Authority {
  ossl::Cert ca;
  ossl::Key key;
};

Authority open_authority(const Keystore& ks) {
  if (!exists(ks.ca_key()))
    refuse(sdk::codes::kBadRequest, "no CA in '" + ks.dir +
                                        "' (flipper dds security init; sign, renew and revoke "
                                        "run where private/ca.key is)");
  return {pki::read_cert(ks.ca_certificate()), pki::read_key(ks.ca_key())};
}

// Why `cert` was not issued by `ca` ("" when it was).
std::string not_issued_by(X509* cert, X509* ca) {
  Store store(X509_STORE_new());
  StoreCtx ctx(X509_STORE_CTX_new());
  if (!store || !ctx || X509_STORE_add_cert(store.get(), ca) != 1 ||
      X509_STORE_CTX_init(ctx.get(), store.get(), cert, nullptr) != 1)
    ossl::fail("internal", "a certificate store");
  const bool ok = X509_verify_cert(ctx.get()) == 1;
  ERR_clear_error();
  return ok ? "" : X509_verify_cert_error_string(X509_STORE_CTX_get_error(ctx.get()));
}

// The content of an S/MIME document at `path` signed by `ca`; refuses one that is not.
std::string verified_document(const std::string& path, X509* ca) {
  const std::string text = pki::read_text(path);
  ossl::Bio in(BIO_new_mem_buf(text.data(), static_cast<int>(text.size())));
  BIO* content_raw = nullptr;
  Pkcs7 p7(in ? SMIME_read_PKCS7(in.get(), &content_raw) : nullptr);
  ossl::Bio content(content_raw);
  Store store(X509_STORE_new());
  ossl::Bio plain(BIO_new(BIO_s_mem()));
  const bool ok =
      p7 && store && plain && X509_STORE_add_cert(store.get(), ca) == 1 &&
      PKCS7_verify(p7.get(), nullptr, store.get(), content.get(), plain.get(), PKCS7_TEXT) == 1;
  ERR_clear_error();
  if (!ok) refuse(sdk::codes::kBadRequest, "'" + path + "' is not a document signed by the CA");
  char* data = nullptr;
  const long n = BIO_get_mem_data(plain.get(), &data);
  return std::string(data, static_cast<std::size_t>(n));
}

}  // namespace

std::string request_identity(const std::string& dir, const std::string& name, std::ostream& out) {
  const Keystore ks{dir};
  if (name.empty()) refuse(sdk::codes::kBadRequest, "an identity needs a name");
  check_namespace(name, "identity name");
  if (exists(ks.private_key(name)))
    refuse(sdk::codes::kBadRequest, "'" + ks.private_key(name) + "' exists: identity '" + name +
                                        "' has a key already (its request: " + ks.request(name) +
                                        ")");
  make_dir(ks.identity_dir(name), true);
  const ossl::Key key = pki::new_key();
  Req req(X509_REQ_new());
  X509_NAME* subject = req ? X509_REQ_get_subject_name(req.get()) : nullptr;
  if (subject == nullptr || X509_REQ_set_version(req.get(), 0) != 1 ||
      X509_NAME_add_entry_by_txt(subject, "CN", MBSTRING_UTF8,
                                 reinterpret_cast<const unsigned char*>(name.c_str()), -1, -1,
                                 0) != 1 ||
      X509_REQ_set_pubkey(req.get(), key.get()) != 1 ||
      X509_REQ_sign(req.get(), key.get(), EVP_sha256()) == 0)
    ossl::fail("internal", "making the request");
  ossl::Bio bio(BIO_new(BIO_s_mem()));
  if (!bio || PEM_write_bio_X509_REQ(bio.get(), req.get()) != 1)
    ossl::fail("internal", "writing the request");
  char* data = nullptr;
  const long n = BIO_get_mem_data(bio.get(), &data);
  out << "flipper dds security: the key and request of '" << name << "' in " << dir << ":\n";
  pki::write_text(ks.private_key(name), pki::key_pem(key.get()), true, out);
  pki::write_text(ks.request(name), std::string(data, static_cast<std::size_t>(n)), false, out);
  return ks.request(name);
}

std::string sign_request(const std::string& ca_dir, const std::string& csr_path,
                         const std::string& role, const std::vector<std::string>& namespaces,
                         long days, std::ostream& out) {
  const Keystore ks{ca_dir};
  check_days(days);
  pki::check_role(role);
  for (const auto& ns : namespaces) check_namespace(ns, "namespace");
  const Authority authority = open_authority(ks);
  const Req req = read_request(csr_path);
  std::string name = checked_request_name(req.get(), csr_path);
  if (exists(ks.certificate(name)))
    refuse(sdk::codes::kBadRequest, "the keystore already has identity '" + name +
                                        "' (renew it, or revoke it before signing a new key)");
  make_dir(ks.identity_dir(name), false);
  const ossl::Cert cert = pki::make_cert(name, X509_REQ_get0_pubkey(req.get()), authority.ca.get(),
                                         authority.key.get(), days);
  out << "flipper dds security: identity '" << name << "' signed in " << ca_dir << ", valid "
      << days << " days:\n";
  copy_file(csr_path, ks.request(name), out);
  issue(ks, name, cert.get(), pki::permissions_xml(name, role, namespaces, days),
        authority.ca.get(), authority.key.get(), out);
  return name;
}

void renew_identity(const std::string& ca_dir, const std::string& name, long days,
                    std::ostream& out) {
  const Keystore ks{ca_dir};
  check_days(days);
  check_namespace(name, "identity name");
  const Authority authority = open_authority(ks);
  if (name.empty() || !exists(ks.certificate(name)))
    refuse(sdk::codes::kBadRequest, "the keystore has no identity '" + name + "'");
  const ossl::Cert old = pki::read_cert(ks.certificate(name));
  if (X509_cmp_current_time(X509_get0_notAfter(old.get())) <= 0)
    refuse(sdk::codes::kBadRequest, "the certificate of '" + name +
                                        "' has expired: the lab makes a new request (revoke "
                                        "'" +
                                        name + "' first)");
  const std::string permissions =
      pki::with_validity(pki::read_text(ks.identity_dir(name) + "/permissions.xml"), days);
  const ossl::Cert cert = pki::make_cert(name, X509_get0_pubkey(old.get()), authority.ca.get(),
                                         authority.key.get(), days);
  out << "flipper dds security: identity '" << name << "' renewed in " << ca_dir << ", valid "
      << days << " days:\n";
  const std::string previous = ks.identity_dir(name) + "/previous";
  make_dir(previous, false);
  copy_file(ks.certificate(name), previous + "/" + pki::serial_hex(old.get()) + ".pem", out);
  issue(ks, name, cert.get(), permissions, authority.ca.get(), authority.key.get(), out);
}

void install_identity(const std::string& dir, const std::string& name, const std::string& from,
                      std::ostream& out) {
  const Keystore ks{dir};
  check_namespace(name, "identity name");
  if (name.empty() || !exists(ks.private_key(name)))
    refuse(sdk::codes::kBadRequest, "'" + ks.private_key(name) + "' is missing: install runs " +
                                        "in the lab's folder, after `flipper dds security " +
                                        "request " + dir + " " + name + "`");
  for (const char* f : {"ca.pem", "governance.p7s", "cert.pem", "permissions.p7s"})
    if (!exists(from + "/" + f))
      refuse(sdk::codes::kBadRequest,
             "'" + from + "/" + f + "' is missing (the CA's outbox/" + name + " holds it)");
  const ossl::Cert ca = pki::read_cert(from + "/ca.pem");
  const ossl::Cert cert = pki::read_cert(from + "/cert.pem");
  if (const std::string why = not_issued_by(cert.get(), ca.get()); !why.empty())
    refuse(sdk::codes::kBadRequest,
           "'" + from + "/cert.pem' was not issued by '" + from + "/ca.pem' (" + why + ")");
  if (const std::string cn = ossl::common_name(cert.get()); cn != name)
    refuse(sdk::codes::kBadRequest,
           "'" + from + "/cert.pem' is for '" + cn + "', not '" + name + "'");
  const ossl::Key key = pki::read_key(ks.private_key(name));
  const int matches = X509_check_private_key(cert.get(), key.get());
  ERR_clear_error();
  if (matches != 1)
    refuse(sdk::codes::kBadRequest, "'" + from + "/cert.pem' is not for this lab's key '" +
                                        ks.private_key(name) + "' (signed from another request?)");
  if (exists(ks.ca_certificate()) &&
      X509_cmp(pki::read_cert(ks.ca_certificate()).get(), ca.get()) != 0)
    refuse(sdk::codes::kBadRequest,
           "'" + ks.ca_certificate() + "' is another CA's than '" + from + "/ca.pem'");
  const std::string permissions = verified_document(from + "/permissions.p7s", ca.get());
  if (permissions.find("<subject_name>CN=" + name + "</subject_name>") == std::string::npos)
    refuse(sdk::codes::kBadRequest, "'" + from + "/permissions.p7s' does not grant CN=" + name);
  verified_document(from + "/governance.p7s", ca.get());
  const bool has_sign = exists(from + "/governance_sign.p7s");  // dds.security.protection: sign
  if (has_sign) verified_document(from + "/governance_sign.p7s", ca.get());
  const bool has_crl = exists(from + "/crl.pem");
  if (has_crl) {
    const ossl::Crl crl = pki::read_crl(from + "/crl.pem", ca.get());
    X509_REVOKED* entry = nullptr;
    if (X509_CRL_get0_by_cert(crl.get(), &entry, cert.get()) == 1)
      refuse(sdk::codes::kBadRequest,
             "'" + from + "/cert.pem' is revoked by '" + from + "/crl.pem'");
  }
  out << "flipper dds security: identity '" << name << "' installed in " << dir << ":\n";
  copy_file(from + "/ca.pem", ks.ca_certificate(), out);
  copy_file(from + "/governance.p7s", ks.governance(), out);
  if (has_sign) copy_file(from + "/governance_sign.p7s", ks.governance_sign(), out);
  copy_file(from + "/cert.pem", ks.certificate(name), out);
  copy_file(from + "/permissions.p7s", ks.permissions(name), out);
  if (has_crl) copy_file(from + "/crl.pem", ks.crl_file(), out);
}

std::string revoke_identity(const std::string& ca_dir, const std::string& name, std::ostream& out) {
  const Keystore ks{ca_dir};
  check_namespace(name, "identity name");
  const Authority authority = open_authority(ks);
  if (name.empty() || !exists(ks.certificate(name)))
    refuse(
        sdk::codes::kBadRequest,
        "the keystore has no identity '" + name + "'" +
            (exists(ks.dir + "/revoked") ? " (revoked ones are in " + ks.dir + "/revoked)" : ""));
  std::vector<ossl::Cert> certs;
  certs.push_back(pki::read_cert(ks.certificate(name)));
  std::error_code ec;
  const std::string previous = ks.identity_dir(name) + "/previous";
  if (exists(previous))
    for (const auto& entry : fs::directory_iterator(previous, ec))
      certs.push_back(pki::read_cert(entry.path().string()));
  if (ec) refuse("io_error", "cannot read '" + previous + "': " + ec.message());
  // The list so far (checked: the CA's), or a new one; the same entries, and NAME's added.
  ossl::Crl crl(exists(ks.crl_file()) ? pki::read_crl(ks.crl_file(), authority.ca.get())
                                      : ossl::Crl(X509_CRL_new()));
  X509_CRL* c = crl.get();
  using Time = std::unique_ptr<ASN1_TIME, ossl::Deleter<ASN1_TIME, ASN1_TIME_free>>;
  const Time now(X509_gmtime_adj(nullptr, 0));
  if (c == nullptr || !now || X509_CRL_set_version(c, 1) != 1 ||
      X509_CRL_set_issuer_name(c, X509_get_subject_name(authority.ca.get())) != 1 ||
      X509_CRL_set1_lastUpdate(c, now.get()) != 1 ||
      // Valid as long as the CA: a list that expired would stop every participant.
      X509_CRL_set1_nextUpdate(c, X509_get0_notAfter(authority.ca.get())) != 1)
    ossl::fail("internal", "making the revocation list");
  for (const auto& cert : certs) {
    X509_REVOKED* listed = nullptr;
    if (X509_CRL_get0_by_cert(c, &listed, cert.get()) == 1) continue;
    X509_REVOKED* r = X509_REVOKED_new();
    if (r == nullptr || X509_REVOKED_set_serialNumber(r, X509_get_serialNumber(cert.get())) != 1 ||
        X509_REVOKED_set_revocationDate(r, now.get()) != 1 || X509_CRL_add0_revoked(c, r) != 1) {
      X509_REVOKED_free(r);
      ossl::fail("internal", "adding to the revocation list");
    }
  }
  if (X509_CRL_sort(c) != 1 || X509_CRL_sign(c, authority.key.get(), EVP_sha256()) == 0)
    ossl::fail("internal", "signing the revocation list");
  ossl::Bio bio(BIO_new(BIO_s_mem()));
  if (!bio || PEM_write_bio_X509_CRL(bio.get(), c) != 1)
    ossl::fail("internal", "writing the revocation list");
  char* data = nullptr;
  const long n = BIO_get_mem_data(bio.get(), &data);
  out << "flipper dds security: identity '" << name << "' revoked (" << certs.size()
      << " certificate" << (certs.size() == 1 ? "" : "s") << ") in " << ca_dir << ":\n";
  pki::write_text(ks.crl_file(), std::string(data, static_cast<std::size_t>(n)), false, out);
  const std::string moved =
      ks.dir + "/revoked/" + name + "-" + pki::serial_hex(certs.front().get());
  make_dir(ks.dir + "/revoked", false);
  fs::rename(ks.identity_dir(name), moved, ec);
  if (ec) refuse("io_error", "cannot move '" + ks.identity_dir(name) + "': " + ec.message());
  out << "  " << ks.identity_dir(name) << " -> " << moved << "\n";
  fs::remove_all(ks.outbox(name), ec);
  return ks.crl_file();
}

}  // namespace flipper::dds
