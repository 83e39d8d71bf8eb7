// Image error metrics: RMSE and mean absolute difference on hand-computed examples, and LDR-FLIP checked
// against properties of its definition and against values derived by hand (constant-colour image pairs).
#include "image/ImageMetrics.h"
#include "util/Error.h"

#include <glm/glm.hpp>
#include <gtest/gtest.h>
#include <tbb/task_arena.h>

#include <algorithm>
#include <cmath>
#include <limits>
#include <random>

using namespace rtsdf;

namespace {

std::vector<glm::vec3> constant(int w, int h, glm::vec3 c) { return std::vector<glm::vec3>(std::size_t(w) * h, c); }

/// A smooth colourful test pattern (sRGB values in [0.1, 0.9]).
std::vector<glm::vec3> pattern(int w, int h) {
  std::vector<glm::vec3> img(std::size_t(w) * h);
  for (int y = 0; y < h; ++y)
    for (int x = 0; x < w; ++x)
      img[std::size_t(y) * w + x] = glm::vec3(0.5f + 0.4f * std::sin(0.21f * x), 0.5f + 0.4f * std::cos(0.17f * y),
                                              0.5f + 0.4f * std::sin(0.05f * (x + y)));
  return img;
}

/// @a img plus amplitude * (a fixed uniform noise pattern in [-1, 1]), clamped to [0, 1].
std::vector<glm::vec3> addNoise(std::vector<glm::vec3> img, float amplitude) {
  std::mt19937 rng(1234);
  std::uniform_real_distribution<float> u(-1.0f, 1.0f);
  for (auto& c : img) {
    const glm::vec3 n(u(rng), u(rng), u(rng));
    c = glm::clamp(c + amplitude * n, 0.0f, 1.0f);
  }
  return img;
}

// ---- An independent, double-precision evaluation of FLIP's colour pipeline for CONSTANT images.
// For a constant image pair the spatial CSF filters (normalised to unit sum, clamp-to-edge borders) leave the
// YCxCz values unchanged, the YCxCz -> XYZ -> linear RGB round trip is the identity (no clamping for colours in
// the sRGB gamut), and every edge/point detector response is zero (the derivative kernels' weights sum to zero),
// so the feature difference is 0 and FLIP = dEc^(1 - 0) = dEc, computed from the paper's formulas:
//   L*a*b* (CIE 1976, white = the sRGB matrix applied to (1, 1, 1)), Hunt: a* *= 0.01 L*, b* *= 0.01 L*,
//   HyAB = |dL| + sqrt(da^2 + db^2), dEc' = HyAB^qc with qc = 0.7, cmax = HyAB(green, blue)^qc,
//   dEc = dEc' * pt / (pc cmax) below pc cmax, else pt + (dEc' - pc cmax) / (cmax - pc cmax) * (1 - pt),
//   pc = 0.4, pt = 0.95.
// The RGB->XYZ matrix here is the textbook one (IEC 61966-2-1 primaries, as tabulated by B. Lindbloom), not the
// implementation's constants; the FLIP values agree to ~4e-5, hence the tolerance of 2e-4.

double decodeSrgb(double s) { return s <= 0.04045 ? s / 12.92 : std::pow((s + 0.055) / 1.055, 2.4); }

struct Lab { double L, a, b; };

Lab huntLab(const glm::dvec3& srgb) {
  static const double M[3][3] = {{0.4124564, 0.3575761, 0.1804375},
                                 {0.2126729, 0.7151522, 0.0721750},
                                 {0.0193339, 0.1191920, 0.9503041}};
  const double rgb[3] = {decodeSrgb(srgb.x), decodeSrgb(srgb.y), decodeSrgb(srgb.z)};
  double t[3];
  for (int i = 0; i < 3; ++i) {
    const double white = M[i][0] + M[i][1] + M[i][2];
    t[i] = (M[i][0] * rgb[0] + M[i][1] * rgb[1] + M[i][2] * rgb[2]) / white;
  }
  const double d = 6.0 / 29.0;
  auto f = [&](double v) { return v > d * d * d ? std::cbrt(v) : v / (3.0 * d * d) + 4.0 / 29.0; };
  const double L = 116.0 * f(t[1]) - 16.0;
  const double a = 500.0 * (f(t[0]) - f(t[1])), b = 200.0 * (f(t[1]) - f(t[2]));
  return {L, 0.01 * L * a, 0.01 * L * b};
}

double hyab(const Lab& p, const Lab& q) { return std::fabs(p.L - q.L) + std::hypot(p.a - q.a, p.b - q.b); }

double expectedConstantFlip(const glm::dvec3& ref, const glm::dvec3& test) {
  const double qc = 0.7, pc = 0.4, pt = 0.95;
  const double cmax = std::pow(hyab(huntLab({0, 1, 0}), huntLab({0, 0, 1})), qc);
  const double e = std::pow(hyab(huntLab(ref), huntLab(test)), qc);
  return e < pc * cmax ? e * pt / (pc * cmax) : pt + (e - pc * cmax) / (cmax - pc * cmax) * (1.0 - pt);
}

} // namespace

