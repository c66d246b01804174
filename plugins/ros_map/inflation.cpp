#include "inflation.hpp"

#include <limits>

namespace flipper::plugins::ros_map {

namespace {

constexpr double kInf = std::numeric_limits<double>::infinity();

// One dimension: d[q] = min_p (q - p)^2 + f[p], by the lower envelope of parabolas.
void transform_1d(const std::vector<double>& f, std::vector<double>& d, std::vector<int>& v,
                  std::vector<double>& z) {
  const int n = static_cast<int>(f.size());
  int k = -1;
  for (int q = 0; q < n; ++q) {
    if (f[q] == kInf) continue;
    while (k >= 0) {
      const double s =
          ((f[q] + double(q) * q) - (f[v[k]] + double(v[k]) * v[k])) / (2.0 * q - 2.0 * v[k]);
      if (s <= z[k]) {
        --k;
      } else {
        break;
      }
    }
    ++k;
    v[k] = q;
    z[k] = k == 0 ? -kInf
                  : ((f[q] + double(q) * q) - (f[v[k - 1]] + double(v[k - 1]) * v[k - 1])) /
                        (2.0 * q - 2.0 * v[k - 1]);
    z[k + 1] = kInf;
  }
  if (k < 0) {
    for (int q = 0; q < n; ++q) d[q] = kInf;
    return;
  }
  int j = 0;
  for (int q = 0; q < n; ++q) {
    while (z[j + 1] < q) ++j;
    const double dq = double(q) - v[j];
    d[q] = dq * dq + f[v[j]];
  }
}

}  // namespace

std::vector<double> squared_distances(const std::vector<std::uint8_t>& sources, std::uint32_t width,
                                      std::uint32_t height) {
  const std::size_t w = width, h = height;
  std::vector<double> out(w * h);
  for (std::size_t i = 0; i < out.size(); ++i) out[i] = sources[i] != 0 ? 0.0 : kInf;
  const std::size_t longest = w > h ? w : h;
  std::vector<double> f(longest), d(longest), z(longest + 1);
  std::vector<int> v(longest);
  // Columns, then rows.
  f.resize(h);
  d.resize(h);
  for (std::size_t x = 0; x < w; ++x) {
    for (std::size_t y = 0; y < h; ++y) f[y] = out[x + w * y];
    transform_1d(f, d, v, z);
    for (std::size_t y = 0; y < h; ++y) out[x + w * y] = d[y];
  }
  f.resize(w);
  d.resize(w);
  for (std::size_t y = 0; y < h; ++y) {
    for (std::size_t x = 0; x < w; ++x) f[x] = out[x + w * y];
    transform_1d(f, d, v, z);
    for (std::size_t x = 0; x < w; ++x) out[x + w * y] = d[x];
  }
  return out;
}

}  // namespace flipper::plugins::ros_map
