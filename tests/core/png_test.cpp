// The SDK's PNG encoder: what it writes decodes (libpng) to the same samples for every layout
// (grey, grey + alpha, RGB, RGBA; 8 and 16 bit; padded rows), the options do what they say, bad
// input is refused, and the unfiltered one-chunk form is byte for byte the PNG laser2d's maps
// were before the encoder was shared (zlib compress2 of unfiltered rows in one IDAT), as are
// render's pictures (libpng's simplified writer) and io's image sequences (libpng at level 1).
#include "plugslam/png.h"

#include <gtest/gtest.h>
#include <png.h>
#include <zlib.h>

#include <algorithm>
#include <random>
#include <vector>

#include "plugslam/errors.h"

using namespace plugslam;

namespace {

struct Decoded {
  int width = 0, height = 0, channels = 0, bit_depth = 0;
  std::vector<uint8_t> bytes;  // rows as stored (16-bit samples big-endian)
};

Decoded decode(const std::string& png) {
  Decoded d;
  // The classic API keeps the stored layout (the simplified one converts).
  png_structp p = png_create_read_struct(PNG_LIBPNG_VER_STRING, nullptr, nullptr, nullptr);
  png_infop info = png_create_info_struct(p);
  struct Reader {
    const std::string* s;
    size_t at;
  } reader{&png, 0};
  png_set_read_fn(p, &reader, [](png_structp pp, png_bytep out, png_size_t n) {
    auto* r = static_cast<Reader*>(png_get_io_ptr(pp));
    if (r->at + n > r->s->size()) png_error(pp, "short");
    std::copy_n(r->s->data() + r->at, n, out);
    r->at += n;
  });
  if (setjmp(png_jmpbuf(p))) {
    png_destroy_read_struct(&p, &info, nullptr);
    ADD_FAILURE() << "libpng cannot read the encoder's output";
    return {};
  }
  png_read_info(p, info);
  d.width = static_cast<int>(png_get_image_width(p, info));
  d.height = static_cast<int>(png_get_image_height(p, info));
  d.channels = png_get_channels(p, info);
  d.bit_depth = png_get_bit_depth(p, info);
  const size_t row = png_get_rowbytes(p, info);
  d.bytes.resize(row * static_cast<size_t>(d.height));
  std::vector<png_bytep> rows(static_cast<size_t>(d.height));
  for (size_t y = 0; y < rows.size(); ++y) rows[y] = d.bytes.data() + y * row;
  png_read_image(p, rows.data());
  png_read_end(p, nullptr);
  png_destroy_read_struct(&p, &info, nullptr);
  return d;
}

// The chunk types of a PNG, in order.
std::vector<std::string> chunkTypes(const std::string& png) {
  std::vector<std::string> out;
  for (size_t at = 8; at + 12 <= png.size();) {
    const auto* b = reinterpret_cast<const unsigned char*>(png.data() + at);
    const size_t n = (size_t(b[0]) << 24) | (size_t(b[1]) << 16) | (size_t(b[2]) << 8) | b[3];
    out.push_back(png.substr(at + 4, 4));
    at += 12 + n;
  }
  return out;
}

std::vector<uint8_t> noise(size_t n, unsigned seed) {
  std::mt19937 rng(seed);
  std::vector<uint8_t> v(n);
  for (auto& x : v) x = static_cast<uint8_t>(rng());
  return v;
}

TEST(Png, EveryLayoutDecodesToItsSamples) {
  for (int channels = 1; channels <= 4; ++channels) {
    for (int bits : {8, 16}) {
      const int w = 37, h = 23, bytes = bits / 8;
      const size_t row = static_cast<size_t>(w) * channels * bytes, stride = row + 5;  // padded
      const std::vector<uint8_t> data = noise(stride * h, channels * 100 + bits);
      PngPixels p{data.data(), w, h, channels, bits, stride};
      const Decoded d = decode(encodePng(p));
      ASSERT_EQ(d.width, w);
      ASSERT_EQ(d.height, h);
      ASSERT_EQ(d.channels, channels);
      ASSERT_EQ(d.bit_depth, bits);
      for (int y = 0; y < h; ++y)
        for (size_t i = 0; i < row; ++i) {
          // 16-bit samples are given in host order (little-endian here), stored big-endian.
          const size_t src = y * stride + (bits == 16 ? (i ^ 1) : i);
          ASSERT_EQ(d.bytes[y * row + i], data[src])
              << channels << " channels, " << bits << " bits, row " << y << " byte " << i;
        }
    }
  }
}

TEST(Png, OptionsDoWhatTheySay) {
  const std::vector<uint8_t> data = noise(200 * 150 * 3, 7);
  const PngPixels p{data.data(), 200, 150, 3, 8, 0};
  const std::string plain = encodePng(p);
  EXPECT_EQ(chunkTypes(plain).front(), "IHDR");
  EXPECT_EQ(chunkTypes(plain).back(), "IEND");
  // 90 kB of noise barely compresses: 8192-byte IDATs, about 12 of them.
  const auto types = chunkTypes(plain);
  EXPECT_GT(std::count(types.begin(), types.end(), "IDAT"), 5);
  PngOptions one;
  one.idat_bytes = 0;
  const auto one_types = chunkTypes(encodePng(p, one));
  EXPECT_EQ(std::count(one_types.begin(), one_types.end(), "IDAT"), 1);
  PngOptions srgb;
  srgb.srgb = true;
  const auto s = chunkTypes(encodePng(p, srgb));
  EXPECT_EQ(s[1], "sRGB");
  EXPECT_EQ(std::count(types.begin(), types.end(), "sRGB"), 0);
  // The zlib header's level bits: 1 -> 0x01, 6 (default) -> 0x9c.
  PngOptions fast;
  fast.level = 1;
  const std::string f = encodePng(p, fast);
  EXPECT_EQ(static_cast<unsigned char>(f[8 + 8 + 13 + 4 + 8 + 1]), 0x01);
  EXPECT_EQ(static_cast<unsigned char>(plain[8 + 8 + 13 + 4 + 8 + 1]), 0x9c);
  // Every option still decodes to the same samples.
  for (const std::string& png : {plain, encodePng(p, one), encodePng(p, srgb), f})
    EXPECT_EQ(decode(png).bytes, data);
}

TEST(Png, BadImagesAreRefused) {
  const std::vector<uint8_t> data(64, 0);
  EXPECT_THROW(encodePng(PngPixels{data.data(), 0, 4, 1, 8, 0}), InputError);
  EXPECT_THROW(encodePng(PngPixels{nullptr, 4, 4, 1, 8, 0}), InputError);
  EXPECT_THROW(encodePng(PngPixels{data.data(), 4, 4, 5, 8, 0}), InputError);
  EXPECT_THROW(encodePng(PngPixels{data.data(), 4, 4, 1, 12, 0}), InputError);
  EXPECT_THROW(encodePng(PngPixels{data.data(), 4, 4, 3, 8, 4}), InputError);  // stride < row
  PngOptions bad;
  bad.level = 10;
  EXPECT_THROW(encodePng(PngPixels{data.data(), 4, 4, 1, 8, 0}, bad), InputError);
}

// laser2d's maps before the shared encoder: unfiltered rows, zlib compress2 at level 6, one IDAT.
std::string laser2dPng(const std::vector<uint8_t>& pixels, int w, int h) {
  auto u32 = [](std::string& s, uint32_t v) {
    for (int k = 3; k >= 0; --k) s.push_back(static_cast<char>(v >> (8 * k)));
  };
  auto chunk = [&](std::string& out, const char* type, const std::string& data) {
    u32(out, static_cast<uint32_t>(data.size()));
    const std::string body = std::string(type, 4) + data;
    out += body;
    u32(out, static_cast<uint32_t>(crc32(0, reinterpret_cast<const Bytef*>(body.data()),
                                         static_cast<uInt>(body.size()))));
  };
  std::string raw;
  for (int y = 0; y < h; ++y) {
    raw.push_back('\0');
    raw.append(reinterpret_cast<const char*>(pixels.data()) + static_cast<size_t>(y) * w, w);
  }
  uLongf size = compressBound(raw.size());
  std::string z(size, '\0');
  compress2(reinterpret_cast<Bytef*>(z.data()), &size, reinterpret_cast<const Bytef*>(raw.data()),
            raw.size(), 6);
  z.resize(size);
  std::string out("\x89PNG\r\n\x1a\n", 8), ihdr;
  u32(ihdr, static_cast<uint32_t>(w));
  u32(ihdr, static_cast<uint32_t>(h));
  ihdr += std::string("\x08\x00\x00\x00\x00", 5);
  chunk(out, "IHDR", ihdr);
  chunk(out, "IDAT", z);
  chunk(out, "IEND", "");
  return out;
}

TEST(Png, UnfilteredOneChunkIsLaser2dsMapPngByteForByte) {
  // A map-like image: walls (0), free space (254), unknown (205), in blocks; and noise. Both
  // above 16 KiB of raw rows, where libpng keeps zlib's full window as compress2 does (smaller
  // images get a smaller window, declared in the zlib header: the same pixels, other bytes).
  for (const auto& [w, h] : {std::pair{160, 120}, std::pair{515, 445}}) {
    std::vector<uint8_t> map(static_cast<size_t>(w) * h);
    for (int y = 0; y < h; ++y)
      for (int x = 0; x < w; ++x)
        map[static_cast<size_t>(y) * w + x] =
            (x % 40 == 0 || y % 30 == 0) ? 0 : ((x / 20 + y / 15) % 3 == 0 ? 205 : 254);
    for (const auto& pixels : {map, noise(map.size(), 3)}) {
      PngOptions flat;
      flat.filters = false;
      flat.idat_bytes = 0;
      EXPECT_EQ(encodePng(PngPixels{pixels.data(), w, h, 1, 8, 0}, flat), laser2dPng(pixels, w, h))
          << w << " x " << h;
    }
  }
}

// render's pictures before the shared encoder: libpng's simplified writer (8-bit sRGB RGB).
std::string simplifiedRgbPng(const std::vector<uint8_t>& rgb, int w, int h) {
  png_image image{};
  image.version = PNG_IMAGE_VERSION;
  image.width = static_cast<png_uint_32>(w);
  image.height = static_cast<png_uint_32>(h);
  image.format = PNG_FORMAT_RGB;
  png_alloc_size_t size = 0;
  EXPECT_TRUE(png_image_write_to_memory(&image, nullptr, &size, 0, rgb.data(), w * 3, nullptr));
  std::string out(size, '\0');
  EXPECT_TRUE(png_image_write_to_memory(&image, out.data(), &size, 0, rgb.data(), w * 3, nullptr));
  out.resize(size);
  return out;
}

// io's image sequences before the shared encoder: libpng's writer at zlib level 1, its default
// filters and IDAT size (grey or RGB 8-bit, grey 16-bit given in host order).
std::string sequencePng(const uint8_t* data, int w, int h, int channels, int bits) {
  std::string out;
  png_structp png = png_create_write_struct(PNG_LIBPNG_VER_STRING, nullptr, nullptr, nullptr);
  png_infop info = png_create_info_struct(png);
  png_set_write_fn(
      png, &out,
      [](png_structp p, png_bytep d, png_size_t n) {
        static_cast<std::string*>(png_get_io_ptr(p))->append(reinterpret_cast<const char*>(d), n);
      },
      [](png_structp) {});
  png_set_compression_level(png, 1);
  png_set_IHDR(png, info, static_cast<png_uint_32>(w), static_cast<png_uint_32>(h), bits,
               channels == 1 ? PNG_COLOR_TYPE_GRAY : PNG_COLOR_TYPE_RGB, PNG_INTERLACE_NONE,
               PNG_COMPRESSION_TYPE_DEFAULT, PNG_FILTER_TYPE_DEFAULT);
  png_write_info(png, info);
  if (bits == 16) png_set_swap(png);
  const size_t row = static_cast<size_t>(w) * channels * (bits / 8);
  std::vector<png_bytep> rows(static_cast<size_t>(h));
  for (size_t y = 0; y < rows.size(); ++y) rows[y] = const_cast<png_bytep>(data + y * row);
  png_write_rows(png, rows.data(), static_cast<png_uint_32>(h));
  png_write_end(png, nullptr);
  png_destroy_write_struct(&png, &info);
  return out;
}

TEST(Png, PicturesAndSequencesAreByteForByteWhatTheirWritersProducedBefore) {
  // A plot-like picture (flat background, lines) and noise, small and large.
  for (const auto& [w, h] : {std::pair{31, 17}, std::pair{640, 480}}) {
    std::vector<uint8_t> plot(static_cast<size_t>(w) * h * 3, 0xff);
    for (int y = 0; y < h; ++y)
      for (int x = 0; x < w; ++x)
        if (x == y || x % 50 == 0) plot[(static_cast<size_t>(y) * w + x) * 3] = 0x20;
    for (const auto& rgb : {plot, noise(plot.size(), 11)}) {
      PngOptions picture;
      picture.srgb = true;  // what render's pictures ask for
      EXPECT_EQ(encodePng(PngPixels{rgb.data(), w, h, 3, 8, 0}, picture),
                simplifiedRgbPng(rgb, w, h))
          << w << " x " << h;
      PngOptions fast;
      fast.level = 1;  // what io's sequence writer asks for
      EXPECT_EQ(encodePng(PngPixels{rgb.data(), w, h, 3, 8, 0}, fast),
                sequencePng(rgb.data(), w, h, 3, 8));
      EXPECT_EQ(encodePng(PngPixels{rgb.data(), w, h, 1, 8, 0}, fast),
                sequencePng(rgb.data(), w, h, 1, 8));
      EXPECT_EQ(encodePng(PngPixels{rgb.data(), w / 2, h, 1, 16, 0}, fast),
                sequencePng(rgb.data(), w / 2, h, 1, 16));
    }
  }
}

}  // namespace
