// Image, EXR and PNG I/O: exact round trips, sRGB encoding against the IEC 61966-2-1 formula, errors that
// name the file, and atomic writes (no file, or the old file, after a failure).
#include "image/Image.h"
#include "image/ImageIO.h"
#include "util/Error.h"

#include "TestUtil.h"

#include <gtest/gtest.h>

#include <cmath>
#include <cstring>
#include <fstream>
#include <iterator>
#include <limits>
#include <string>

using namespace rtsdf;
namespace fs = std::filesystem;

namespace {

/// Calls @a f, expects an Error, and returns its message.
template <class F>
std::string errorOf(F&& f) {
  try {
    f();
  } catch (const Error& e) {
    return e.what();
  }
  ADD_FAILURE() << "expected rtsdf::Error";
  return {};
}

std::string readBytes(const fs::path& p) {
  std::ifstream in(p, std::ios::binary);
  return std::string(std::istreambuf_iterator<char>(in), std::istreambuf_iterator<char>());
}

/// Number of entries in a folder (to catch leftover temporary files).
std::size_t entries(const fs::path& dir) {
  return std::size_t(std::distance(fs::directory_iterator(dir), fs::directory_iterator()));
}

bool bitEqual(float a, float b) { return std::memcmp(&a, &b, sizeof(float)) == 0; }

/// The sRGB encoding as published (IEC 61966-2-1), in double precision.
double srgbFormula(double v) { return v <= 0.0031308 ? 12.92 * v : 1.055 * std::pow(v, 1.0 / 2.4) - 0.055; }

} // namespace

// ------------------------------------------------------------------------------------------ Image

TEST(Image, SizeLimits) {
  EXPECT_NO_THROW(Image(1, 1));
  EXPECT_NO_THROW(Image(kMaxImageSize, 1));
  EXPECT_THROW(Image(0, 5), Error);
  EXPECT_THROW(Image(5, 0), Error);
  EXPECT_THROW(Image(-1, 5), Error);
  EXPECT_THROW(Image(kMaxImageSize + 1, 1), Error);
  EXPECT_THROW(Image(1, kMaxImageSize + 1), Error);
  const Image img(7, 3);
  EXPECT_EQ(img.width(), 7);
  EXPECT_EQ(img.height(), 3);
  EXPECT_EQ(img.pixelCount(), 21u);
  EXPECT_EQ(img.index(2, 1), 9u);
}

TEST(Image, ChannelsKeepInsertionOrderAndCheckSizes) {
  Image img(2, 2);
  img.setChannel("sun.V", {1, 2, 3, 4});
  img.setChannel("B", {0, 0, 0, 0});
  img.setChannel("A", {5, 6, 7, 8});
  img.setChannel("B", {9, 9, 9, 9}); // replace keeps the position
  EXPECT_EQ(img.channelNames(), (std::vector<std::string>{"sun.V", "B", "A"}));
  EXPECT_TRUE(img.hasChannel("A"));
  EXPECT_FALSE(img.hasChannel("a"));
  EXPECT_EQ(img.channel("B"), (std::vector<float>{9, 9, 9, 9}));
  EXPECT_THROW(img.setChannel("C", {1, 2, 3}), Error);
  EXPECT_THROW(img.setChannel("", {1, 2, 3, 4}), Error);
  const std::string msg = errorOf([&] { img.channel("missing.V"); });
  EXPECT_NE(msg.find("missing.V"), std::string::npos) << msg;
  Image empty;
  EXPECT_THROW(empty.setChannel("R", {}), Error);
}

// ------------------------------------------------------------------------------------------ EXR

