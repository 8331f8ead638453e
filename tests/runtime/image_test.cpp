#include <gtest/gtest.h>

#include <OpenImageIO/imageio.h>

#include <filesystem>

#include "io/image.hpp"
#include "runtime/error.hpp"

namespace splatcl {
namespace {

TEST(Image, WritesPngTopDownWithRowZeroAtTheBottom) {
  const auto path = (std::filesystem::temp_directory_path() / "splatcl_image_test.png").string();
  // 2x2: bottom row red, top row blue.
  const std::vector<float> rgb = {1, 0, 0, 1, 0, 0, 0, 0, 1, 0, 0, 1};
  write_image_rgb(path, 2, 2, rgb);
  auto in = OIIO::ImageInput::open(path);
  ASSERT_TRUE(in);
  EXPECT_EQ(in->spec().width, 2);
  std::vector<unsigned char> pixels(12);
  ASSERT_TRUE(in->read_image(0, 0, 0, 3, OIIO::TypeDesc::UINT8, pixels.data()));
  // The first file row is the top (blue), the second the bottom (red).
  const std::vector<unsigned char> expected = {0, 0, 255, 0, 0, 255, 255, 0, 0, 255, 0, 0};
  EXPECT_EQ(pixels, expected);
}

// EXR is the linear radiance: 32-bit floats, so bright light keeps its value (half floats turned
// everything above 65504 into +inf; a helper's audit of clustered shading, a light of colour 3e5).
TEST(Image, ExrKeepsFloatRadiance) {
  const auto path = (std::filesystem::temp_directory_path() / "splatcl_image_test.exr").string();
  const std::vector<float> rgb = {1e5f, 3e5f, 0.123456789f, 1e-3f, 2.0f, 65504.0f};
  write_image_rgb(path, 2, 1, rgb);
  auto in = OIIO::ImageInput::open(path);
  ASSERT_TRUE(in);
  EXPECT_EQ(in->spec().format, OIIO::TypeDesc::FLOAT);
  std::vector<float> pixels(6);
  ASSERT_TRUE(in->read_image(0, 0, 0, 3, OIIO::TypeDesc::FLOAT, pixels.data()));
  EXPECT_EQ(pixels, rgb);
}

TEST(Image, MismatchedSizeAndUnknownFormatAreClearErrors) {
  const auto dir = std::filesystem::temp_directory_path();
  EXPECT_THROW(write_image_rgb((dir / "x.png").string(), 2, 2, std::vector<float>(3)), Error);
  EXPECT_THROW(write_image_rgb((dir / "x.unknownformat").string(), 1, 1, std::vector<float>(3)), Error);
}

TEST(Image, HeatColorIsClampedAndMonotoneInRed) {
  EXPECT_EQ(heat_color(-1.0f), heat_color(0.0f));
  EXPECT_EQ(heat_color(2.0f), heat_color(1.0f));
  EXPECT_LT(heat_color(0.0f)[0], heat_color(0.8f)[0]);
}

}  // namespace
}  // namespace splatcl
