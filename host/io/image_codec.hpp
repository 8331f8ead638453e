#pragma once
// Image encoding and decoding through OpenImageIO, which lives in a module loaded on first use
// (libsplatcl_oiio.so: beside the executable in the build tree, in lib/splatcl/ when installed,
// or where $SPLATCL_OIIO_MODULE names it), so that commands that touch no image start without it.
#include <cstdint>
#include <string>
#include <vector>

namespace splatcl {

// The encoded file for `path`'s extension (PNG, EXR, ...) of width×height RGB floats in [0, 1],
// row 0 = bottom. Throws Error("cannot write PATH: cause").
std::vector<unsigned char> encode_image_rgb(const std::string& path, int width, int height, const std::vector<float>& rgb);

// Throws Error(prefix + why) when `path` names an image (by its extension) and the module cannot
// be loaded: the output checks call it, so a broken install fails before any work.
void check_image_module(const std::string& path, const std::string& prefix);

struct DecodedImage {
  int width = 0, height = 0, channels = 0;
  std::vector<std::uint8_t> pixels;  // 8-bit channels, top row first
};
// The image at `path`. Throws Error("cannot read WHAT PATH: cause").
DecodedImage decode_image_u8(const std::string& path, const std::string& what);

}  // namespace splatcl
