#include "bounded_file.hpp"

#include <filesystem>
#include <fstream>

#include "flipper/sdk/errors.hpp"

namespace flipper::plugins::ros_map {

namespace sdk = flipper::sdk;
namespace fs = std::filesystem;

std::string read_bounded_file(const std::string& path, std::uint64_t max_bytes,
                              const std::string& what, const char* limit_name) {
  // stat, not open: opening a FIFO without a writer blocks.
  std::error_code ec;
  const auto status = fs::status(path, ec);
  if (ec || !fs::exists(status))
    throw sdk::Error(sdk::codes::kBadWorld, what + ": cannot read file " + path);
  if (!fs::is_regular_file(status))
    throw sdk::Error(sdk::codes::kNotARegularFile, what + ": " + path + " is not a regular file");
  const std::uintmax_t size = fs::file_size(path, ec);
  if (ec || size > max_bytes)
    throw sdk::Error(sdk::codes::kFileTooLarge, what + ": " + path + " has " +
                                                    std::to_string(size) + " bytes; the limit is " +
                                                    limit_name + " = " + std::to_string(max_bytes));
  std::ifstream in(path, std::ios::binary);
  if (!in) throw sdk::Error(sdk::codes::kBadWorld, what + ": cannot read file " + path);
  std::string bytes(static_cast<std::size_t>(size), '\0');
  in.read(bytes.data(), static_cast<std::streamsize>(size));
  // A file that shrank while read is refused; one that grew is read up to its size at stat.
  if (in.gcount() != static_cast<std::streamsize>(size))
    throw sdk::Error(sdk::codes::kBadWorld, what + ": " + path + " changed while it was read");
  return bytes;
}

}  // namespace flipper::plugins::ros_map
