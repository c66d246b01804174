#pragma once
// The front-end modules of this tree (docs/architecture.md §1 "Front ends are modules"): `serve`
// (apps/studio, and the accounts it reads) and `dds` (apps/dds: the node, DDS Security keystores,
// the DDS services of a session) are plugins of kind `frontend` in <exe>/../lib/flipper/frontends,
// loaded by the plugin loader like any other (flipper/sdk/frontend.hpp) and run on a host
// (frontend_host.cpp). `flipper` itself links no network stack; a study run never maps them.
//
// Beyond sdk::FrontendHost, an in-tree module gets an InTreeCall from FrontendHost::internals:
// which command to run with which parsed options. It shares this flipper's kernel (flipper
// exports its symbols), so it must be of the same build: the tag says so, and a module of
// another build is refused (frontend_mismatch).
#include <memory>
#include <string>

#include "flipper/sdk/errors.hpp"

namespace flipper::wiring {
struct SessionHost;
}

namespace flipper::cli {

struct CommonOptions;
struct AccountsArgs;
struct DdsSecurityArgs;
struct DdsServices;

/// The hand-over's version: bump the number when InTreeCall changes.
inline constexpr const char* kInTreeTag = "flipper " FLIPPER_VERSION " frontends/3";

/// What flipper asks of an in-tree module. Pointers are flipper's, valid during the call.
struct InTreeCall {
  /// serve | accounts (serve's module); dds | dds security | dds services (dds's module).
  std::string command;
  const CommonOptions* opts = nullptr;        ///< serve, accounts, dds
  const AccountsArgs* accounts = nullptr;     ///< accounts
  const DdsSecurityArgs* security = nullptr;  ///< dds security
  std::string action;  ///< dds security: init | add | request | sign | renew | revoke | install
  wiring::SessionHost* host = nullptr;  ///< dds services: the session's host
  DdsServices* services = nullptr;      ///< dds services: filled in
};

/// Loads the in-tree module `module` and runs `call` on it; returns the command's exit status.
/// A missing or unloadable module is [frontend_missing] (exit 1), naming the file.
int run_in_tree(const std::string& module, InTreeCall& call);

/// The error of an in-tree module run by another build's flipper, or by `flipper frontend`.
/// Inline: the message states the module's own tag.
[[noreturn]] inline void refuse_foreign_host(const std::string& module) {
  throw sdk::Error("frontend_mismatch", "the front-end module '" + module + "' ('" + kInTreeTag +
                                            "') runs only under `flipper " + module +
                                            "` of the same build (a mixed install? reinstall "
                                            "flipper)");
}

}  // namespace flipper::cli
