// Out-of-line destructors of the front-end interfaces (flipper/sdk/frontend.hpp): their vtables
// and typeinfo live once, in libflipper_sdk.so.
#include "flipper/sdk/frontend.hpp"

namespace flipper::sdk {
inline namespace FLIPPER_ABI_NAMESPACE {

FrontendHost::~FrontendHost() = default;

}  // namespace FLIPPER_ABI_NAMESPACE
}  // namespace flipper::sdk
