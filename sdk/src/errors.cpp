#include "flipper/sdk/errors.hpp"

namespace flipper::sdk {
inline namespace v1 {
Error::Error(std::string code, const std::string& message)
    : std::runtime_error(message), code_(std::move(code)) {}
Error::~Error() = default;
}  // namespace v1
}  // namespace flipper::sdk