// ------------------------------------------------------------------------------------------ RMSE

TEST(Rmse, HandComputedExamples) {
  // Differences (0, 0, 0, -4): RMSE = sqrt(16 / 4) = 2, mean |d| = 4 / 4 = 1.
  const std::vector<float> a = {1, 2, 3, 4}, b = {1, 2, 3, 8};
  EXPECT_DOUBLE_EQ(rmse(a, b), 2.0);
  EXPECT_DOUBLE_EQ(meanAbsDifference(a, b), 1.0);
  // Differences (-3, 4): RMSE = sqrt((9 + 16) / 2) = sqrt(12.5), mean |d| = 3.5.
  EXPECT_DOUBLE_EQ(rmse({0, 0}, {3, 4}), std::sqrt(12.5));
  EXPECT_DOUBLE_EQ(meanAbsDifference({0, 0}, {3, 4}), 3.5);
  EXPECT_DOUBLE_EQ(rmse(a, a), 0.0);
  // Order of arguments does not matter for these two.
  EXPECT_DOUBLE_EQ(rmse(b, a), 2.0);
}

TEST(Rmse, Masks) {
  const std::vector<float> a = {1, 2, 3, 4}, b = {1, 2, 3, 8};
  EXPECT_DOUBLE_EQ(rmse(a, b, {1, 1, 1, 0}), 0.0);
  EXPECT_DOUBLE_EQ(rmse(a, b, {0, 0, 0, 1}), 4.0);
  EXPECT_DOUBLE_EQ(rmse(a, b, {0, 7, 0, 255}), std::sqrt(8.0)); // any non-zero selects: (0 + 16) / 2
  EXPECT_DOUBLE_EQ(meanAbsDifference(a, b, {0, 1, 0, 1}), 2.0);
  EXPECT_DOUBLE_EQ(meanAbsDifference(a, b, {}), 1.0); // empty mask: all pixels
}

TEST(Rmse, LargeInputIsExact) {
  // 1e6 pixels, half differ by 3: RMSE = sqrt(9 / 2), mean |d| = 1.5 (exact in double).
  std::vector<float> a(1000000, 0.25f), b = a;
  for (std::size_t i = 0; i < b.size(); i += 2) b[i] += 3.0f;
  EXPECT_DOUBLE_EQ(rmse(a, b), std::sqrt(4.5));
  EXPECT_DOUBLE_EQ(meanAbsDifference(a, b), 1.5);
}

