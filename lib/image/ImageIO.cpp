#include "image/ImageIO.h"

#include "util/AtomicFile.h"
#include "util/Error.h"

#include <ImfChannelList.h>
#include <ImfFrameBuffer.h>
#include <ImfHeader.h>
#include <ImfInputFile.h>
#include <ImfOutputFile.h>
#include <fmt/format.h>
#include <png.h>

#include <algorithm>
#include <cmath>
#include <cstring>
#include <exception>
#include <system_error>

namespace rtsdf {
namespace fs = std::filesystem;

namespace {

/// Throw when any value of any channel is NaN (and, when @a rejectInf, infinite), naming channel and pixel.
void checkFinite(const fs::path& path, const Image& image, const std::vector<std::string>& names, bool rejectInf) {
  for (const auto& name : names) {
    const auto& values = image.channel(name);
    for (std::size_t i = 0; i < values.size(); ++i) {
      const float v = values[i];
      if (std::isnan(v) || (rejectInf && std::isinf(v)))
        throw Error(fmt::format("{}: channel '{}' has a non-finite value ({}) at pixel ({}, {})", path.string(), name,
                                v, i % std::size_t(image.width()), i / std::size_t(image.width())));
    }
  }
}

void checkReadable(const fs::path& path) {
  std::error_code ec;
  if (!fs::exists(path, ec)) throw Error(fmt::format("{}: file does not exist", path.string()));
  if (fs::is_directory(path, ec)) throw Error(fmt::format("{}: is a directory, not a file", path.string()));
}

} // namespace

// ---------------------------------------------------------------------------------------------- transfer

float linearToSrgb(float v) {
  v = std::clamp(v, 0.0f, 1.0f);
  return v <= 0.0031308f ? 12.92f * v : 1.055f * std::pow(v, 1.0f / 2.4f) - 0.055f;
}

float srgbToLinear(float v) {
  v = std::clamp(v, 0.0f, 1.0f);
  return v <= 0.04045f ? v / 12.92f : std::pow((v + 0.055f) / 1.055f, 2.4f);
}

// ---------------------------------------------------------------------------------------------- EXR

void writeExr(const fs::path& path, const Image& image) {
  const auto names = image.channelNames();
  if (names.empty()) throw Error(fmt::format("{}: cannot write an EXR image with no channels", path.string()));
  checkFinite(path, image, names, true);

  writeFileAtomically(path, [&](const fs::path& tmp) {
    try {
      Imf::Header header(image.width(), image.height());
      header.compression() = Imf::ZIP_COMPRESSION;
      for (const auto& name : names) header.channels().insert(name, Imf::Channel(Imf::FLOAT));
      Imf::FrameBuffer fb;
      const std::size_t xStride = sizeof(float), yStride = sizeof(float) * std::size_t(image.width());
      for (const auto& name : names)
        // OpenEXR's slice API takes a non-const pointer even for writing; it only reads through it.
        fb.insert(name, Imf::Slice(Imf::FLOAT, reinterpret_cast<char*>(const_cast<float*>(image.channel(name).data())),
                                   xStride, yStride));
      Imf::OutputFile file(tmp.c_str(), header);
      file.setFrameBuffer(fb);
      file.writePixels(image.height());
    } catch (const Error&) {
      throw;
    } catch (const std::exception& e) {
      throw Error(fmt::format("{}: cannot write EXR: {}", path.string(), e.what()));
    }
  });
}

Image readExr(const fs::path& path) {
  checkReadable(path);
  try {
    Imf::InputFile file(path.c_str());
    const Imath::Box2i dw = file.header().dataWindow();
    const long long w = (long long)dw.max.x - dw.min.x + 1, h = (long long)dw.max.y - dw.min.y + 1;
    if (w < 1 || h < 1 || w > kMaxImageSize || h > kMaxImageSize)
      throw Error(fmt::format("{}: EXR data window {}x{} is empty or too large", path.string(), w, h));
    Image image{int(w), int(h)};
    const Imf::ChannelList& channels = file.header().channels();
    std::vector<std::pair<std::string, std::vector<float>>> data;
    for (auto it = channels.begin(); it != channels.end(); ++it) {
      if (it.channel().xSampling != 1 || it.channel().ySampling != 1)
        throw Error(fmt::format("{}: EXR channel '{}' is subsampled, which is not supported", path.string(),
                                it.name()));
      data.emplace_back(it.name(), std::vector<float>(image.pixelCount()));
    }
    if (data.empty()) throw Error(fmt::format("{}: EXR file has no channels", path.string()));
    Imf::FrameBuffer fb;
    const std::size_t xStride = sizeof(float), yStride = sizeof(float) * std::size_t(w);
    for (auto& [name, values] : data) {
      // The slice base points at pixel (0, 0) of the data window's coordinate system.
      char* base = reinterpret_cast<char*>(values.data()) - std::ptrdiff_t(dw.min.x) * std::ptrdiff_t(xStride) -
                   std::ptrdiff_t(dw.min.y) * std::ptrdiff_t(yStride);
      fb.insert(name, Imf::Slice(Imf::FLOAT, base, xStride, yStride));
    }
    file.setFrameBuffer(fb);
    file.readPixels(dw.min.y, dw.max.y);
    for (auto& [name, values] : data) image.setChannel(name, std::move(values));
    return image;
  } catch (const Error&) {
    throw;
  } catch (const std::exception& e) {
    throw Error(fmt::format("{}: cannot read EXR: {}", path.string(), e.what()));
  }
}

// ---------------------------------------------------------------------------------------------- PNG

void writePng(const fs::path& path, const PngPixels& pixels) {
  if (pixels.width <= 0 || pixels.height <= 0 ||
      pixels.rgb.size() != std::size_t(pixels.width) * std::size_t(pixels.height) * 3)
    throw Error(fmt::format("{}: cannot write PNG: {} bytes for {}x{} RGB pixels", path.string(), pixels.rgb.size(),
                            pixels.width, pixels.height));
  const std::vector<std::uint8_t>& rgb = pixels.rgb;
  writeFileAtomically(path, [&](const fs::path& tmp) {
    png_image png;
    std::memset(&png, 0, sizeof(png));
    png.version = PNG_IMAGE_VERSION;
    png.width = png_uint_32(pixels.width);
    png.height = png_uint_32(pixels.height);
    png.format = PNG_FORMAT_RGB; // 8-bit sRGB: libpng writes an sRGB chunk
    if (!png_image_write_to_file(&png, tmp.c_str(), 0, rgb.data(), png_int_32(3 * pixels.width), nullptr)) {
      const std::string message = png.message;
      png_image_free(&png);
      throw Error(fmt::format("{}: cannot write PNG: {}", path.string(), message));
    }
  });
}

void writePng(const fs::path& path, const Image& image, const std::string& r, const std::string& g,
              const std::string& b) {
  const std::string* names[3] = {&r, &g, &b};
  const std::vector<float>* src[3] = {};
  for (int c = 0; c < 3; ++c) {
    try {
      src[c] = &image.channel(*names[c]);
    } catch (const Error& e) {
      throw Error(fmt::format("{}: cannot write PNG: {}", path.string(), e.what()));
    }
  }
  checkFinite(path, image, {r, g, b}, false);

  std::vector<std::uint8_t> rgb(image.pixelCount() * 3);
  for (std::size_t i = 0; i < image.pixelCount(); ++i)
    for (int c = 0; c < 3; ++c)
      rgb[3 * i + c] = std::uint8_t(std::lround(linearToSrgb((*src[c])[i]) * 255.0f));

  writePng(path, PngPixels{image.width(), image.height(), std::move(rgb)});
}

PngPixels readPng(const fs::path& path) {
  checkReadable(path);
  png_image png;
  std::memset(&png, 0, sizeof(png));
  png.version = PNG_IMAGE_VERSION;
  if (!png_image_begin_read_from_file(&png, path.c_str())) {
    const std::string message = png.message;
    png_image_free(&png);
    throw Error(fmt::format("{}: cannot read PNG: {}", path.string(), message));
  }
  if (png.width < 1 || png.height < 1 || png.width > png_uint_32(kMaxImageSize) ||
      png.height > png_uint_32(kMaxImageSize)) {
    png_image_free(&png);
    throw Error(fmt::format("{}: PNG size {}x{} is empty or too large", path.string(), png.width, png.height));
  }
  png.format = PNG_FORMAT_RGB;
  PngPixels out;
  out.width = int(png.width);
  out.height = int(png.height);
  out.rgb.resize(PNG_IMAGE_SIZE(png));
  if (!png_image_finish_read(&png, nullptr, out.rgb.data(), 0, nullptr)) {
    const std::string message = png.message;
    png_image_free(&png);
    throw Error(fmt::format("{}: cannot read PNG: {}", path.string(), message));
  }
  return out;
}

} // namespace rtsdf
