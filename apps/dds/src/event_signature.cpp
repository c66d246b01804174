#include "flipper/dds/event_signature.hpp"

#include <openssl/x509_vfy.h>

#include <fstream>
#include <sstream>

#include "pki.hpp"

namespace flipper::dds {
namespace {

using Store = std::unique_ptr<X509_STORE, ossl::Deleter<X509_STORE, X509_STORE_free>>;
using StoreCtx =
    std::unique_ptr<X509_STORE_CTX, ossl::Deleter<X509_STORE_CTX, X509_STORE_CTX_free>>;

std::string read_file(const std::string& path) {
  std::ifstream in(path, std::ios::binary);
  if (!in) throw sdk::Error(sdk::codes::kBadConfig, "DDS Security: cannot read '" + path + "'");
  std::ostringstream s;
  s << in.rdbuf();
  return s.str();
}

}  // namespace

struct EventSigner::Impl {
  ossl::Key key;
  std::string certificate;
};

EventSigner::EventSigner(const Keystore& ks, const std::string& name)
    : impl_(std::make_unique<Impl>()) {
  impl_->certificate = read_file(ks.certificate(name));
  const ossl::Cert cert = ossl::cert_from_pem(impl_->certificate);
  if (!cert) ossl::fail(sdk::codes::kBadConfig, "reading '" + ks.certificate(name) + "'");
  if (const std::string cn = ossl::common_name(cert.get()); cn != name)
    throw sdk::Error(sdk::codes::kBadConfig, "DDS Security: the certificate '" +
                                                 ks.certificate(name) + "' is for '" + cn +
                                                 "', not '" + name + "'");
  const std::string pem = read_file(ks.private_key(name));
  ossl::Bio bio(BIO_new_mem_buf(pem.data(), static_cast<int>(pem.size())));
  impl_->key.reset(bio ? PEM_read_bio_PrivateKey(bio.get(), nullptr, nullptr, nullptr) : nullptr);
  if (!impl_->key) ossl::fail(sdk::codes::kBadConfig, "reading '" + ks.private_key(name) + "'");
  if (X509_check_private_key(cert.get(), impl_->key.get()) != 1)
    ossl::fail(sdk::codes::kBadConfig,
               "'" + ks.private_key(name) + "' is not the key of '" + ks.certificate(name) + "'");
}

EventSigner::~EventSigner() = default;

void EventSigner::sign(LexiconEvent& e) const {
  e.certificate = impl_->certificate;
  const std::string text = signed_text(e);
  ossl::MdCtx ctx(EVP_MD_CTX_new());
  std::size_t size = 0;
  if (!ctx ||
      EVP_DigestSignInit(ctx.get(), nullptr, EVP_sha256(), nullptr, impl_->key.get()) != 1 ||
      EVP_DigestSign(ctx.get(), nullptr, &size, reinterpret_cast<const unsigned char*>(text.data()),
                     text.size()) != 1)
    ossl::fail("internal", "signing event " + e.identity());
  std::string signature(size, '\0');
  if (EVP_DigestSign(ctx.get(), reinterpret_cast<unsigned char*>(signature.data()), &size,
                     reinterpret_cast<const unsigned char*>(text.data()), text.size()) != 1)
    ossl::fail("internal", "signing event " + e.identity());
  signature.resize(size);
  e.signature = std::move(signature);
}

struct EventVerifier::Impl {
  Store store;
  std::string crl;  // the revocation list's path, "" for none
  struct Known {
    std::string error;  // empty: issued by the CA
    std::string cn;
    ossl::Key key;
  };
  std::map<std::string, Known> certificates;  // by PEM

  const Known& known(const std::string& pem) {
    if (auto it = certificates.find(pem); it != certificates.end()) return it->second;
    constexpr std::size_t kMaxCached = 1024;  // a flood of certificates cannot grow memory
    if (certificates.size() >= kMaxCached) certificates.clear();
    Known k;
    const ossl::Cert cert = ossl::cert_from_pem(pem);
    if (!cert) {
      k.error = "its certificate is not a PEM certificate";
    } else {
      StoreCtx ctx(X509_STORE_CTX_new());
      if (!ctx || X509_STORE_CTX_init(ctx.get(), store.get(), cert.get(), nullptr) != 1 ||
          X509_verify_cert(ctx.get()) != 1) {
        const int error = ctx ? X509_STORE_CTX_get_error(ctx.get()) : X509_V_ERR_UNSPECIFIED;
        k.error = error == X509_V_ERR_CERT_REVOKED
                      ? "its certificate (serial " + pki::serial_hex(cert.get()) +
                            ") was revoked by the CA (" + crl + ")"
                      : std::string("its certificate was not issued by the keystore's CA (") +
                            X509_verify_cert_error_string(error) + ")";
      }
      k.cn = ossl::common_name(cert.get());
      k.key.reset(X509_get_pubkey(cert.get()));
    }
    ERR_clear_error();
    return certificates.emplace(pem, std::move(k)).first->second;
  }
};

EventVerifier::EventVerifier(const Keystore& ks) : impl_(std::make_unique<Impl>()) {
  impl_->store.reset(X509_STORE_new());
  const ossl::Cert ca = ossl::cert_from_pem(read_file(ks.ca_certificate()));
  if (!ca || !impl_->store || X509_STORE_add_cert(impl_->store.get(), ca.get()) != 1)
    ossl::fail(sdk::codes::kBadConfig, "DDS Security: reading '" + ks.ca_certificate() + "'");
  // The revocation list (dds.security.crl), read once: a new one takes effect on restart, as it
  // does for Cyclone's handshake (keystore.cpp security_properties).
  impl_->crl = ks.revocation_list();
  if (!impl_->crl.empty()) {
    const ossl::Crl list = pki::read_crl(impl_->crl, ca.get());
    if (X509_STORE_add_crl(impl_->store.get(), list.get()) != 1 ||
        X509_STORE_set_flags(impl_->store.get(), X509_V_FLAG_CRL_CHECK) != 1)
      ossl::fail("internal", "the revocation list '" + impl_->crl + "'");
  }
}

EventVerifier::~EventVerifier() = default;

std::optional<std::string> EventVerifier::why_not(const LexiconEvent& e) {
  if (e.certificate.empty() || e.signature.empty()) return "it is not signed";
  const Impl::Known& k = impl_->known(e.certificate);
  if (!k.error.empty()) return k.error;
  if (k.cn != e.site)
    return "it claims site '" + e.site + "' but is signed by '" + k.cn.substr(0, 64) + "'";
  const std::string text = signed_text(e);
  ossl::MdCtx ctx(EVP_MD_CTX_new());
  const bool ok =
      ctx && k.key &&
      EVP_DigestVerifyInit(ctx.get(), nullptr, EVP_sha256(), nullptr, k.key.get()) == 1 &&
      EVP_DigestVerify(ctx.get(), reinterpret_cast<const unsigned char*>(e.signature.data()),
                       e.signature.size(), reinterpret_cast<const unsigned char*>(text.data()),
                       text.size()) == 1;
  ERR_clear_error();
  if (!ok) return "its signature does not match its content";
  return std::nullopt;
}

}  // namespace flipper::dds
