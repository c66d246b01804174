#pragma once
/// @file event_signature.hpp
/// Site identity in the replication itself (docs/ros2.md, "Secured sites"): with
/// DDS Security on, every lexicon event carries the certificate of the site that made it and
/// that site's signature (ECDSA P-256, SHA-256) over the event's content (signed_text), so any
/// site may relay it (catch-up) and every site can tell who made it. An event is accepted only
/// when its certificate was issued by the keystore's CA and is not on its revocation list
/// (Keystore::revocation_list, dds.security.crl), the certificate's subject CN is the event's
/// site, and the signature verifies.

#include <map>
#include <memory>
#include <optional>
#include <string>

#include "flipper/dds/keystore.hpp"
#include "flipper/dds/lexicon_event.hpp"

namespace flipper::dds {

/// Signs this site's events with its identity key.
class EventSigner {
 public:
  /// Identity `name` of `keystore`; throws sdk::Error(bad_config) when its certificate's CN is
  /// not `name` or a file is missing.
  EventSigner(const Keystore& keystore, const std::string& name);
  ~EventSigner();
  EventSigner(const EventSigner&) = delete;
  EventSigner& operator=(const EventSigner&) = delete;
  /// Sets e.certificate and e.signature.
  void sign(LexiconEvent& e) const;

 private:
  struct Impl;
  std::unique_ptr<Impl> impl_;
};

/// Checks received events against the keystore's CA (certificates verified once, then cached).
class EventVerifier {
 public:
  /// Throws sdk::Error(bad_config) when the CA or the revocation list cannot be read, or the
  /// list is not signed by the CA.
  explicit EventVerifier(const Keystore& keystore);
  ~EventVerifier();
  EventVerifier(const EventVerifier&) = delete;
  EventVerifier& operator=(const EventVerifier&) = delete;
  /// Why `e` is not authentic, or nothing when it is.
  std::optional<std::string> why_not(const LexiconEvent& e);

 private:
  struct Impl;
  std::unique_ptr<Impl> impl_;
};

}  // namespace flipper::dds
