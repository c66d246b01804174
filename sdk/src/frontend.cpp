// Out-of-line destructors of the front-end interfaces (flipper/sdk/frontend.hpp): their vtables
// and typeinfo live once, in libflipper_sdk.so.
#include "flipper/sdk/frontend.hpp"

namespace flipper::sdk {
inline namespace v1 {

FrontendHost::~FrontendHost() = default;

}  // namespace v1
}  // namespace flipper::sdk