TEST(Exr, RoundTripIsBitExact) {
  test::TempDir dir;
  Image img(7, 5); // not square, odd sizes
  const std::vector<std::string> names = {"R", "G", "B", "sun.V", "lamp.shadow"};
  for (std::size_t c = 0; c < names.size(); ++c) {
    std::vector<float> v(img.pixelCount());
    for (std::size_t i = 0; i < v.size(); ++i)
      v[i] = std::sin(float(i) * 0.37f + float(c)) * std::pow(10.0f, float(int(i % 9) - 4));
    v[0] = -0.0f;
    v[1] = std::numeric_limits<float>::denorm_min();
    v[2] = std::numeric_limits<float>::max();
    v[3] = -std::numeric_limits<float>::min();
    img.setChannel(names[c], v);
  }
  const fs::path p = dir / "out.exr";
  writeExr(p, img);
  EXPECT_EQ(entries(dir.path()), 1u); // no temporary file left behind

  const std::string bytes = readBytes(p);
  ASSERT_GE(bytes.size(), 4u);
  EXPECT_EQ(bytes.substr(0, 4), std::string("\x76\x2f\x31\x01", 4)); // OpenEXR magic number
  // Header attribute: name "compression", type "compression", size 1, value ZIP_COMPRESSION (3).
  EXPECT_NE(bytes.find(std::string("compression\0compression\0\x01\0\0\0\x03", 29)), std::string::npos);
  for (const auto& n : names) { // one float channel per image channel, by name ("float" type tag 2)
    EXPECT_NE(bytes.find(n + std::string("\0\x02\0\0\0", 5)), std::string::npos) << n;
  }

  const Image back = readExr(p);
  EXPECT_EQ(back.width(), 7);
  EXPECT_EQ(back.height(), 5);
  EXPECT_EQ(back.channelCount(), names.size());
  for (const auto& n : names) {
    ASSERT_TRUE(back.hasChannel(n)) << n;
    const auto& a = img.channel(n);
    const auto& b = back.channel(n);
    ASSERT_EQ(a.size(), b.size());
    for (std::size_t i = 0; i < a.size(); ++i) EXPECT_TRUE(bitEqual(a[i], b[i])) << n << " pixel " << i;
  }
}

TEST(Exr, RowZeroIsTheTopRow) {
  test::TempDir dir;
  Image img(3, 2);
  img.setChannel("Y", {1, 2, 3, 4, 5, 6});
  writeExr(dir / "y.exr", img);
  EXPECT_EQ(readExr(dir / "y.exr").channel("Y"), (std::vector<float>{1, 2, 3, 4, 5, 6}));
}

TEST(Exr, ReadErrorsNameTheFile) {
  test::TempDir dir;
  const fs::path missing = dir / "missing.exr";
  std::string msg = errorOf([&] { readExr(missing); });
  EXPECT_NE(msg.find(missing.string()), std::string::npos) << msg;

  const fs::path garbage = dir / "garbage.exr";
  test::writeText(garbage, "this is not an OpenEXR file, just some text of a reasonable length............");
  msg = errorOf([&] { readExr(garbage); });
  EXPECT_NE(msg.find(garbage.string()), std::string::npos) << msg;

  // A truncated real file.
  Image img(16, 16);
  img.setChannel("R", std::vector<float>(256, 0.25f));
  writeExr(dir / "full.exr", img);
  const std::string bytes = readBytes(dir / "full.exr");
  const fs::path truncated = dir / "truncated.exr";
  test::writeText(truncated, bytes.substr(0, bytes.size() / 2));
  msg = errorOf([&] { readExr(truncated); });
  EXPECT_NE(msg.find(truncated.string()), std::string::npos) << msg;
}

TEST(Exr, NonFiniteValuesAreRejectedAndNoFileIsLeft) {
  test::TempDir dir;
  for (float bad : {std::numeric_limits<float>::quiet_NaN(), std::numeric_limits<float>::infinity(),
                    -std::numeric_limits<float>::infinity()}) {
    Image img(4, 3);
    img.setChannel("R", std::vector<float>(12, 0.5f));
    std::vector<float> v(12, 0.5f);
    v[img.index(2, 1)] = bad;
    img.setChannel("sun.V", v);
    const fs::path p = dir / "bad.exr";
    const std::string msg = errorOf([&] { writeExr(p, img); });
    EXPECT_NE(msg.find(p.string()), std::string::npos) << msg;
    EXPECT_NE(msg.find("sun.V"), std::string::npos) << msg;
    EXPECT_NE(msg.find("(2, 1)"), std::string::npos) << msg;
    EXPECT_FALSE(fs::exists(p));
    EXPECT_EQ(entries(dir.path()), 0u);
  }
}