TEST(Rmse, LargeInputIsSymmetricAccurateAndDeterministic) {
  // Random differences: the sums are not exact, so the summation order shows in the last bits.
  std::mt19937 rng(99);
  std::uniform_real_distribution<float> u(-2.0f, 2.0f);
  std::vector<float> a(1000003), b(a.size());
  for (std::size_t i = 0; i < a.size(); ++i) a[i] = u(rng), b[i] = u(rng);
  long double sq = 0.0L, ab = 0.0L; // serial, extended precision: an independent reference
  for (std::size_t i = 0; i < a.size(); ++i) {
    const long double d = (long double)a[i] - (long double)b[i];
    sq += d * d;
    ab += std::fabs(d);
  }
  const double r = rmse(a, b), m = meanAbsDifference(a, b);
  // Measured: 2.5e-14 off for the RMSE, 0 for the mean (double sums of 1e6 terms).
  EXPECT_NEAR(r, double(std::sqrt(sq / a.size())), 5e-14);
  EXPECT_NEAR(m, double(ab / a.size()), 5e-14);
  EXPECT_EQ(rmse(b, a), r); // (-d)^2 == d^2 and |-d| == |d| bit for bit, whatever the order
  EXPECT_EQ(meanAbsDifference(b, a), m);
  // A fixed reduction tree: one thread gives the same bits as all of them.
  tbb::task_arena one(1);
  one.execute([&] {
    EXPECT_EQ(rmse(a, b), r);
    EXPECT_EQ(meanAbsDifference(a, b), m);
  });
}

TEST(Rmse, Errors) {
  EXPECT_THROW(rmse({1, 2}, {1, 2, 3}), Error);
  EXPECT_THROW(meanAbsDifference({1, 2}, {1}), Error);
  EXPECT_THROW(rmse({1, 2}, {1, 2}, {1}), Error);       // mask size
  EXPECT_THROW(rmse({1, 2}, {1, 2}, {0, 0}), Error);    // nothing selected
  EXPECT_THROW(rmse({}, {}), Error);                    // empty
  EXPECT_THROW(meanAbsDifference({}, {}), Error);
}

// ------------------------------------------------------------------------------------------ FLIP

TEST(Flip, IdenticalImagesGiveZeroEverywhere) {
  const auto img = addNoise(pattern(37, 23), 0.2f);
  const FlipResult r = flip(img, img, 37, 23);
  ASSERT_EQ(r.errorMap.size(), 37u * 23u);
  for (float e : r.errorMap) EXPECT_EQ(e, 0.0f);
  EXPECT_EQ(r.mean, 0.0);
}

TEST(Flip, ErrorMapWithinUnitIntervalAndMeanIsItsAverage) {
  const int w = 48, h = 40;
  const auto ref = pattern(w, h);
  for (float amp : {0.05f, 0.5f, 1.0f}) {
    const FlipResult r = flip(ref, addNoise(ref, amp), w, h);
    double sum = 0.0;
    for (float e : r.errorMap) {
      EXPECT_GE(e, 0.0f);
      EXPECT_LE(e, 1.0f);
      sum += e;
    }
    EXPECT_NEAR(r.mean, sum / double(w * h), 1e-12);
  }
  // Extreme inputs, including out-of-range values (clamped) and saturated colours.
  std::vector<glm::vec3> a(std::size_t(w) * h), b(a.size());
  std::mt19937 rng(7);
  std::uniform_int_distribution<int> bit(0, 1);
  for (std::size_t i = 0; i < a.size(); ++i) {
    a[i] = glm::vec3(float(bit(rng)), float(bit(rng)), float(bit(rng))) * 1.5f - 0.2f;
    b[i] = glm::vec3(float(bit(rng)), float(bit(rng)), float(bit(rng)));
  }
  for (float e : flip(a, b, w, h).errorMap) {
    EXPECT_GE(e, 0.0f);
    EXPECT_LE(e, 1.0f);
  }
}

TEST(Flip, MeanGrowsWithNoiseAmplitude) {
  const int w = 64, h = 48;
  const auto ref = pattern(w, h);
  double previous = 0.0;
  for (float amp : {0.005f, 0.02f, 0.05f, 0.1f, 0.2f}) {
    const double m = flip(ref, addNoise(ref, amp), w, h).mean;
    EXPECT_GT(m, previous) << "amplitude " << amp;
    previous = m;
  }
}

