#include "io/image.hpp"

#include <OpenImageIO/filesystem.h>
#include <OpenImageIO/imageio.h>

#include <algorithm>
#include <cmath>
#include <filesystem>
#include <string_view>

#include "io/atomic_file.hpp"
#include "runtime/error.hpp"

namespace splatcl {

void write_image_rgb(const std::string& path, int width, int height, const std::vector<float>& rgb) {
  if (width <= 0 || height <= 0 || rgb.size() != static_cast<std::size_t>(width) * static_cast<std::size_t>(height) * 3)
    throw Error("cannot write " + path + ": image size does not match its data");
  // OpenImageIO picks the format from the extension and encodes into memory; the bytes then go
  // through write_file_atomically like every other output, which checks each write and the close.
  // (OpenImageIO's own PNG file writer reports success on a full disk: the file lands truncated.)
  const std::string extension = std::filesystem::path(path).extension().string();
  auto out = OIIO::ImageOutput::create(path);
  if (!out) throw Error("cannot write " + path + ": no image format for '" + extension + "'");
  if (!out->supports("ioproxy")) throw Error("cannot write " + path + ": the '" + extension + "' writer cannot encode into memory");
  std::vector<unsigned char> encoded;
  OIIO::Filesystem::IOVecOutput memory(encoded);
  out->set_ioproxy(&memory);
  const bool is_float = extension == ".exr" || extension == ".hdr";
  OIIO::ImageSpec spec(width, height, 3, is_float ? OIIO::TypeDesc::HALF : OIIO::TypeDesc::UINT8);
  if (!out->open(path, spec)) throw Error("cannot write " + path + ": " + out->geterror());
  const std::size_t row = static_cast<std::size_t>(width) * 3;
  // Start at the last row with a negative stride: files are top-down, our buffers bottom-up.
  const float* last_row = rgb.data() + row * static_cast<std::size_t>(height - 1);
  const bool ok = out->write_image(OIIO::TypeDesc::FLOAT, last_row, OIIO::AutoStride, -static_cast<OIIO::stride_t>(row * sizeof(float)));
  if (!ok || !out->close()) throw Error("cannot write " + path + ": " + out->geterror());
  out.reset();
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
