#include "flipper/sdk/errors.hpp"

namespace flipper::sdk {
inline namespace FLIPPER_ABI_NAMESPACE {
Error::Error(std::string code, const std::string& message)
    : std::runtime_error(message), code_(std::move(code)) {}
Error::~Error() = default;

StoppedError::StoppedError(StopCause cause, const std::string& message)
    : Error(codes::kDeadlineExceeded, message), cause_(cause) {}
StoppedError::~StoppedError() = default;

StopCause stop_cause_of(const std::exception& e) noexcept {
  const auto* stopped = dynamic_cast<const StoppedError*>(&e);
  return stopped != nullptr ? stopped->cause() : StopCause::none;
}
}  // namespace FLIPPER_ABI_NAMESPACE
}  // namespace flipper::sdk