TEST(Flip, BlackVersusWhiteByHand) {
  // Black: L* = 0. White: L* = 100, a* = b* = 0. HyAB = 100, 100^0.7 = 25.12.
  // Green (L* 87.73, a* -86.18, b* 83.18) and blue (32.30, 79.19, -107.86), Hunt-adjusted: (-75.61, 72.98) and
  // (25.58, -34.84): HyAB = 55.43 + 147.87 = 203.30, cmax = 203.30^0.7 = 41.28, pc cmax = 16.51.
  // 25.12 > 16.51: FLIP = 0.95 + (25.12 - 16.51) / (41.28 - 16.51) * 0.05 = 0.9674.
  const int w = 24, h = 17;
  const FlipResult r = flip(constant(w, h, glm::vec3(0.0f)), constant(w, h, glm::vec3(1.0f)), w, h);
  EXPECT_NEAR(r.mean, 0.9674, 1e-3);
  EXPECT_NEAR(r.mean, expectedConstantFlip({0, 0, 0}, {1, 1, 1}), 2e-4);
  for (float e : r.errorMap) EXPECT_NEAR(e, r.mean, 1e-5); // uniform, borders included
}

TEST(Flip, ConstantColourPairsMatchTheColourPipelineDerivedByHand) {
  struct Case {
    glm::vec3 ref, test;
  };
  const Case cases[] = {
      {{0.5f, 0.5f, 0.5f}, {0.6f, 0.6f, 0.6f}},     // achromatic, below pc * cmax
      {{0.8f, 0.2f, 0.2f}, {0.2f, 0.2f, 0.8f}},     // red vs blue: chroma, above pc * cmax
      {{0.3f, 0.6f, 0.2f}, {0.32f, 0.6f, 0.2f}},    // small chromatic change
      {{0.1f, 0.1f, 0.1f}, {0.1f, 0.1f, 0.12f}},    // dark, blue-yellow only
      {{0.9f, 0.85f, 0.2f}, {0.2f, 0.85f, 0.9f}},   // yellow vs cyan
      {{0.02f, 0.01f, 0.0f}, {0.0f, 0.0f, 0.0f}},   // linear segment of the sRGB curve, near black
  };
  const int w = 21, h = 13;
  for (const Case& c : cases) {
    const double expected = expectedConstantFlip(c.ref, c.test);
    for (double ppd : {67.0, 30.0, 120.0}) { // no spatial structure: the viewing distance must not matter
      const FlipResult r = flip(constant(w, h, c.ref), constant(w, h, c.test), w, h, ppd);
      EXPECT_NEAR(r.mean, expected, 2e-4) << "ppd " << ppd << " ref (" << c.ref.x << ", " << c.ref.y << ", "
                                          << c.ref.z << ")";
      const auto [lo, hi] = std::minmax_element(r.errorMap.begin(), r.errorMap.end());
      EXPECT_NEAR(*lo, *hi, 1e-5); // uniform, borders included
    }
  }
  // Spot values of the hand derivation itself (so a mistake there cannot hide behind the comparison above).
  EXPECT_NEAR(expectedConstantFlip({0.5, 0.5, 0.5}, {0.6, 0.6, 0.6}), 0.2850, 1e-3);
  EXPECT_NEAR(expectedConstantFlip({0.8, 0.2, 0.2}, {0.2, 0.2, 0.8}), 0.9511, 1e-3);
}

