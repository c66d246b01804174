// The DDS Security keystore (keystore.hpp): init, add, and what a participant reads from it; the
// certificates and signed documents are made by pki.cpp, the lab <-> CA commands are lab_keys.cpp.
#include "flipper/dds/keystore.hpp"

#include <dlfcn.h>

#include <dds/dds.h>

#include <algorithm>
#include <filesystem>
#include <ostream>

#include "flipper/dds/config_keys.hpp"
#include "flipper/dds/names.hpp"
#include "flipper/kernel/config.hpp"
#include "flipper/naturalization/config_keys.hpp"
#include "pki.hpp"

namespace flipper::dds {
namespace {

namespace fs = std::filesystem;
using pki::refuse;

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

void check_enclave(const std::string& enclave) {
  // SROS2's enclave names are absolute ROS 2 names: "/" then name tokens joined by "/".
  const std::string what = "dds.security.enclave '" + enclave.substr(0, 128) + "'";
  if (enclave.size() < 2 || enclave.front() != '/' || enclave.back() == '/' || enclave.size() > 256)
    refuse(sdk::codes::kBadConfig,
           what + " is not an SROS2 enclave name (/name[/name]..., e.g. /lab1/flipper)");
  std::size_t from = 1;
  while (from <= enclave.size()) {
    const std::size_t to = std::min(enclave.find('/', from), enclave.size());
    if (to == from) refuse(sdk::codes::kBadConfig, what + " has an empty part (/name[/name]...)");
    check_namespace(enclave.substr(from, to - from), "a part of " + what);
    from = to + 1;
  }
}

void init_keystore(const std::string& dir, std::ostream& out) {
  const Keystore ks{dir};
  std::error_code ec;
  if (fs::exists(ks.ca_certificate(), ec))
    refuse(sdk::codes::kBadRequest, "'" + dir + "' already holds a keystore (ca.pem)");
  fs::create_directories(dir + "/private", ec);
  if (ec) refuse("io_error", "cannot create '" + dir + "/private': " + ec.message());
  fs::permissions(dir + "/private", fs::perms::owner_all, ec);
  const ossl::Key key = pki::new_key();
  const ossl::Cert ca = pki::make_cert("Flipper DDS CA", key.get(), nullptr, nullptr, pki::kCaDays);
  out << "flipper dds security: a keystore in " << dir << ":\n";
  pki::write_text(ks.ca_key(), pki::key_pem(key.get()), true, out);
  pki::write_text(ks.ca_certificate(), ossl::cert_to_pem(ca.get()), false, out);
  // dds.security.protection chooses between the two (docs/ros2.md, "Protection").
  const std::string governance = pki::governance_xml(/*encrypt=*/true);
  pki::write_text(dir + "/governance.xml", governance, false, out);
  pki::write_text(ks.governance(), pki::smime_signed(governance, ca.get(), key.get()), false, out);
  const std::string sign_only = pki::governance_xml(/*encrypt=*/false);
  pki::write_text(dir + "/governance_sign.xml", sign_only, false, out);
  pki::write_text(ks.governance_sign(), pki::smime_signed(sign_only, ca.get(), key.get()), false,
                  out);
}

void add_identity(const std::string& dir, const std::string& name, const std::string& role,
                  const std::vector<std::string>& namespaces, long days, std::ostream& out) {
  const Keystore ks{dir};
  pki::check_role(role);
  check_namespace(name, "identity name");
  for (const auto& ns : namespaces) check_namespace(ns, "namespace");
  std::error_code ec;
  if (name.empty()) refuse(sdk::codes::kBadRequest, "an identity needs a name");
  if (!fs::exists(ks.ca_key(), ec))
    refuse(sdk::codes::kBadRequest, "no keystore in '" + dir + "' (flipper dds security init)");
  if (fs::exists(ks.identity_dir(name), ec))
    refuse(sdk::codes::kBadRequest, "the keystore already has identity '" + name + "'");
  const ossl::Cert ca = pki::read_cert(ks.ca_certificate());
  const ossl::Key ca_key = pki::read_key(ks.ca_key());
  fs::create_directories(ks.identity_dir(name), ec);
  if (ec) refuse("io_error", "cannot create '" + ks.identity_dir(name) + "': " + ec.message());
  const ossl::Key key = pki::new_key();
  const ossl::Cert cert = pki::make_cert(name, key.get(), ca.get(), ca_key.get(), days);
  const std::string permissions = pki::permissions_xml(name, role, namespaces, days);
  out << "flipper dds security: identity '" << name << "' in " << dir << ", valid " << days
      << " days:\n";
  pki::write_text(ks.private_key(name), pki::key_pem(key.get()), true, out);
  pki::write_text(ks.certificate(name), ossl::cert_to_pem(cert.get()), false, out);
  pki::write_text(ks.identity_dir(name) + "/permissions.xml", permissions, false, out);
  pki::write_text(ks.permissions(name), pki::smime_signed(permissions, ca.get(), ca_key.get()),
                  false, out);
}

void export_enclave(const std::string& dir, const std::string& name, const std::string& keystore,
                    const std::string& enclave, std::ostream& out) {
  const Keystore from{dir};
  const Keystore to{keystore, {}, enclave};
  check_namespace(name, "identity name");
  check_enclave(enclave);
  const std::string hint = "flipper dds security add, or install at a lab";
  for (const auto& f : {from.ca_certificate(), from.governance(), from.certificate(name),
                        from.private_key(name), from.permissions(name)})
    require_file(f, hint);
  std::error_code ec;
  if (fs::exists(to.enclave_dir(), ec))
    refuse(sdk::codes::kBadRequest, "'" + to.enclave_dir() + "' exists already");
  fs::create_directories(to.enclave_dir(), ec);
  if (ec) refuse("io_error", "cannot create '" + to.enclave_dir() + "': " + ec.message());
  out << "flipper dds security: identity '" << name << "' as the SROS2 enclave " << enclave
      << " of " << keystore << ":\n";
  const std::string ca = pki::read_text(from.ca_certificate());
  pki::write_text(to.ca_certificate(), ca, false, out);
  pki::write_text(to.permissions_ca(), ca, false, out);
  pki::write_text(to.governance(), pki::read_text(from.governance()), false, out);
  pki::write_text(to.certificate(name), pki::read_text(from.certificate(name)), false, out);
  pki::write_text(to.private_key(name), pki::read_text(from.private_key(name)), true, out);
  pki::write_text(to.permissions(name), pki::read_text(from.permissions(name)), false, out);
}

std::string Keystore::revocation_list() const {
  if (!crl.empty()) return crl;
  std::error_code ec;
  return fs::exists(crl_file(), ec) ? crl_file() : std::string();
}

std::vector<std::pair<std::string, std::string>> security_properties(const Keystore& ks,
                                                                     const std::string& name) {
  const std::string hint =
      ks.sros2() ? "an SROS2 enclave: ros2 security create_enclave " + ks.dir + " " + ks.enclave +
                       ", or flipper dds security export"
      : ks.sign_only
          ? "dds.security.protection: sign; keystores made before it have only governance.p7s"
          : "flipper dds security init DIR; flipper dds security add DIR " + name;
  for (const auto& f : {ks.ca_certificate(), ks.permissions_ca(), ks.governance(),
                        ks.certificate(name), ks.private_key(name), ks.permissions(name)})
    require_file(f, hint);
  const auto file = [](const std::string& path) {
    return "file:" + fs::absolute(path).lexically_normal().string();
  };
  std::vector<std::pair<std::string, std::string>> properties = {
      {"dds.sec.auth.library.path", plugin_path("dds_security_auth")},
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
      {"dds.sec.access.permissions_ca", file(ks.permissions_ca())},
      {"dds.sec.access.governance", file(ks.governance())},
      {"dds.sec.access.permissions", file(ks.permissions(name))}};
  if (const std::string crl = ks.revocation_list(); !crl.empty()) {
    const ossl::Cert ca = pki::read_cert(ks.ca_certificate());
    const ossl::Crl list = pki::read_crl(crl, ca.get());
    X509_REVOKED* entry = nullptr;
    if (X509_CRL_get0_by_cert(list.get(), &entry, pki::read_cert(ks.certificate(name)).get()) == 1)
      refuse(sdk::codes::kBadConfig, "DDS Security: the certificate of identity '" + name +
                                         "' is revoked by '" + crl +
                                         "' (the lab requests a new one)");
    // Cyclone 0.10's name for the CRL property (dds_security_api_defs.h,
    // ORG_ECLIPSE_CYCLONEDDS_SEC_AUTH_CRL): read at participant creation, so a new list takes
    // effect when the participant restarts.
    properties.emplace_back("org.eclipse.cyclonedds.sec.auth.crl", file(crl));
  }
  return properties;
}

std::optional<SecurityConfig> security_config(const kernel::Config& config) {
  const std::string dir = config.get(keys::kKeystore);
  if (dir.empty()) return std::nullopt;
  SecurityConfig sc{Keystore{dir, config.get(keys::kCrl), config.get(keys::kEnclave),
                             config.get(keys::kProtection) == keys::Protection::sign},
                    config.get(keys::kIdentity)};
  if (sc.keystore.sros2()) {
    check_enclave(sc.keystore.enclave);
    if (sc.keystore.sign_only)
      refuse(sdk::codes::kBadConfig,
             "dds.security.protection: sign is for Flipper's keystore layout; with "
             "dds.security.enclave the enclave's governance.p7s decides the protection");
  }
  if (!sc.keystore.crl.empty())
    require_file(sc.keystore.crl,
                 "dds.security.crl; the CA's `flipper dds security revoke` "
                 "writes its crl.pem");
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
  return ossl::common_name(pki::read_cert(pem_path).get());
}

}  // namespace flipper::dds
