#include "image/Image.h"

#include "util/Error.h"

#include <fmt/format.h>

namespace rtsdf {

Image::Image(int width, int height) : mWidth(width), mHeight(height) {
  if (width < 1 || height < 1 || width > kMaxImageSize || height > kMaxImageSize)
    throw Error(fmt::format("image size {}x{} is invalid: width and height must be in [1, {}]", width, height,
                            kMaxImageSize));
}

void Image::setChannel(const std::string& name, std::vector<float> values) {
  if (name.empty()) throw Error("image channel name must not be empty");
  if (pixelCount() == 0)
    throw Error(fmt::format("cannot add channel '{}' to an image with no pixels", name));
  if (values.size() != pixelCount())
    throw Error(fmt::format("channel '{}' has {} values, but the {}x{} image has {} pixels", name, values.size(),
                            mWidth, mHeight, pixelCount()));
  for (auto& [n, v] : mChannels)
    if (n == name) {
      v = std::move(values);
      return;
    }
  mChannels.emplace_back(name, std::move(values));
}

bool Image::hasChannel(const std::string& name) const {
  for (const auto& c : mChannels)
    if (c.first == name) return true;
  return false;
}

const std::vector<float>& Image::channel(const std::string& name) const {
  for (const auto& c : mChannels)
    if (c.first == name) return c.second;
  throw Error(fmt::format("image has no channel '{}' (channels: {})", name,
                          mChannels.empty() ? std::string("none") : fmt::format("{}", fmt::join(channelNames(), ", "))));
}

std::vector<std::string> Image::channelNames() const {
  std::vector<std::string> names;
  names.reserve(mChannels.size());
  for (const auto& c : mChannels) names.push_back(c.first);
  return names;
}

} // namespace rtsdf
