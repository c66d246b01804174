#pragma once
/// @file lab_keys.hpp
/// Labs that own their keys (docs/ros2.md, "Labs that keep their keys"): a lab makes its key and
/// a certificate signing request (CSR); the project's CA checks the request and issues the
/// certificate and the signed permissions, which the lab installs next to its key. The key never
/// leaves the lab's keystore folder. Both folders have the layout of keystore.hpp.
///
///   lab: request_identity(LAB, NAME)        -> LAB/identities/NAME/key.pem (0600), NAME.csr
///   CA:  sign_request(CA, NAME.csr, NS...)  -> CA/identities/NAME/, CA/outbox/NAME/
///   lab: install_identity(LAB, NAME, OUTBOX) -> LAB/ca.pem, governance.p7s,
///                                              identities/NAME/cert.pem, permissions.p7s
///   CA:  renew_identity(CA, NAME)           -> a new certificate for the same key
///   CA:  revoke_identity(CA, NAME)          -> CA/crl.pem, signed by the CA, names every
///                                              certificate NAME was issued; CA/revoked/
///
/// Every refusal is sdk::Error(bad_request) (bad_config for a name that is not a ROS 2 name
/// token) naming what is wrong; nothing is written before every check passed.

#include <ostream>
#include <string>
#include <vector>

namespace flipper::dds {

/// The lab's side: a new P-256 key for identity `name` in `dir` (created if missing) and a CSR
/// whose subject is exactly CN=`name`, signed by that key. Returns the CSR's path. Refuses a
/// name that is not a ROS 2 name token, and an identity that already has a key in `dir`.
std::string request_identity(const std::string& dir, const std::string& name, std::ostream& out);

/// The CA's side: checks the CSR at `csr_path` (a PEM CSR; its signature verifies with its own
/// key; a P-256 EC or 2048-bit RSA key; its subject exactly one CN, a ROS 2 name token, not yet
/// an identity of the keystore `ca_dir`), then issues its certificate and the permissions of
/// `role` for `namespaces` (as add_identity: keystore.hpp), valid `days` days, and fills the
/// outbox. Returns the name.
std::string sign_request(const std::string& ca_dir, const std::string& csr_path,
                         const std::string& role, const std::vector<std::string>& namespaces,
                         long days, std::ostream& out);

/// The CA's side: a new certificate (new serial) for identity `name`'s key, and its permissions
/// with a new validity, `days` days from now; the old certificate moves to previous/. Refuses
/// an identity whose certificate has expired (the lab requests again).
void renew_identity(const std::string& ca_dir, const std::string& name, long days,
                    std::ostream& out);

/// The CA's side: adds every certificate identity `name` holds (cert.pem and previous/) to the
/// CA's revocation list (crl.pem, kept with the entries it had, signed anew, valid until the CA
/// expires) and moves the identity's folder to revoked/NAME-SERIAL, so NAME may be signed again
/// (a new key). Returns the CRL's path.
std::string revoke_identity(const std::string& ca_dir, const std::string& name, std::ostream& out);

/// The lab's side: checks what the CA sent (folder `from`: cert.pem issued by from/ca.pem for
/// CN=`name` and this lab's key, permissions.p7s and governance.p7s signed by that CA, crl.pem
/// when present signed by it; `dir`'s ca.pem, if any, the same CA) and copies it into `dir`.
void install_identity(const std::string& dir, const std::string& name, const std::string& from,
                      std::ostream& out);

}  // namespace flipper::dds
