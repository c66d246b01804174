#pragma once
/// @file session_request.hpp
/// Typed access to request fields with the protocol's errors: a missing field is `missing_field`,
/// a field of the wrong type is `bad_request`; both messages name the field and what was expected.
/// Shared by every op handler (also those other modules install).

#include <cstdint>
#include <optional>
#include <string>
#include <vector>

#include "flipper/kernel/session.hpp"

namespace flipper::kernel::request {

/// The field's value; throws missing_field when absent (or null).
const Json& require(const Json& req, const char* field, const char* what);
std::string require_string(const Json& req, const char* field, const char* what);
/// An integer (2.0 counts as 2). A whole number beyond 64 bits (a 20-digit integer, 1e300) is
/// refused with `out_of_range_code` (default bad_request), never wrapped or saturated.
std::int64_t require_int(const Json& req, const char* field, const char* what,
                         const char* out_of_range_code = nullptr);
std::optional<std::string> optional_string(const Json& req, const char* field, const char* what);
std::optional<std::int64_t> optional_int(const Json& req, const char* field, const char* what,
                                         const char* out_of_range_code = nullptr);

}  // namespace flipper::kernel::request
