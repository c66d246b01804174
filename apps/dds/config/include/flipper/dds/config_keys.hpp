#pragma once
/// @file config_keys.hpp
/// The DDS front end's config keys (docs/config.md "Who declares a key"; docs/ros2.md): the
/// participant (`dds.*`) and what it publishes (`publish.*`), declared here with the SDK's typed
/// handles and nowhere else. config_schema() is this layer's schema fragment, which the host
/// composes with the kernel's before it loads a config. Header-only.

#include <cstdint>

#include "flipper/sdk/config_handles.hpp"

namespace flipper::dds::keys {

namespace param = sdk::param;

/// publish.plans
enum class Plans { none, dds };

inline constexpr param::Choice<Plans, 2> kPublishPlans{
    "publish.plans", Plans::none, {"none", "dds"}, "publish each accepted plan"};
inline constexpr param::Int<std::int64_t> kDomain{"dds.domain", 0, 0, 232, "DDS domain id"};
inline constexpr param::TextList<0> kInterfaces{
    "dds.interfaces", {}, "network interfaces (empty: loopback only)"};
inline constexpr param::Text kConfig{"dds.config", "",
                                     "a Cyclone DDS XML config (empty: the built-in one)"};
inline constexpr param::Text kNamespace{
    "dds.namespace", "",
    "this node's ROS 2 namespace: topics rt/<namespace>/flipper/... (empty: rt/flipper/...)"};
inline constexpr param::Path kKeystore{
    "dds.security.keystore", "",
    "DDS Security: the folder of `flipper dds security init` (empty: security off)"};
inline constexpr param::Text kIdentity{
    "dds.security.identity", "",
    "DDS Security: this participant's identity in the keystore (empty: lexicon.site, else "
    "dds.namespace)"};
inline constexpr param::Path kCrl{
    "dds.security.crl", "",
    "DDS Security: the CA's revocation list (`flipper dds security revoke`), honoured by the "
    "handshake and the lexicon event check (empty: <keystore>/crl.pem when it exists)"};
inline constexpr param::Text kEnclave{
    "dds.security.enclave", "",
    "DDS Security: an SROS2 keystore's enclave (/lab1/flipper): its files in "
    "<keystore>/enclaves/<enclave>/ (empty: Flipper's own layout)"};
/// dds.security.protection: which of Flipper's governance documents a participant uses.
enum class Protection { sign, encrypt };
inline constexpr param::Choice<Protection, 2> kProtection{
    "dds.security.protection",
    Protection::encrypt,
    {"sign", "encrypt"},
    "DDS Security: RTPS messages, data and metadata signed, or encrypted as SROS2's default "
    "(Flipper's keystore: governance_sign.p7s or governance.p7s)"};

/// nav2.distro: which ROS 2 distribution's NavigateThroughPoses result the Nav2 stack speaks.
enum class Nav2Distro { humble, jazzy };

inline constexpr param::Bool kNav2Execute{
    "nav2.execute", false,
    "send each accepted plan to Nav2 as a NavigateThroughPoses goal (docs/ros2.md)"};
inline constexpr param::Choice<Nav2Distro, 2> kNav2Distro{
    "nav2.distro",
    Nav2Distro::humble,
    {"humble", "jazzy"},
    "the Nav2 stack's ROS 2 distribution (result layout: humble empty, jazzy error_code)"};
inline constexpr param::Text kNav2Action{
    "nav2.action", "navigate_through_poses",
    "the action's name under dds.namespace: rq/<namespace>/<action>/_action/..."};
inline constexpr param::Text kNav2BehaviorTree{
    "nav2.behavior_tree", "", "the goal's behavior_tree (empty: the navigator's default)"};

/// The schema fragment: the sections `publish`, `dds` and `nav2`.
inline sdk::ParamSchema config_schema() {
  sdk::ParamSchema s;
  s.add_section("publish", "what the DDS front end publishes");
  param::add(s, kPublishPlans);
  s.add_section("dds", "Cyclone DDS (flipper dds; loopback-only by default)");
  param::add(s, kDomain);
  param::add(s, kInterfaces);
  param::add(s, kConfig);
  param::add(s, kNamespace);
  param::add(s, kKeystore);
  param::add(s, kIdentity);
  param::add(s, kCrl);
  param::add(s, kEnclave);
  param::add(s, kProtection);
  s.add_section("nav2", "Nav2 as the executor of accepted plans (NavigateThroughPoses over DDS)");
  param::add(s, kNav2Execute);
  param::add(s, kNav2Distro);
  param::add(s, kNav2Action);
  param::add(s, kNav2BehaviorTree);
  return s;
}

}  // namespace flipper::dds::keys
