#include "synth/png.h"

#include <png.h>

#include "synth/config.h"

namespace grapebench {

namespace {

void png_append(png_structp png, png_bytep data, png_size_t n) {
  static_cast<std::string*>(png_get_io_ptr(png))->append(reinterpret_cast<const char*>(data), n);
}

}  // namespace

std::string png_bytes(int w, int h, int bit_depth, int colour_type, const std::vector<unsigned char>& pixels) {
  std::string out;
  png_structp png = png_create_write_struct(PNG_LIBPNG_VER_STRING, nullptr, nullptr, nullptr);
  png_infop info = png_create_info_struct(png);
  if (!png || !info || setjmp(png_jmpbuf(png))) {
    png_destroy_write_struct(&png, &info);
    throw InputError("PNG encoding failed");
  }
  png_set_write_fn(png, &out, png_append, nullptr);
  png_set_IHDR(png, info, w, h, bit_depth, colour_type, PNG_INTERLACE_NONE, PNG_COMPRESSION_TYPE_DEFAULT,
               PNG_FILTER_TYPE_DEFAULT);
  png_write_info(png, info);
  const std::size_t row = pixels.size() / h;
  for (int y = 0; y < h; ++y) png_write_row(png, const_cast<unsigned char*>(pixels.data() + y * row));
  png_write_end(png, nullptr);
  png_destroy_write_struct(&png, &info);
  return out;
}

std::string rgb_image_png(int width, int height, const std::vector<std::uint8_t>& rgb) {
  return png_bytes(width, height, 8, PNG_COLOR_TYPE_RGB, rgb);
}

}  // namespace grapebench
