// PGM decoding after netpbm's pgm(5): magic, whitespace-separated width, height and maxval with
// '#' comments to the end of a line, one whitespace character, then the raster.
#include "pgm.hpp"

#include <cctype>

#include "flipper/sdk/errors.hpp"

namespace flipper::plugins::ros_map {

namespace sdk = flipper::sdk;

namespace {

class Reader {
 public:
  Reader(std::string_view bytes, const std::string& name) : b_(bytes), name_(name) {}

  [[noreturn]] void fail(const std::string& what) const {
    throw sdk::Error(sdk::codes::kBadWorld, name_ + ": " + what);
  }

  void skip_space_and_comments() {
    while (pos_ < b_.size()) {
      const char c = b_[pos_];
      if (c == '#') {
        while (pos_ < b_.size() && b_[pos_] != '\n' && b_[pos_] != '\r') ++pos_;
      } else if (std::isspace(static_cast<unsigned char>(c)) != 0) {
        ++pos_;
      } else {
        return;
      }
    }
  }

  // A decimal header number of at most 10 digits, at most `max`.
  std::uint64_t number(const char* field, std::uint64_t max) {
    skip_space_and_comments();
    if (pos_ >= b_.size()) fail(std::string("truncated header: no ") + field);
    std::uint64_t v = 0;
    std::size_t digits = 0;
    while (pos_ < b_.size() && std::isdigit(static_cast<unsigned char>(b_[pos_])) != 0) {
      if (++digits > 10) fail(std::string(field) + " has too many digits");
      v = v * 10 + static_cast<std::uint64_t>(b_[pos_] - '0');
      ++pos_;
    }
    if (digits == 0) fail(std::string(field) + " is not a number");
    if (v > max)
      fail(std::string(field) + " " + std::to_string(v) + " is above " + std::to_string(max));
    return v;
  }

  std::size_t pos() const { return pos_; }
  void advance(std::size_t n) { pos_ += n; }
  std::string_view bytes() const { return b_; }

 private:
  std::string_view b_;
  const std::string& name_;
  std::size_t pos_ = 0;
};

}  // namespace

GreyImage decode_pgm(std::string_view bytes, const std::string& name, std::uint64_t max_cells,
                     const char* limit_name) {
  Reader r(bytes, name);
  if (bytes.size() < 2 || bytes[0] != 'P' || (bytes[1] != '5' && bytes[1] != '2'))
    r.fail("not a PGM image (the file must start with P5 or P2)");
  const bool plain = bytes[1] == '2';
  r.advance(2);
  GreyImage img;
  const std::uint64_t width = r.number("width", 0xFFFFFFFFu);
  const std::uint64_t height = r.number("height", 0xFFFFFFFFu);
  if (width == 0 || height == 0)
    r.fail("the image is empty (" + std::to_string(width) + " x " + std::to_string(height) + ")");
  if (width * height > max_cells)
    throw sdk::Error(sdk::codes::kWorldTooLarge,
                     name + ": " + std::to_string(width) + " x " + std::to_string(height) + " = " +
                         std::to_string(width * height) + " cells; the limit is " + limit_name +
                         " = " + std::to_string(max_cells));
  const std::uint64_t maxval = r.number("maxval", 65535);
  if (maxval == 0) r.fail("maxval is 0");
  img.width = static_cast<std::uint32_t>(width);
  img.height = static_cast<std::uint32_t>(height);
  img.maxval = static_cast<std::uint32_t>(maxval);
  const std::size_t count = static_cast<std::size_t>(width * height);
  if (plain) {
    img.pixels.reserve(count);
    for (std::size_t i = 0; i < count; ++i) {
      r.skip_space_and_comments();
      if (r.pos() >= bytes.size())
        r.fail("truncated: " + std::to_string(count) + " pixels expected, " + std::to_string(i) +
               " found");
      img.pixels.push_back(static_cast<std::uint16_t>(r.number("pixel", maxval)));
    }
    return img;
  }
  // Binary: exactly one whitespace character after maxval, then the raster.
  if (r.pos() >= bytes.size() || std::isspace(static_cast<unsigned char>(bytes[r.pos()])) == 0)
    r.fail("no whitespace after maxval");
  r.advance(1);
  const std::size_t sample = maxval > 255 ? 2 : 1;
  const std::size_t available = bytes.size() - r.pos();
  if (available < count * sample)
    r.fail("truncated: " + std::to_string(count * sample) + " bytes of pixels expected (" +
           std::to_string(width) + " x " + std::to_string(height) + (sample == 2 ? " x 2" : "") +
           "), " + std::to_string(available) + " found");
  img.pixels.resize(count);
  const auto* p = reinterpret_cast<const unsigned char*>(bytes.data() + r.pos());
  for (std::size_t i = 0; i < count; ++i) {
    const std::uint32_t v = sample == 2 ? (std::uint32_t{p[2 * i]} << 8) | p[2 * i + 1] : p[i];
    if (v > maxval)
      r.fail("pixel " + std::to_string(i) + " is " + std::to_string(v) + ", above maxval " +
             std::to_string(maxval));
    img.pixels[i] = static_cast<std::uint16_t>(v);
  }
  return img;
}

}  // namespace flipper::plugins::ros_map
