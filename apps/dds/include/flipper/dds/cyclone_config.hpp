#pragma once
/// @file cyclone_config.hpp
/// A Cyclone DDS configuration as Cyclone 0.10.2 itself reads it (docs/ros2.md,
/// "Loopback by default"), so the loopback rule checks what Cyclone will use, not what the text
/// seems to say:
///   - the text is a list of items, as in CYCLONEDDS_URI: an XML item (starting with `<`) runs to
///     the end of its top-level element, and more items may follow it (after a comma, blanks or
///     nothing); any other item runs to the next comma and names a file (`file://` prefix
///     optional), whose content is read here and handed to Cyclone in its place (so the file
///     Cyclone reads is the file that was checked);
///   - XML is parsed with Cyclone's own parser (ddsrt_xmlp, exported by libddsc): comments,
///     CDATA and the anonymous close tag `</>` mean what they mean to Cyclone;
///   - element and attribute names are matched without regard to case, and every element is
///     looked at wherever it sits (a `Domain` for another id included), as Cyclone moves
///     misplaced sections into `Domain` and matches ids leniently.
/// Anything the check cannot prove loopback-only is refused (sdk::Error bad_config).

#include <string>
#include <vector>

namespace flipper::dds {

/// One XML element of a configuration (names as written).
struct XmlElement {
  std::string name;
  std::vector<std::pair<std::string, std::string>> attributes;
  std::string text;  ///< character data directly inside (comments excluded)
  std::vector<XmlElement> children;
  /// The attribute's value (name matched without case), or nullptr.
  const std::string* attribute(const std::string& attr) const;
};

/// A configuration resolved the way Cyclone resolves it.
struct CycloneConfig {
  std::vector<std::string> items;  ///< each item's XML (files replaced by their content)
  std::vector<XmlElement> roots;   ///< the top-level elements of every item, in order
  /// The items joined into one configuration string for dds_create_domain.
  std::string text() const;
};

/// Resolves `uri` (an XML string or a list of items); `source` names it in errors
/// ("CYCLONEDDS_URI", "dds.config"). Throws sdk::Error(bad_config) for an item that cannot be
/// read or parsed.
CycloneConfig resolve_cyclone_config(const std::string& uri, const std::string& source);

/// A loopback address literal: 127.0.0.0/8 or ::1, bracketed or not (never a host name, which
/// could resolve elsewhere).
bool loopback_address(std::string address);

/// What a resolved configuration selects for domain `domain`.
struct NetworkSelection {
  std::vector<std::string> interfaces;  ///< names or addresses, every Domain's (any id)
  bool selects_for_domain = false;      ///< a NetworkInterface applies to `domain` itself
  std::vector<std::string> peers;       ///< discovery peer addresses (host part)
  std::vector<std::string> unprovable;  ///< settings the loopback check cannot vouch for
};
NetworkSelection network_selection(const CycloneConfig& config, int domain);

}  // namespace flipper::dds