TEST(Exr, FailedWriteKeepsTheOldFile) {
  test::TempDir dir;
  const fs::path p = dir / "keep.exr";
  Image good(2, 2);
  good.setChannel("R", {1, 2, 3, 4});
  writeExr(p, good);
  const std::string before = readBytes(p);
  Image bad(2, 2);
  bad.setChannel("R", {1, std::numeric_limits<float>::quiet_NaN(), 3, 4});
  EXPECT_THROW(writeExr(p, bad), Error);
  EXPECT_EQ(readBytes(p), before);
  EXPECT_EQ(entries(dir.path()), 1u);
}

TEST(Exr, WriteErrors) {
  test::TempDir dir;
  Image img(2, 2);
  img.setChannel("R", {1, 2, 3, 4});
  const fs::path p = dir / "no" / "such" / "dir" / "out.exr";
  const std::string msg = errorOf([&] { writeExr(p, img); });
  EXPECT_NE(msg.find(p.string()), std::string::npos) << msg;
  EXPECT_FALSE(fs::exists(p));
  EXPECT_EQ(entries(dir.path()), 0u);

  const fs::path q = dir / "nochannels.exr";
  const std::string msg2 = errorOf([&] { writeExr(q, Image(2, 2)); });
  EXPECT_NE(msg2.find(q.string()), std::string::npos) << msg2;
  EXPECT_FALSE(fs::exists(q));
}

// ------------------------------------------------------------------------------------------ PNG

TEST(Png, SrgbEncodingMatchesTheFormula) {
  // Values checked against the published piecewise definition (and its well-known numbers).
  EXPECT_FLOAT_EQ(linearToSrgb(0.0f), 0.0f);
  EXPECT_NEAR(linearToSrgb(0.0031308f), 0.0031308 * 12.92, 1e-6); // = 0.04045, the knee
  EXPECT_NEAR(linearToSrgb(0.0031308f), 0.04045, 1e-5);
  EXPECT_NEAR(linearToSrgb(0.5f), 1.055 * std::pow(0.5, 1.0 / 2.4) - 0.055, 1e-6);
  EXPECT_NEAR(linearToSrgb(0.5f), 0.735357, 1e-5);
  EXPECT_FLOAT_EQ(linearToSrgb(1.0f), 1.0f);
  EXPECT_NEAR(linearToSrgb(0.001f), 0.01292, 1e-7); // linear segment
  // Clamping.
  EXPECT_FLOAT_EQ(linearToSrgb(2.0f), 1.0f);
  EXPECT_FLOAT_EQ(linearToSrgb(-0.5f), 0.0f);
  EXPECT_FLOAT_EQ(linearToSrgb(std::numeric_limits<float>::infinity()), 1.0f);
  // Inverse.
  for (double v : {0.0, 0.002, 0.0031308, 0.01, 0.18, 0.5, 0.9, 1.0}) {
    EXPECT_NEAR(srgbToLinear(float(srgbFormula(v))), v, 2e-6) << v;
    EXPECT_NEAR(linearToSrgb(float(v)), srgbFormula(v), 2e-6) << v;
  }
  EXPECT_NEAR(srgbToLinear(0.04045f), 0.0031308, 1e-6);
  EXPECT_FLOAT_EQ(srgbToLinear(1.5f), 1.0f);
  EXPECT_FLOAT_EQ(srgbToLinear(-1.0f), 0.0f);
}

TEST(Png, GradientRoundTrip) {
  test::TempDir dir;
  // Row 0: R ramps through every byte; G ramps down; B constant; rows differ in B to catch row order.
  Image img(256, 3);
  std::vector<float> r(img.pixelCount()), g(img.pixelCount()), b(img.pixelCount());
  for (int y = 0; y < 3; ++y)
    for (int x = 0; x < 256; ++x) {
      const std::size_t i = img.index(x, y);
      r[i] = float(std::pow((x / 255.0 + 0.055) / 1.055, 2.4)); // linear value whose sRGB byte is x
      if (x / 255.0 <= 0.04045) r[i] = float(x / 255.0 / 12.92);
      g[i] = float(255 - x) / 255.0f; // linear ramp: bytes follow the formula
      b[i] = y == 0 ? 0.0f : y == 1 ? 0.5f : 1.0f;
    }
  img.setChannel("R", r);
  img.setChannel("G", g);
  img.setChannel("B", b);
  const fs::path p = dir / "ramp.png";
  writePng(p, img);
  EXPECT_EQ(entries(dir.path()), 1u);
  EXPECT_EQ(readBytes(p).substr(1, 3), "PNG");
  const PngPixels px = readPng(p);
  ASSERT_EQ(px.width, 256);
  ASSERT_EQ(px.height, 3);
  ASSERT_EQ(px.rgb.size(), 256u * 3u * 3u);
  for (int y = 0; y < 3; ++y)
    for (int x = 0; x < 256; ++x) {
      const std::size_t i = img.index(x, y);
      EXPECT_EQ(px.rgb[3 * i + 0], x) << x;
      EXPECT_EQ(px.rgb[3 * i + 1], int(std::lround(srgbFormula((255 - x) / 255.0) * 255.0))) << x;
      EXPECT_EQ(px.rgb[3 * i + 2], y == 0 ? 0 : y == 1 ? int(std::lround(srgbFormula(0.5) * 255.0)) : 255);
    }
  EXPECT_EQ(int(std::lround(srgbFormula(0.5) * 255.0)), 188); // 0.7354 * 255 = 187.5
}

