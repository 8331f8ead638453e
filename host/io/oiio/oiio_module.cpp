#include "io/oiio/oiio_module.h"

#include <OpenImageIO/filesystem.h>
#include <OpenImageIO/imageio.h>

#include <algorithm>
#include <cstring>
#include <exception>
#include <filesystem>
#include <string>
#include <vector>

namespace {

int fail(const std::string& message, char* error, size_t error_size) {
  if (error_size > 0) {
    const size_t n = std::min(message.size(), error_size - 1);
    std::memcpy(error, message.data(), n);
    error[n] = '\0';
  }
  return 1;
}

}  // namespace

extern "C" int splatcl_oiio_encode_rgb(const char* path, int width, int height, const float* rgb, void* sink,
                                       void (*append)(void* sink, const unsigned char* bytes, size_t size), char* error,
                                       size_t error_size) {
  try {
    // OpenImageIO picks the format from the extension and encodes into memory; the caller writes
    // the bytes atomically. (OpenImageIO's own PNG file writer reports success on a full disk and
    // leaves the file truncated.)
    const std::string extension = std::filesystem::path(path).extension().string();
    auto out = OIIO::ImageOutput::create(path);
    if (!out) return fail("no image format for '" + extension + "'", error, error_size);
    if (!out->supports("ioproxy")) return fail("the '" + extension + "' writer cannot encode into memory", error, error_size);
    std::vector<unsigned char> encoded;
    OIIO::Filesystem::IOVecOutput memory(encoded);
    out->set_ioproxy(&memory);
    // Linear radiance in 32-bit floats: half floats turned light above 65504 into +inf.
    const bool is_float = extension == ".exr" || extension == ".hdr";
    OIIO::ImageSpec spec(width, height, 3, is_float ? OIIO::TypeDesc::FLOAT : OIIO::TypeDesc::UINT8);
    if (!out->open(path, spec)) return fail(out->geterror(), error, error_size);
    const std::size_t row = static_cast<std::size_t>(width) * 3;
    // Start at the last row with a negative stride: files are top-down, the buffers bottom-up.
    const float* last_row = rgb + row * static_cast<std::size_t>(height - 1);
    const bool ok = out->write_image(OIIO::TypeDesc::FLOAT, last_row, OIIO::AutoStride, -static_cast<OIIO::stride_t>(row * sizeof(float)));
    if (!ok || !out->close()) return fail(out->geterror(), error, error_size);
    out.reset();
    append(sink, encoded.data(), encoded.size());
    return 0;
  } catch (const std::exception& e) {
    return fail(e.what(), error, error_size);
  }
}

extern "C" int splatcl_oiio_decode_u8(const char* path, void* sink,
                                      unsigned char* (*allocate)(void* sink, int width, int height, int channels),
                                      char* error, size_t error_size) {
  try {
    auto input = OIIO::ImageInput::open(path);
    if (!input) return fail(OIIO::geterror(), error, error_size);
    const OIIO::ImageSpec& spec = input->spec();
    if (spec.width <= 0 || spec.height <= 0 || spec.nchannels <= 0) return fail("the image is empty", error, error_size);
    unsigned char* pixels = allocate(sink, spec.width, spec.height, spec.nchannels);
    if (!input->read_image(0, 0, 0, spec.nchannels, OIIO::TypeDesc::UINT8, pixels)) return fail(input->geterror(), error, error_size);
    return 0;
  } catch (const std::exception& e) {
    return fail(e.what(), error, error_size);
  }
}
