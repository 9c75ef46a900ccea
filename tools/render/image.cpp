#include "tools/render/image.h"

#include "core/mesh.h"
#include "tools/output/atomic_file.h"

#include <png.h>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <ostream>

namespace jetshell {

Image Image::downsample(int factor) const {
  Image out(width / factor, height / factor);
  const float weight = 1.0f / static_cast<float>(factor * factor);
  for (int y = 0; y < out.height; ++y) {
    for (int x = 0; x < out.width; ++x) {
      Rgb sum;
      for (int dy = 0; dy < factor; ++dy)
        for (int dx = 0; dx < factor; ++dx) {
          const Rgb& p = at(x * factor + dx, y * factor + dy);
          sum.r += p.r, sum.g += p.g, sum.b += p.b;
        }
      out.at(x, y) = {sum.r * weight, sum.g * weight, sum.b * weight};
    }
  }
  return out;
}

namespace {

std::uint8_t toSrgb8(float linear) {
  const float c = std::clamp(linear, 0.0f, 1.0f);
  const float s = c <= 0.0031308f ? 12.92f * c : 1.055f * std::pow(c, 1.0f / 2.4f) - 0.055f;
  return static_cast<std::uint8_t>(std::lround(255.0f * s));
}

}  // namespace

void writePng(const std::string& path, const Image& image) {
  std::vector<std::uint8_t> rgb(static_cast<std::size_t>(image.width) * image.height * 3);
  for (std::size_t k = 0; k < image.pixels.size(); ++k) {
    rgb[3 * k] = toSrgb8(image.pixels[k].r);
    rgb[3 * k + 1] = toSrgb8(image.pixels[k].g);
    rgb[3 * k + 2] = toSrgb8(image.pixels[k].b);
  }
  writePngRgb8(path, image.width, image.height, rgb);
}

void writePngRgb8(const std::string& path, int width, int height, const std::vector<std::uint8_t>& rgb) {
  if (width <= 0 || height <= 0 || rgb.size() != static_cast<std::size_t>(width) * height * 3)
    throw InputError(path + ": PNG encoding failed (" + std::to_string(rgb.size()) + " bytes for a " +
                     std::to_string(width) + "x" + std::to_string(height) + " RGB image)");
  // libpng's simplified API reports errors by return value (no setjmp, no callbacks).
  png_image img{};
  img.version = PNG_IMAGE_VERSION;
  img.width = static_cast<png_uint_32>(width);
  img.height = static_cast<png_uint_32>(height);
  img.format = PNG_FORMAT_RGB;
  png_alloc_size_t bytes = 0;
  if (!png_image_write_to_memory(&img, nullptr, &bytes, 0, rgb.data(), 0, nullptr))
    throw InputError(path + ": PNG encoding failed (" + img.message + ")");
  std::vector<char> encoded(bytes);
  if (!png_image_write_to_memory(&img, encoded.data(), &bytes, 0, rgb.data(), 0, nullptr))
    throw InputError(path + ": PNG encoding failed (" + img.message + ")");
  writeFileAtomically(path, [&](std::ostream& out) { out.write(encoded.data(), static_cast<std::streamsize>(bytes)); });
}

std::vector<std::uint8_t> readPngRgb(const std::string& path, int& width, int& height) {
  png_image img{};
  img.version = PNG_IMAGE_VERSION;
  if (!png_image_begin_read_from_file(&img, path.c_str())) throw InputError(path + ": not a readable PNG (" + img.message + ")");
  img.format = PNG_FORMAT_RGB;
  std::vector<std::uint8_t> data(PNG_IMAGE_SIZE(img));
  if (!png_image_finish_read(&img, nullptr, data.data(), 0, nullptr)) {
    const std::string message = img.message;
    png_image_free(&img);
    throw InputError(path + ": PNG decode failed (" + message + ")");
  }
  width = static_cast<int>(img.width);
  height = static_cast<int>(img.height);
  return data;
}

}  // namespace jetshell
