#pragma once
// The server's TLS settings (docs/serve.md "HTTPS"): serve.tls.cert and serve.tls.key read into
// an OpenSSL context for Beast's ssl_stream, TLS 1.2 or later, checked at start so a bad file
// stops `flipper serve` with a bad_config naming it (never at the first connection).
#include <boost/asio/ssl/context.hpp>
#include <memory>
#include <string>

namespace flipper::studio {

/// A server context with the certificate chain in `cert` and its private key in `key` (PEM,
/// the key unencrypted). Throws sdk::Error(bad_config) naming the file and what is wrong: only
/// one of them given, unreadable, no PEM certificate or key in it, or a key that is not the
/// certificate's.
std::unique_ptr<boost::asio::ssl::context> make_tls_context(const std::string& cert,
                                                            const std::string& key);

}  // namespace flipper::studio
