// Reads 8-bit RGB or RGBA, non-interlaced PNG files (what gnuplot's pngcairo writes) into pixels,
// so tests can check what a picture shows. Written from the PNG specification: chunks, zlib
// stream, per-row filters (none, sub, up, average, Paeth).
#pragma once

#include <zlib.h>

#include <cstdint>
#include <cstdlib>
#include <fstream>
#include <sstream>
#include <stdexcept>
#include <string>
#include <vector>

namespace rlt::test {

struct Image {
  int width = 0, height = 0;
  std::vector<uint8_t> rgb;  // [height][width][3]

  const uint8_t* at(int x, int y) const { return &rgb[3 * (size_t(y) * width + x)]; }
};

inline uint32_t big_endian(const std::string& s, size_t at) {
  return uint32_t(uint8_t(s[at])) << 24 | uint32_t(uint8_t(s[at + 1])) << 16 |
         uint32_t(uint8_t(s[at + 2])) << 8 | uint32_t(uint8_t(s[at + 3]));
}

inline Image read_png(const std::string& path) {
  std::ifstream in(path, std::ios::binary);
  std::stringstream buffer;
  buffer << in.rdbuf();
  const std::string file = buffer.str();
  if (file.size() < 8 || file.compare(0, 8, "\x89PNG\r\n\x1a\n") != 0)
    throw std::runtime_error(path + " is not a PNG file");
  Image image;
  int channels = 0;
  std::string compressed;
  for (size_t at = 8; at + 8 <= file.size();) {
    const uint32_t length = big_endian(file, at);
    const std::string type = file.substr(at + 4, 4);
    if (at + 12 + length > file.size())
      throw std::runtime_error(path + ": truncated chunk " + type);
    const std::string data = file.substr(at + 8, length);
    if (type == "IHDR") {
      image.width = int(big_endian(data, 0));
      image.height = int(big_endian(data, 4));
      const int depth = uint8_t(data[8]), colour = uint8_t(data[9]), interlace = uint8_t(data[12]);
      if (depth != 8 || (colour != 2 && colour != 6) || interlace != 0)
        throw std::runtime_error(path + ": only 8-bit RGB(A) non-interlaced PNGs are read here");
      channels = colour == 6 ? 4 : 3;
    } else if (type == "IDAT") {
      compressed += data;
    } else if (type == "IEND") {
      break;
    }
    at += 12 + length;
  }
  if (channels == 0) throw std::runtime_error(path + ": no IHDR chunk");
  const size_t stride = size_t(image.width) * channels;
  std::vector<uint8_t> raw((stride + 1) * image.height);
  uLongf raw_size = raw.size();
  if (uncompress(raw.data(), &raw_size, reinterpret_cast<const Bytef*>(compressed.data()),
                 compressed.size()) != Z_OK ||
      raw_size != raw.size())
    throw std::runtime_error(path + ": the image data does not inflate to its size");
  // undo the row filters in place; byte i's left neighbour is i - channels
  std::vector<uint8_t> pixels(stride * image.height), zero(stride, 0);
  for (int y = 0; y < image.height; ++y) {
    const uint8_t filter = raw[y * (stride + 1)];
    const uint8_t* row = &raw[y * (stride + 1) + 1];
    uint8_t* out = &pixels[y * stride];
    const uint8_t* up = y > 0 ? &pixels[(y - 1) * stride] : zero.data();
    for (size_t i = 0; i < stride; ++i) {
      const int a = i >= size_t(channels) ? out[i - channels] : 0, b = up[i],
                c = i >= size_t(channels) ? up[i - channels] : 0;
      int predictor = 0;
      switch (filter) {
        case 0:
          break;
        case 1:
          predictor = a;
          break;
        case 2:
          predictor = b;
          break;
        case 3:
          predictor = (a + b) / 2;
          break;
        case 4: {
          const int p = a + b - c, pa = std::abs(p - a), pb = std::abs(p - b), pc = std::abs(p - c);
          predictor = pa <= pb && pa <= pc ? a : (pb <= pc ? b : c);
          break;
        }
        default:
          throw std::runtime_error(path + ": unknown row filter");
      }
      out[i] = uint8_t(row[i] + predictor);
    }
  }
  image.rgb.resize(size_t(image.width) * image.height * 3);
  for (size_t p = 0; p < size_t(image.width) * image.height; ++p)
    for (int k = 0; k < 3; ++k) image.rgb[3 * p + k] = pixels[p * channels + k];
  return image;
}

// pixels within `tolerance` of colour 0xRRGGBB in every channel
inline int count_colour(const Image& image, uint32_t colour, int tolerance = 10) {
  int count = 0;
  for (size_t p = 0; p < size_t(image.width) * image.height; ++p) {
    bool near = true;
    for (int k = 0; k < 3; ++k)
      near = near && std::abs(int(image.rgb[3 * p + k]) - int((colour >> (16 - 8 * k)) & 0xff)) <=
                         tolerance;
    count += near;
  }
  return count;
}

}  // namespace rlt::test
