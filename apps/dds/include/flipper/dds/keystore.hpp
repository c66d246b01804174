#pragma once
/// @file keystore.hpp
/// DDS Security for sites and robots (docs/ros2.md, "Secured sites"): a keystore
/// folder of Flipper's layout (below), or an SROS2 keystore's enclave (Keystore::enclave), made
/// with OpenSSL (libcrypto), read by Cyclone's OMG DDS Security plugins (libdds_security_auth, _ac,
/// _crypto) and by the lexicon replication:
///
///   DIR/ca.pem                   the project CA: issues identities, signs governance and
///                                permissions (identity CA and permissions CA in one, as SROS2's
///                                default keystore)
///   DIR/private/ca.key           its key (keep it off the robots)
///   DIR/governance.xml, .p7s     domains 0..230: only authenticated participants join, every
///                                topic's readers and writers are access-controlled, discovery,
///                                liveliness, RTPS messages, metadata and data encrypted (SROS2's
///                                default); governance_sign.xml, .p7s the same, all signed only
///                                (dds.security.protection)
///   DIR/identities/NAME/         one per site or robot: cert.pem (subject CN=NAME), key.pem,
///                                permissions.xml and its signed permissions.p7s; at a CA that
///                                signed a lab's request, no key.pem (the lab keeps it) but
///                                NAME.csr, and previous/ (renewed certificates)
///   DIR/outbox/NAME/             at the CA: what lab NAME installs (lab_keys.hpp)
///   DIR/crl.pem                  the CA's revocation list (revoke); DIR/revoked/ at the CA
///                                holds the revoked identities' folders
///
/// Permissions by role (docs/ros2.md, "Roles"), for namespaces NS (default: NAME; an
/// operator's default: every namespace, `*`):
///   site      publish rt/flipper/lexicon, rt/NS/flipper/{plan,actions,answer}
///             subscribe rt/flipper/lexicon, rt/NS/flipper/request
///   robot     publish rt/NS/flipper/{plan,actions,answer}; subscribe rt/NS/flipper/request;
///             Nav2's client, A = NS/navigate_through_poses/_action/: publish
///             rq/A{send_goal,get_result,cancel_goal}Request, subscribe rr/A...Reply,
///             rt/A{feedback,status}
///   operator  publish rt/NS/flipper/request; subscribe rt/NS/flipper/{plan,actions,answer},
///             rt/A{feedback,status}
/// so only NAME may serve NAME's robot (answer its requests, publish its plans), only sites
/// replicate the lexicon (whose events carry their site's signature: event_signature.hpp), and
/// only operators send requests. Every reader of rt/NS/flipper/answer sees every answer there.

#include <optional>
#include <string>
#include <utility>
#include <vector>

namespace flipper::kernel {
class Config;
}

namespace flipper::dds {

struct Keystore {
  std::string dir;
  /// dds.security.crl: the revocation list to honour ("": crl_file() when it exists).
  std::string crl = {};
  /// dds.security.enclave: an SROS2 keystore's enclave ("/lab1/flipper"). When set, a
  /// participant's files are SROS2's, in enclave_dir(), whatever the identity's name:
  /// identity_ca.cert.pem, permissions_ca.cert.pem, governance.p7s, cert.pem, key.pem,
  /// permissions.p7s (docs/ros2.md, "SROS2 keystores").
  std::string enclave = {};
  /// dds.security.protection: sign reads governance_sign.p7s (Flipper's layout only).
  bool sign_only = false;

