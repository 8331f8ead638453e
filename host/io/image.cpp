#include "io/image.hpp"

#include <algorithm>
#include <cmath>
#include <string_view>

#include "io/atomic_file.hpp"
#include "io/image_codec.hpp"
#include "runtime/error.hpp"

namespace splatcl {

void write_image_rgb(const std::string& path, int width, int height, const std::vector<float>& rgb) {
  if (width <= 0 || height <= 0 || rgb.size() != static_cast<std::size_t>(width) * static_cast<std::size_t>(height) * 3)
    throw Error("cannot write " + path + ": image size does not match its data");
  // Encoded in memory, then written like every other output: each write and the close checked.
  const std::vector<unsigned char> encoded = encode_image_rgb(path, width, height, rgb);
  write_file_atomically(path, std::string_view(reinterpret_cast<const char*>(encoded.data()), encoded.size()));
}

std::array<float, 3> heat_color(float t) {
  static constexpr std::array<std::array<float, 3>, 5> stops = {{
      {0.05f, 0.05f, 0.35f}, {0.0f, 0.55f, 0.85f}, {0.2f, 0.85f, 0.45f}, {0.98f, 0.85f, 0.1f}, {0.85f, 0.1f, 0.05f}}};
  if (!(t > 0.0f)) return stops.front();
  if (t >= 1.0f) return stops.back();
  const float x = t * static_cast<float>(stops.size() - 1);
  const auto i = static_cast<std::size_t>(x);
  const float f = x - static_cast<float>(i);
  std::array<float, 3> c{};
  for (int k = 0; k < 3; ++k) c[k] = stops[i][k] * (1 - f) + stops[i + 1][k] * f;
  return c;
}

}  // namespace splatcl
