#pragma once
/// @file Image.h
/// @brief A float image with named planar channels, the in-memory form of rtsdf's EXR/PNG outputs.
#include <cstddef>
#include <string>
#include <utility>
#include <vector>

namespace rtsdf {

/// @brief Largest width or height an Image accepts (guards against absurd allocations from bad settings).
constexpr int kMaxImageSize = 16384;

/// @brief A float image with named planar channels (x fastest, row 0 at the top).
/// @note Channels keep their insertion order; values are linear unless a channel's name says otherwise.
class Image {
public:
  Image() = default;
  /// @brief An image of @a width x @a height pixels with no channels.
  /// @throw Error when width or height is < 1 or > kMaxImageSize.
  Image(int width, int height);

  int width() const { return mWidth; }
  int height() const { return mHeight; }
  std::size_t pixelCount() const { return std::size_t(mWidth) * std::size_t(mHeight); }
  /// @brief Index of pixel (@a x, @a y) in a channel's values.
  std::size_t index(int x, int y) const { return std::size_t(y) * std::size_t(mWidth) + std::size_t(x); }

  /// @brief Add (or replace, keeping its position) a channel.
  /// @param name non-empty, e.g. "R" or "sun.V"
  /// @param values pixelCount() values, x fastest, row 0 at the top
  /// @throw Error when @a name is empty or @a values.size() != pixelCount().
  void setChannel(const std::string& name, std::vector<float> values);
  bool hasChannel(const std::string& name) const;
  /// @brief The values of channel @a name. @throw Error naming the channel (and the ones present) if absent.
  const std::vector<float>& channel(const std::string& name) const;
  /// @brief Channel names in insertion order.
  std::vector<std::string> channelNames() const;
  std::size_t channelCount() const { return mChannels.size(); }

private:
  int mWidth = 0, mHeight = 0;
  std::vector<std::pair<std::string, std::vector<float>>> mChannels; // few channels: linear lookup
};

} // namespace rtsdf