  bool sros2() const { return !enclave.empty(); }
  std::string enclave_dir() const { return dir + "/enclaves" + enclave; }
  /// The identity CA (authentication), also the one the lexicon event check trusts.
  std::string ca_certificate() const {
    return sros2() ? enclave_dir() + "/identity_ca.cert.pem" : dir + "/ca.pem";
  }
  /// The CA that signed the governance and permissions.
  std::string permissions_ca() const {
    return sros2() ? enclave_dir() + "/permissions_ca.cert.pem" : dir + "/ca.pem";
  }
  std::string ca_key() const { return dir + "/private/ca.key"; }
  std::string governance() const {
    return sros2()     ? enclave_dir() + "/governance.p7s"
           : sign_only ? dir + "/governance_sign.p7s"
                       : dir + "/governance.p7s";
  }
  /// The signed governance of protection `sign` (init writes both).
  std::string governance_sign() const { return dir + "/governance_sign.p7s"; }
  std::string identity_dir(const std::string& name) const {
    return sros2() ? enclave_dir() : dir + "/identities/" + name;
  }
  std::string certificate(const std::string& name) const {
    return identity_dir(name) + "/cert.pem";
  }
  std::string private_key(const std::string& name) const { return identity_dir(name) + "/key.pem"; }
  std::string permissions(const std::string& name) const {
    return identity_dir(name) + "/permissions.p7s";
  }
  /// A lab's certificate signing request (lab_keys.hpp request_identity).
  std::string request(const std::string& name) const {
    return identity_dir(name) + "/" + name + ".csr";
  }
  /// What the CA sends back to lab NAME (sign, renew): ca.pem, governance.p7s, cert.pem,
  /// permissions.p7s (and crl.pem when there is one).
  std::string outbox(const std::string& name) const { return dir + "/outbox/" + name; }
  /// The CA's certificate revocation list (lab_keys.hpp revoke_identity); at a lab, its copy.
  std::string crl_file() const { return dir + "/crl.pem"; }
  /// The CRL participants and the event check honour: `crl`, else crl_file() when it exists,
  /// else "" (nothing revoked).
  std::string revocation_list() const;
};

/// Throws sdk::Error(bad_config) unless `enclave` is an SROS2 enclave name: "/" then ROS 2 name
/// tokens (names.hpp) joined by "/", e.g. /lab1/flipper.
void check_enclave(const std::string& enclave);

/// Highest DDS domain the governance and permissions cover (Cyclone's limit for them).
inline constexpr int kMaxSecureDomain = 230;

/// Creates the CA, the governance document and its signed copy in `dir` (created if missing;
/// throws sdk::Error(bad_request) when it already holds a keystore). Lines of what was written
/// go to `out`.
void init_keystore(const std::string& dir, std::ostream& out);

/// Adds identity `name` (a ROS 2 name token: names.hpp) with its certificate, key and signed
/// permissions of `role` (site, robot or operator, below) for `namespaces` (empty: {name}; an
/// operator's: every robot), valid `days` days. Throws
/// sdk::Error(bad_request) when the keystore is missing or already has `name`. (A lab that keeps
/// its own key uses request_identity and the CA sign_request instead: lab_keys.hpp.)
void add_identity(const std::string& dir, const std::string& name, const std::string& role,
                  const std::vector<std::string>& namespaces, long days, std::ostream& out);

/// Writes identity `name` of keystore `dir` (its CA, governance, certificate, key, permissions)
/// as the SROS2 enclave `enclave` of the SROS2 keystore `keystore` (created if missing), in the
/// files ros2 security create_enclave writes. Throws sdk::Error(bad_request) when the enclave
/// exists, sdk::Error(bad_config) naming a missing file.
void export_enclave(const std::string& dir, const std::string& name, const std::string& keystore,
                    const std::string& enclave, std::ostream& out);

/// The DDS Security participant QoS properties (dds.sec.*) for identity `name` of `keystore`:
/// plugins, CA, certificate, key, governance, permissions, and the CRL when there is one
/// (Cyclone 0.10's org.eclipse.cyclonedds.sec.auth.crl). Throws sdk::Error(bad_config) naming a
/// missing file, a CRL the CA did not sign, or `name`'s own certificate revoked.
std::vector<std::pair<std::string, std::string>> security_properties(const Keystore& keystore,
                                                                     const std::string& name);

/// DDS Security as the config asks for it: the keystore (dds.security.keystore) and this
/// participant's identity (dds.security.identity, else lexicon.site, else dds.namespace).
struct SecurityConfig {
  Keystore keystore;
  std::string identity;
};
/// Nothing when dds.security.keystore is empty (security off). Throws sdk::Error(bad_config)
/// when no identity can be named or dds.domain is above kMaxSecureDomain.
std::optional<SecurityConfig> security_config(const kernel::Config& config);

/// The common name (CN) of a PEM certificate's subject; throws sdk::Error(bad_config).
std::string certificate_common_name(const std::string& pem_path);

}  // namespace flipper::dds
