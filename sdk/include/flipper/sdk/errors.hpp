#pragma once
/// @file errors.hpp
/// The one exception type that crosses the plugin boundary. It carries a stable machine-readable
/// `code` (the protocol's error codes) and a message for a person. Exported from the SDK library
/// so that it is caught by type on both sides.

#include <stdexcept>
#include <string>

#include "flipper/sdk/export.hpp"
#include "flipper/sdk/stop.hpp"

namespace flipper::sdk {
inline namespace FLIPPER_ABI_NAMESPACE {

/// Stable error codes. They appear in protocol answers (`error.code`) and CLI messages; never
/// rename one, only add.
namespace codes {
inline constexpr const char* kBadConfig = "bad_config";
inline constexpr const char* kBadWorld = "bad_world";
inline constexpr const char* kBadProgram = "bad_program";  ///< canonical text that does not read
inline constexpr const char* kBadGrammar = "bad_grammar";
inline constexpr const char* kBadRequest = "bad_request";
inline constexpr const char* kPluginNotFound = "plugin_not_found";
inline constexpr const char* kPluginAbiMismatch = "plugin_abi_mismatch";
inline constexpr const char* kPluginLoadFailed = "plugin_load_failed";
inline constexpr const char* kPluginDuplicate = "plugin_duplicate";
inline constexpr const char* kPluginError = "plugin_error";  ///< a plugin call threw
inline constexpr const char* kExecution = "execution_error";
inline constexpr const char* kBudgetExceeded = "budget_exceeded";
inline constexpr const char* kInputTooLong = "input_too_long";
inline constexpr const char* kInternal = "internal";
// Limits on hostile input (docs/bad-input.md):
inline constexpr const char* kTooDeep = "too_deep";               ///< JSON nested too deep
inline constexpr const char* kWorldTooLarge = "world_too_large";  ///< more cells than allowed
inline constexpr const char* kFileTooLarge = "file_too_large";
inline constexpr const char* kNotARegularFile = "not_a_regular_file";  ///< a FIFO, device, dir
inline constexpr const char* kDeadlineExceeded =
    "deadline_exceeded";                                     ///< a time limit: StoppedError
inline constexpr const char* kWriteFailed = "write_failed";  ///< e.g. the device is full
}  // namespace codes

/// An error with a stable code. Plugins throw it (or any std::exception; the kernel wraps those
/// as `plugin_error` with the plugin id).
class FLIPPER_SDK_API Error : public std::runtime_error {
 public:
  Error(std::string code, const std::string& message);
  ~Error() override;
  /// The stable code, e.g. "bad_world".
  const std::string& code() const noexcept { return code_; }

 private:
  std::string code_;
};

/// `deadline_exceeded` naming the limit that fired: a CPU budget (`cpu_budget`) or the
/// wall-clock backstop (`wall_backstop`); answers carry it as `stopped` (docs/protocol.md).
class FLIPPER_SDK_API StoppedError : public Error {
 public:
  StoppedError(StopCause cause, const std::string& message);
  ~StoppedError() override;
  StopCause cause() const noexcept { return cause_; }

 private:
  StopCause cause_;
};
/// The cause of a StoppedError, or none for any other exception.
FLIPPER_SDK_API StopCause stop_cause_of(const std::exception& e) noexcept;

}  // namespace FLIPPER_ABI_NAMESPACE
}  // namespace flipper::sdk
