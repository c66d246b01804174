#pragma once
/// @file thrown_code.hpp
/// The code of the sdk::Error a call throws, for tests that check a refusal by its stable code
/// (docs/protocol.md "Errors").
#include <string>
#include <utility>

#include "flipper/sdk/errors.hpp"

namespace flipper::testsupport {

/// The code of the sdk::Error `f` throws; "" when it returns (other exceptions propagate).
template <class F>
std::string thrown_code(F&& f) {
  try {
    std::forward<F>(f)();
  } catch (const flipper::sdk::Error& e) {
    return e.code();
  }
  return "";
}

}  // namespace flipper::testsupport