TEST(Flip, SinglePixelEdgeShiftIsDetected) {
  // A vertical black/white edge at x = 32 in the reference and x = 33 in the test: column 32 differs.
  const int w = 64, h = 32;
  std::vector<glm::vec3> ref(std::size_t(w) * h), test(ref.size());
  for (int y = 0; y < h; ++y)
    for (int x = 0; x < w; ++x) {
      ref[std::size_t(y) * w + x] = glm::vec3(x >= 32 ? 1.0f : 0.0f);
      test[std::size_t(y) * w + x] = glm::vec3(x >= 33 ? 1.0f : 0.0f);
    }
  const FlipResult r = flip(ref, test, w, h);
  EXPECT_GT(r.mean, 0.0);
  for (int y = 0; y < h; ++y) {
    const float* row = r.errorMap.data() + std::size_t(y) * w;
    EXPECT_GT(row[32], 0.3f) << y; // the shifted column
    // The error peaks at the change (the CSF blur spreads it over a few pixels) ...
    const int peak = int(std::max_element(row, row + w) - row);
    EXPECT_LE(std::abs(peak - 32), 2) << y;
    EXPECT_GT(row[peak], 0.5f) << y;
    // ... and is exactly zero beyond the filters' reach: at 67 ppd the CSF radius is 10 pixels and the feature
    // radius 9, so pixels more than 10 pixels from both columns 32 and 33 see identical neighbourhoods.
    for (int x = 0; x < w; ++x)
      if (x < 32 - 10 || x > 33 + 10) EXPECT_EQ(row[x], 0.0f) << x << ", " << y;
  }
  // The same shift on a thin line: a one-pixel white line moved by one pixel.
  for (int y = 0; y < h; ++y)
    for (int x = 0; x < w; ++x) {
      ref[std::size_t(y) * w + x] = glm::vec3(x == 20 ? 1.0f : 0.0f);
      test[std::size_t(y) * w + x] = glm::vec3(x == 21 ? 1.0f : 0.0f);
    }
  const FlipResult line = flip(ref, test, w, h);
  EXPECT_GT(line.errorMap[std::size_t(h / 2) * w + 20], 0.3f);
  EXPECT_GT(line.errorMap[std::size_t(h / 2) * w + 21], 0.3f);
}

TEST(Flip, MaskedMean) {
  const int w = 32, h = 16;
  const auto ref = pattern(w, h);
  const FlipResult r = flip(ref, addNoise(ref, 0.1f), w, h);
  std::vector<std::uint8_t> mask(r.errorMap.size(), 0);
  double sum = 0.0;
  int n = 0;
  for (int y = 4; y < 9; ++y)
    for (int x = 3; x < 20; ++x) {
      mask[std::size_t(y) * w + x] = 1;
      sum += r.errorMap[std::size_t(y) * w + x];
      ++n;
    }
  EXPECT_NEAR(maskedMean(r, mask), sum / n, 1e-12);
  EXPECT_NEAR(maskedMean(r, {}), r.mean, 1e-12);
  EXPECT_THROW(maskedMean(r, std::vector<std::uint8_t>(10, 1)), Error);
  EXPECT_THROW(maskedMean(r, std::vector<std::uint8_t>(r.errorMap.size(), 0)), Error);
}

TEST(Flip, Errors) {
  const auto a = constant(4, 4, glm::vec3(0.5f));
  EXPECT_THROW(flip(a, a, 4, 3), Error);
  EXPECT_THROW(flip(a, constant(4, 3, glm::vec3(0.5f)), 4, 4), Error);
  EXPECT_THROW(flip({}, {}, 0, 0), Error);
  EXPECT_THROW(flip(a, a, 4, 4, 0.0), Error);
  EXPECT_THROW(flip(a, a, 4, 4, -5.0), Error);
  EXPECT_THROW(flip(a, a, 4, 4, std::numeric_limits<double>::quiet_NaN()), Error);
  auto nan = a;
  nan[5].y = std::numeric_limits<float>::quiet_NaN();
  EXPECT_THROW(flip(a, nan, 4, 4), Error);
}

TEST(Flip, TinyImagesAndDeterminism) {
  // 1x1 and 1xN images only exercise the clamped borders.
  const FlipResult one = flip({glm::vec3(0.0f)}, {glm::vec3(1.0f)}, 1, 1);
  EXPECT_NEAR(one.mean, expectedConstantFlip({0, 0, 0}, {1, 1, 1}), 2e-4);
  const auto ref = pattern(97, 61);
  const auto test = addNoise(ref, 0.07f);
  const FlipResult r1 = flip(ref, test, 97, 61), r2 = flip(ref, test, 97, 61);
  EXPECT_EQ(r1.errorMap, r2.errorMap);
  EXPECT_EQ(r1.mean, r2.mean);
}
