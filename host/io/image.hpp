#pragma once
// Image output through OpenImageIO (format from the extension: .png, .exr, ...; host/io/image_codec.hpp),
// written atomically.
#include <array>
#include <cstdint>
#include <string>
#include <vector>

namespace splatcl {

// rgb: width*height*3 floats in [0,1] (clamped on 8-bit formats), row 0 = bottom (OpenGL
// convention; flipped to the file's top-down order here).
void write_image_rgb(const std::string& path, int width, int height, const std::vector<float>& rgb);

// A perceptually ordered colour ramp (dark blue → cyan → yellow → red) for heat maps; t in [0,1].
std::array<float, 3> heat_color(float t);

}  // namespace splatcl
