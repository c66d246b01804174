// OpenSSL context of the HTTPS server (tls_context.hpp, docs/serve.md "HTTPS").
#include "tls_context.hpp"

#include <openssl/bio.h>
#include <openssl/err.h>
#include <openssl/evp.h>
#include <openssl/pem.h>
#include <openssl/ssl.h>

#include <cerrno>
#include <cstring>
#include <fstream>
#include <sstream>

#include "flipper/sdk/errors.hpp"

namespace flipper::studio {
namespace {

[[noreturn]] void bad(const std::string& message) {
  ERR_clear_error();
  throw sdk::Error(sdk::codes::kBadConfig, message);
}

// The file's text (certificates and keys are small); bad_config when it cannot be read.
std::string read_text(const char* key, const std::string& path) {
  std::ifstream file(path, std::ios::binary);
  if (!file) bad(std::string(key) + " '" + path + "': cannot read it: " + std::strerror(errno));
  std::ostringstream text;
  text << file.rdbuf();
  if (file.bad()) bad(std::string(key) + " '" + path + "': cannot read it");
  return text.str();
}

struct KeyFree {
  void operator()(EVP_PKEY* key) const { EVP_PKEY_free(key); }
};
struct BioFree {
  void operator()(BIO* bio) const { BIO_free(bio); }
};

// An encrypted key fails instead of asking for a passphrase on the terminal.
int no_passphrase(char* /*buf*/, int /*size*/, int /*rwflag*/, void* /*userdata*/) {
  return 0;
}

}  // namespace

std::unique_ptr<boost::asio::ssl::context> make_tls_context(const std::string& cert,
                                                            const std::string& key) {
  if (cert.empty() != key.empty())
    bad(std::string(cert.empty() ? "serve.tls.key" : "serve.tls.cert") + " is set but " +
        (cert.empty() ? "serve.tls.cert" : "serve.tls.key") +
        " is not: HTTPS needs the certificate and its key");
  read_text("serve.tls.cert", cert);
  const std::string key_text = read_text("serve.tls.key", key);
  namespace ssl = boost::asio::ssl;
  auto context = std::make_unique<ssl::context>(ssl::context::tls_server);
  context->set_options(ssl::context::default_workarounds | ssl::context::no_sslv2 |
                       ssl::context::no_sslv3 | ssl::context::no_tlsv1 | ssl::context::no_tlsv1_1 |
                       ssl::context::single_dh_use);
  SSL_CTX* native = context->native_handle();
  ERR_clear_error();
  if (SSL_CTX_use_certificate_chain_file(native, cert.c_str()) != 1)
    bad("serve.tls.cert '" + cert + "' holds no PEM certificate");
  const std::unique_ptr<BIO, BioFree> bio(
      BIO_new_mem_buf(key_text.data(), static_cast<int>(key_text.size())));
  const std::unique_ptr<EVP_PKEY, KeyFree> pkey(
      bio ? PEM_read_bio_PrivateKey(bio.get(), nullptr, no_passphrase, nullptr) : nullptr);
  if (!pkey && key_text.find("ENCRYPTED") != std::string::npos)
    bad("serve.tls.key '" + key + "' is encrypted: give the key without a passphrase");
  if (!pkey) bad("serve.tls.key '" + key + "' holds no PEM private key");
  if (SSL_CTX_use_PrivateKey(native, pkey.get()) != 1 || SSL_CTX_check_private_key(native) != 1)
    bad("serve.tls.key '" + key + "' is not the private key of the certificate in '" + cert + "'");
  return context;
}

}  // namespace flipper::studio
