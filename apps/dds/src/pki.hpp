#pragma once
// The certificate-authority pieces the keystore (keystore.cpp) and the lab ↔ CA commands
// (lab_keys.cpp) share: files, keys, certificates, S/MIME-signed documents, with libcrypto.
// Internal to apps/dds; docs/ros2.md, "Secured sites", describes what they make.
#include <chrono>
#include <ostream>
#include <string>
#include <vector>

#include "openssl_util.hpp"

namespace flipper::dds::pki {

/// Default lifetime of an identity's certificate and permissions (`--days`), and the bounds.
inline constexpr long kIdentityDays = 365;
inline constexpr long kMaxIdentityDays = 3650;
/// Lifetime of the project CA's certificate (init).
inline constexpr long kCaDays = 3650;

[[noreturn]] void refuse(const std::string& code, const std::string& message);

std::string read_text(const std::string& path);
/// Writes `text` to `path` (mode 0600 when `secret`), checked; names the file on `out`.
void write_text(const std::string& path, const std::string& text, bool secret, std::ostream& out);

ossl::Key new_key();
std::string key_pem(EVP_PKEY* key);
ossl::Key read_key(const std::string& path);
ossl::Cert read_cert(const std::string& path);

/// A certificate for `subject_cn` holding the public part of `key`, issued by `issuer` with
/// `issuer_key` (both null: self-signed by `key`, a CA), valid from a day ago (clocks of other
/// machines may lag) for `days` days.
ossl::Cert make_cert(const std::string& subject_cn, EVP_PKEY* key, X509* issuer,
                     EVP_PKEY* issuer_key, long days);

/// `openssl smime -sign -text`: multipart/signed, the CA's certificate included.
std::string smime_signed(const std::string& document, X509* ca, EVP_PKEY* ca_key);

/// The governance document: every protection ENCRYPT (`encrypt`, SROS2's default) or SIGN.
std::string governance_xml(bool encrypt);
/// Throws sdk::Error(bad_request) unless `role` is site, robot or operator.
void check_role(const std::string& role);

/// The permissions of identity `name` in `role` (site, robot or operator; else
/// sdk::Error(bad_request)) for `namespaces` (empty: {name}, an operator's {"*"}), valid from a
/// day ago for `days`.
std::string permissions_xml(const std::string& name, const std::string& role,
                            const std::vector<std::string>& namespaces, long days);
/// `permissions` with its <validity> replaced: from a day ago for `days` (renew).
std::string with_validity(const std::string& permissions, long days);

/// The certificate revocation list at `path`, checked: PEM, signed by `ca` (else
/// sdk::Error(bad_config) naming the file).
ossl::Crl read_crl(const std::string& path, X509* ca);

/// The certificate's serial number in hexadecimal (as `openssl x509 -serial` prints it).
std::string serial_hex(X509* cert);

}  // namespace flipper::dds::pki
