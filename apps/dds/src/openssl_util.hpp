#pragma once
// OpenSSL (libcrypto) handles with their free functions, and the few reads and writes the
// keystore and the event signatures share. Internal to apps/dds.
#include <openssl/bio.h>
#include <openssl/crypto.h>
#include <openssl/err.h>
#include <openssl/evp.h>
#include <openssl/pem.h>
#include <openssl/x509.h>

#include <memory>
#include <string>

#include "flipper/sdk/errors.hpp"

namespace flipper::dds::ossl {

template <class T, void (*Free)(T*)>
struct Deleter {
  void operator()(T* p) const { Free(p); }
};
using Bio = std::unique_ptr<BIO, Deleter<BIO, BIO_free_all>>;
using Key = std::unique_ptr<EVP_PKEY, Deleter<EVP_PKEY, EVP_PKEY_free>>;
using Cert = std::unique_ptr<X509, Deleter<X509, X509_free>>;
using Crl = std::unique_ptr<X509_CRL, Deleter<X509_CRL, X509_CRL_free>>;
using MdCtx = std::unique_ptr<EVP_MD_CTX, Deleter<EVP_MD_CTX, EVP_MD_CTX_free>>;

/// Frees memory OpenSSL allocated for us. OPENSSL_free would pass __FILE__ and so compile this
/// checkout's path into the binary, which an installed flipper must not hold
/// (docs/architecture.md, "installed binary").
inline void free_memory(void* memory) {
  CRYPTO_free(memory, "", 0);
}

/// OpenSSL's last error as text (and the queue cleared).
inline std::string last_error() {
  char text[256] = "unknown OpenSSL error";
  if (const unsigned long e = ERR_get_error(); e != 0) ERR_error_string_n(e, text, sizeof text);
  ERR_clear_error();
  return text;
}

[[noreturn]] inline void fail(const std::string& code, const std::string& what) {
  throw sdk::Error(code, what + ": " + last_error());
}

inline Cert cert_from_pem(const std::string& pem) {
  Bio bio(BIO_new_mem_buf(pem.data(), static_cast<int>(pem.size())));
  return Cert(bio ? PEM_read_bio_X509(bio.get(), nullptr, nullptr, nullptr) : nullptr);
}

inline std::string cert_to_pem(X509* cert) {
  Bio bio(BIO_new(BIO_s_mem()));
  if (!bio || PEM_write_bio_X509(bio.get(), cert) != 1) fail("internal", "writing a certificate");
  char* data = nullptr;
  const long n = BIO_get_mem_data(bio.get(), &data);
  return std::string(data, static_cast<std::size_t>(n));
}

/// The subject's common name, or "" when it has none.
inline std::string common_name(X509* cert) {
  char cn[256] = {};
  const int n = X509_NAME_get_text_by_NID(X509_get_subject_name(cert), NID_commonName, cn,
                                          static_cast<int>(sizeof cn));
  return n > 0 ? std::string(cn, static_cast<std::size_t>(n)) : std::string();
}

}  // namespace flipper::dds::ossl
