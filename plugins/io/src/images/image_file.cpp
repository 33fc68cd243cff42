#include "images/image_file.h"

#include <fstream>

#include "images/jpeg.h"
#include "images/png.h"
#include "plugslam/errors.h"

namespace plugslam {
namespace io {

void checkImageSize(const std::string& name, std::size_t width, std::size_t height) {
  if (width == 0 || height == 0)
    throw ParseError(name, 0, "image has no pixels (" + std::to_string(width) + "x" +
                                  std::to_string(height) + ")");
  if (width > kMaxImagePixels / height)
    throw ParseError(name, 0, "image of " + std::to_string(width) + "x" + std::to_string(height) +
                                  " pixels is larger than the " +
                                  std::to_string(kMaxImagePixels) + " pixels accepted");
}

Image decodeImage(const std::uint8_t* data, std::size_t size, const std::string& name,
                  ImageChannels channels) {
  if (isPng(data, size)) return decodePng(data, size, name, channels);
  if (isJpeg(data, size)) return decodeJpeg(data, size, name, channels);
  throw ParseError(name, 0,
                   size == 0 ? std::string("empty file, expected a PNG or JPEG image")
                             : std::string("not a PNG or JPEG image (unknown signature)"));
}

std::vector<std::uint8_t> readFileBytes(const std::string& path) {
  std::ifstream in(path, std::ios::binary);
  if (!in) throw InputError("cannot open '" + path + "'");
  in.seekg(0, std::ios::end);
  const std::streamoff n = in.tellg();
  if (n < 0) throw InputError("cannot read '" + path + "' (not a regular file?)");
  in.seekg(0, std::ios::beg);
  std::vector<std::uint8_t> bytes(static_cast<std::size_t>(n));
  if (n > 0 && !in.read(reinterpret_cast<char*>(bytes.data()), n))
    throw InputError("cannot read '" + path + "'");
  return bytes;
}

Image readImageFile(const std::string& path, ImageChannels channels) {
  const std::vector<std::uint8_t> bytes = readFileBytes(path);
  return decodeImage(bytes.data(), bytes.size(), path, channels);
}

DepthImage readDepthFile(const std::string& path, double units_per_metre) {
  const std::vector<std::uint8_t> bytes = readFileBytes(path);
  return decodeDepthPng(bytes.data(), bytes.size(), path, units_per_metre);
}

}  // namespace io
}  // namespace plugslam