TEST(Png, ClampingGreyAndChannelChoice) {
  test::TempDir dir;
  Image img(4, 1);
  img.setChannel("sun.V", {-1.0f, 0.0f, 1.0f, 7.5f});
  img.setChannel("other", {0.0f, 0.0f, 0.0f, 0.0f});
  writePng(dir / "grey.png", img, "sun.V", "sun.V", "sun.V");
  const PngPixels px = readPng(dir / "grey.png");
  const std::vector<std::uint8_t> expected = {0, 0, 0, 0, 0, 0, 255, 255, 255, 255, 255, 255};
  EXPECT_EQ(px.rgb, expected);
  writePng(dir / "mixed.png", img, "other", "sun.V", "other");
  EXPECT_EQ(readPng(dir / "mixed.png").rgb, (std::vector<std::uint8_t>{0, 0, 0, 0, 0, 0, 0, 255, 0, 0, 255, 0}));
}

TEST(Png, ErrorsNameTheFileAndLeaveNoFile) {
  test::TempDir dir;
  Image img(2, 2);
  img.setChannel("R", {0, 0.25f, 0.5f, 1});
  img.setChannel("G", {0, 0.25f, 0.5f, 1});
  img.setChannel("B", {0, 0.25f, 0.5f, 1});

  // Missing channel: names the file and the channel; nothing written.
  const fs::path p = dir / "x.png";
  std::string msg = errorOf([&] { writePng(p, img, "R", "G", "sun.V"); });
  EXPECT_NE(msg.find(p.string()), std::string::npos) << msg;
  EXPECT_NE(msg.find("sun.V"), std::string::npos) << msg;
  EXPECT_FALSE(fs::exists(p));

  // Missing directory.
  const fs::path q = dir / "nope" / "x.png";
  msg = errorOf([&] { writePng(q, img); });
  EXPECT_NE(msg.find(q.string()), std::string::npos) << msg;
  EXPECT_EQ(entries(dir.path()), 0u);

  // NaN: rejected, an existing file is kept as it was.
  writePng(p, img);
  const std::string before = readBytes(p);
  Image nan = img;
  nan.setChannel("G", {0, std::numeric_limits<float>::quiet_NaN(), 0, 0});
  msg = errorOf([&] { writePng(p, nan); });
  EXPECT_NE(msg.find(p.string()), std::string::npos) << msg;
  EXPECT_NE(msg.find("'G'"), std::string::npos) << msg;
  EXPECT_EQ(readBytes(p), before);
  EXPECT_EQ(entries(dir.path()), 1u);

  // Reading: missing, garbage, truncated.
  const fs::path missing = dir / "missing.png";
  msg = errorOf([&] { readPng(missing); });
  EXPECT_NE(msg.find(missing.string()), std::string::npos) << msg;
  const fs::path garbage = dir / "garbage.png";
  test::writeText(garbage, "definitely not a PNG file");
  msg = errorOf([&] { readPng(garbage); });
  EXPECT_NE(msg.find(garbage.string()), std::string::npos) << msg;
  const fs::path truncated = dir / "truncated.png";
  test::writeText(truncated, before.substr(0, before.size() - 20));
  msg = errorOf([&] { readPng(truncated); });
  EXPECT_NE(msg.find(truncated.string()), std::string::npos) << msg;
}
