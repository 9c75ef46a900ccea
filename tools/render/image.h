// RGB images and PNG output (libpng).
#pragma once

#include <cstdint>
#include <string>
#include <vector>

namespace jetshell {

struct Rgb {
  float r = 0, g = 0, b = 0;  // linear 0..1
};

/// A width × height RGB image, row 0 at the top.
struct Image {
  int width = 0, height = 0;
  std::vector<Rgb> pixels;
  Image() = default;
  Image(int w, int h, Rgb fill = {}) : width(w), height(h), pixels(static_cast<std::size_t>(w) * h, fill) {}
  Rgb& at(int x, int y) { return pixels[static_cast<std::size_t>(y) * width + x]; }
  const Rgb& at(int x, int y) const { return pixels[static_cast<std::size_t>(y) * width + x]; }
  /// Box-filtered reduction by an integer factor (supersampling's last step).
  Image downsample(int factor) const;
};

/// Encodes the image as an 8-bit sRGB PNG and writes it atomically. Throws InputError naming the path when it
/// cannot be written.
void writePng(const std::string& path, const Image& image);

/// Writes 8-bit sRGB bytes (row-major RGB, width × height × 3) as a PNG, atomically. Throws InputError naming
/// the path when it cannot be encoded or written.
void writePngRgb8(const std::string& path, int width, int height, const std::vector<std::uint8_t>& rgb);

/// Decodes a PNG (any bit depth or colour type libpng reads) into width, height and 8-bit RGB bytes (tests).
/// Throws InputError when the file is not a readable PNG.
std::vector<std::uint8_t> readPngRgb(const std::string& path, int& width, int& height);

}  // namespace jetshell
