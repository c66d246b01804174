// Typed request fields.
#include <cmath>
#include <limits>
#include <nlohmann/json.hpp>

#include "flipper/kernel/session_request.hpp"
#include "flipper/sdk/errors.hpp"

namespace flipper::kernel::request {
namespace {

[[noreturn]] void wrong_type(const char* field, const char* expected, const char* what) {
  throw sdk::Error(sdk::codes::kBadRequest,
                   std::string("field '") + field + "' must be " + expected + " (" + what + ")");
}

}  // namespace

const Json& require(const Json& req, const char* field, const char* what) {
  auto it = req.find(field);
  if (it == req.end() || it->is_null())
    throw sdk::Error(session_codes::kMissingField,
                     std::string("missing field '") + field + "' (" + what + ")");
  return *it;
}

std::string require_string(const Json& req, const char* field, const char* what) {
  const Json& v = require(req, field, what);
  if (!v.is_string()) wrong_type(field, "a string", what);
  return v.get<std::string>();
}

std::int64_t require_int(const Json& req, const char* field, const char* what,
                         const char* out_of_range_code) {
  const Json& v = require(req, field, what);
  auto out_of_range = [&]() {
    throw sdk::Error(out_of_range_code != nullptr ? out_of_range_code : sdk::codes::kBadRequest,
                     std::string("field '") + field + "' is out of range: integers go from " +
                         std::to_string(std::numeric_limits<std::int64_t>::min()) + " to " +
                         std::to_string(std::numeric_limits<std::int64_t>::max()) + " (" + what +
                         ")");
  };
  constexpr auto kMax = static_cast<std::uint64_t>(std::numeric_limits<std::int64_t>::max());
  if (v.is_number_unsigned() && v.get<std::uint64_t>() > kMax) out_of_range();
  if (v.is_number_integer()) return v.get<std::int64_t>();
  // 2.0 is accepted as 2; 2.5 is not an integer. Casting a double beyond int64 is undefined:
  // compare against 2^63 first.
  if (v.is_number_float()) {
    const double d = v.get<double>();
    if (std::isfinite(d) && d == std::floor(d)) {
      if (d >= 0x1p63 || d < -0x1p63) out_of_range();
      return static_cast<std::int64_t>(d);
    }
  }
  wrong_type(field, "an integer", what);
}

std::optional<std::string> optional_string(const Json& req, const char* field, const char* what) {
  auto it = req.find(field);
  if (it == req.end() || it->is_null()) return std::nullopt;
  return require_string(req, field, what);
}

std::optional<std::int64_t> optional_int(const Json& req, const char* field, const char* what,
                                         const char* out_of_range_code) {
  auto it = req.find(field);
  if (it == req.end() || it->is_null()) return std::nullopt;
  return require_int(req, field, what, out_of_range_code);
}

}  // namespace flipper::kernel::request
