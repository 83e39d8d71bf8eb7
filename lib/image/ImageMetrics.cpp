#include "image/ImageMetrics.h"

#include "image/ImageIO.h"
#include "util/Error.h"

#include <fmt/format.h>
#include <glm/glm.hpp>
#include <tbb/blocked_range.h>
#include <tbb/parallel_for.h>
#include <tbb/parallel_reduce.h>

#include <algorithm>
#include <cmath>
#include <limits>

namespace rtsdf {
namespace {

// ------------------------------------------------------------------------------------------ RMSE, mean abs

struct Sum {
  double sum = 0.0;
  std::size_t n = 0;
};

/// Mean of term(a[i] - b[i]) over the selected pixels; deterministic (fixed reduction tree).
template <class Term>
double meanOver(const char* what, const std::vector<float>& a, const std::vector<float>& b,
                const std::vector<std::uint8_t>& mask, Term term) {
  if (a.size() != b.size())
    throw Error(fmt::format("{}: the images differ in size ({} vs {} values)", what, a.size(), b.size()));
  if (!mask.empty() && mask.size() != a.size())
    throw Error(fmt::format("{}: the mask has {} values but the images have {}", what, mask.size(), a.size()));
  const Sum s = tbb::parallel_deterministic_reduce(
      tbb::blocked_range<std::size_t>(0, a.size(), 1 << 14), Sum{},
      [&](const tbb::blocked_range<std::size_t>& r, Sum s) {
        for (std::size_t i = r.begin(); i != r.end(); ++i)
          if (mask.empty() || mask[i]) {
            s.sum += term(double(a[i]) - double(b[i]));
            ++s.n;
          }
        return s;
      },
      [](Sum x, const Sum& y) { return Sum{x.sum + y.sum, x.n + y.n}; });
  if (s.n == 0) throw Error(fmt::format("{}: no pixel selected (empty images or an all-zero mask)", what));
  return s.sum / double(s.n);
}

// ------------------------------------------------------------------------------------------ FLIP
// Constants and steps follow NVIDIA's reference implementation of LDR-FLIP: repository NVlabs/flip, file
// flip_evaluator/cpp/FLIP.h (FLIP 1.x, BSD-3-Clause; also cpp/FLIP.h), which implements the HPG 2020 paper.
// As there, the CSF filters are applied separably (NVlabs/flip misc/separatedConvolutions.pdf: the sum of two
// Gaussians of the blue-yellow channel becomes two separable passes), borders are clamped to edge, and all
// per-pixel arithmetic is in float.

constexpr float kPi = 3.14159265358979f;
constexpr float kQc = 0.7f;   // colour difference exponent
constexpr float kPc = 0.4f;   // cmax fraction where the error remapping changes slope
constexpr float kPt = 0.95f;  // remapped error at pc * cmax
constexpr float kW = 0.082f;  // feature filter width in degrees
constexpr float kQf = 0.5f;   // feature difference exponent

/// Spatial CSF of one opponent channel: a1*sqrt(pi/b1)*exp(-pi^2 x^2/b1) + a2*sqrt(pi/b2)*exp(-pi^2 x^2/b2).
struct Csf {
  float a1, b1, a2, b2;
};
constexpr Csf kCsfY{1.0f, 0.0047f, 0.0f, 1.0e-5f};    // achromatic
constexpr Csf kCsfCx{1.0f, 0.0053f, 0.0f, 1.0e-5f};   // red-green
constexpr Csf kCsfCz{34.1f, 0.04f, 13.5f, 0.025f};    // blue-yellow

const glm::vec3 kD65{0.950428545f, 1.000000000f, 1.088900371f};     // reference white (XYZ)
const glm::vec3 kInvD65{1.052156925f, 1.000000000f, 0.918357670f};  // its inverse

glm::vec3 linearRgbToXyz(const glm::vec3& c) {
  // sRGB primaries, D65 (the reference's exact fractions).
  const float a11 = 10135552.0f / 24577794.0f, a12 = 8788810.0f / 24577794.0f, a13 = 4435075.0f / 24577794.0f;
  const float a21 = 2613072.0f / 12288897.0f, a22 = 8788810.0f / 12288897.0f, a23 = 887015.0f / 12288897.0f;
  const float a31 = 1425312.0f / 73733382.0f, a32 = 8788810.0f / 73733382.0f, a33 = 70074185.0f / 73733382.0f;
  return {a11 * c.x + a12 * c.y + a13 * c.z, a21 * c.x + a22 * c.y + a23 * c.z, a31 * c.x + a32 * c.y + a33 * c.z};
}

glm::vec3 xyzToLinearRgb(const glm::vec3& c) {
  return {3.241003275f * c.x - 1.537398934f * c.y - 0.498615861f * c.z,
          -0.969224334f * c.x + 1.875930071f * c.y + 0.041554224f * c.z,
          0.055639423f * c.x - 0.204011202f * c.y + 1.057148933f * c.z};
}

glm::vec3 xyzToYCxCz(glm::vec3 xyz) {
  xyz *= kInvD65;
  return {116.0f * xyz.y - 16.0f, 500.0f * (xyz.x - xyz.y), 200.0f * (xyz.y - xyz.z)};
}

glm::vec3 yCxCzToXyz(const glm::vec3& v) {
  const float y = (v.x + 16.0f) / 116.0f, cx = v.y / 500.0f, cz = v.z / 200.0f;
  return glm::vec3(y + cx, y, y - cz) * kD65;
}

glm::vec3 xyzToLab(glm::vec3 xyz) {
  const float delta = 6.0f / 29.0f, deltaSquare = delta * delta, deltaCube = delta * deltaSquare;
  const float factor = 1.0f / (3.0f * deltaSquare), term = 4.0f / 29.0f;
  xyz *= kInvD65;
  auto f = [&](float t) { return t > deltaCube ? std::pow(t, 1.0f / 3.0f) : factor * t + term; };
  const float fx = f(xyz.x), fy = f(xyz.y), fz = f(xyz.z);
  return {116.0f * fy - 16.0f, 500.0f * (fx - fy), 200.0f * (fy - fz)};
}

/// Linear RGB -> L*a*b* with the Hunt adjustment of a* and b* (chroma scaled by 0.01 L*).
glm::vec3 huntLab(const glm::vec3& linearRgb) {
  const glm::vec3 lab = xyzToLab(linearRgbToXyz(linearRgb));
  return {lab.x, 0.01f * lab.x * lab.y, 0.01f * lab.x * lab.z};
}

/// HyAB distance: city block in L*, Euclidean in (a*, b*).
float hyab(const glm::vec3& p, const glm::vec3& q) {
  const float da = p.y - q.y, db = p.z - q.z;
  return std::fabs(p.x - q.x) + std::sqrt(da * da + db * db);
}

/// cmax: the Hunt-adjusted HyAB distance of pure green and pure blue, raised to qc.
float maxColourDistance() {
  return std::pow(hyab(huntLab({0.0f, 1.0f, 0.0f}), huntLab({0.0f, 0.0f, 1.0f})), kQc);
}

float gaussian(float x2, float a, float b) { return a * std::sqrt(kPi / b) * std::exp(-kPi * kPi * x2 / b); }
/// Square root of the 2D Gaussian's amplitude: g(x) g(y) is then the 2D Gaussian (separated convolution).
float gaussianSqrt(float x2, float a, float b) {
  return std::sqrt(a * std::sqrt(kPi / b)) * std::exp(-kPi * kPi * x2 / b);
}

/// The 1D spatial filters, normalised so each 2D filter sums to one.
/// yCx: (Y, Cx) weights; cz: the two Gaussians of Cz (their separable products are summed).
struct SpatialFilters {
  int radius = 0;
  std::vector<glm::vec2> yCx, cz;
};

SpatialFilters makeSpatialFilters(float ppd) {
  SpatialFilters f;
  const float maxB = std::max({kCsfY.b1, kCsfY.b2, kCsfCx.b1, kCsfCx.b2, kCsfCz.b1, kCsfCz.b2});
  f.radius = int(std::ceil(3.0f * std::sqrt(maxB / (2.0f * kPi * kPi)) * ppd));
  const int width = 2 * f.radius + 1;
  const float deltaX = 1.0f / ppd; // degrees per pixel
  glm::vec2 sumYCx(0.0f), sumCz(0.0f);
  for (int x = 0; x < width; ++x) {
    const float ix = float(x - f.radius) * deltaX, ix2 = ix * ix;
    const glm::vec2 yCx(gaussian(ix2, kCsfY.a1, kCsfY.b1), gaussian(ix2, kCsfCx.a1, kCsfCx.b1));
    const glm::vec2 cz(gaussianSqrt(ix2, kCsfCz.a1, kCsfCz.b1), gaussianSqrt(ix2, kCsfCz.a2, kCsfCz.b2));
    f.yCx.push_back(yCx);
    f.cz.push_back(cz);
    sumYCx += yCx;
    sumCz += cz;
  }
  const glm::vec2 normYCx = 1.0f / sumYCx;
  const float normCz = 1.0f / std::sqrt(sumCz.x * sumCz.x + sumCz.y * sumCz.y);
  for (int x = 0; x < width; ++x) {
    f.yCx[x] *= normYCx;
    f.cz[x] *= normCz;
  }
  return f;
}

/// The 1D feature filters (Gaussian, first and second derivative), sigma = w/2 degrees: the Gaussian sums to
/// one; the positive and the negative weights of each derivative sum to +1 and -1.
struct FeatureFilter {
  int radius = 0;
  std::vector<glm::vec3> weights; // (g, dg, ddg)
};

FeatureFilter makeFeatureFilter(float ppd) {
  FeatureFilter f;
  const float stdDev = 0.5f * kW * ppd;
  f.radius = int(std::ceil(3.0f * stdDev));
  const int width = 2 * f.radius + 1;
  float gSum = 0.0f, dgPos = 0.0f, dgNeg = 0.0f, ddgPos = 0.0f, ddgNeg = 0.0f;
  for (int x = 0; x < width; ++x) {
    const float xx = float(x - f.radius);
    const float g = std::exp(-(xx * xx) / (2.0f * stdDev * stdDev));
    const float dg = -xx * g;
    const float ddg = (xx * xx / (stdDev * stdDev) - 1.0f) * g;
    gSum += g;
    (dg > 0.0f ? dgPos : dgNeg) += std::fabs(dg);
    (ddg > 0.0f ? ddgPos : ddgNeg) += std::fabs(ddg);
    f.weights.emplace_back(g, dg, ddg);
  }
  // Guard (not in the reference): at very low ppd the tails underflow to zero; a zero sum gives zero weights
  // instead of 0/0.
  auto divide = [](float v, float s) { return s > 0.0f ? v / s : 0.0f; };
  for (auto& w : f.weights)
    w = glm::vec3(divide(w.x, gSum), divide(w.y, w.y > 0.0f ? dgPos : dgNeg), divide(w.z, w.z > 0.0f ? ddgPos : ddgNeg));
  return f;
}

inline int clampIndex(int i, int n) { return std::min(std::max(i, 0), n - 1); }

using Rows = tbb::blocked_range<int>;

/// Spatially filtered colour difference of two YCxCz images, remapped to [0, 1].
std::vector<float> colourDifference(const std::vector<glm::vec3>& ref, const std::vector<glm::vec3>& test, int w,
                                    int h, float ppd) {
  const SpatialFilters f = makeSpatialFilters(ppd);
  const int r = f.radius;
  const std::size_t n = std::size_t(w) * std::size_t(h);
  // Horizontal pass: (Y, Cx) with their Gaussians, Cz with each of its two Gaussians.
  std::vector<glm::vec2> refYCx(n), refCz(n), testYCx(n), testCz(n);
  tbb::parallel_for(Rows(0, h), [&](const Rows& rows) {
    for (int y = rows.begin(); y != rows.end(); ++y)
      for (int x = 0; x < w; ++x) {
        glm::vec2 rYCx(0.0f), rCz(0.0f), tYCx(0.0f), tCz(0.0f);
        for (int ix = -r; ix <= r; ++ix) {
          const std::size_t j = std::size_t(y) * w + clampIndex(x + ix, w);
          const glm::vec2 wYCx = f.yCx[ix + r], wCz = f.cz[ix + r];
          rYCx += wYCx * glm::vec2(ref[j].x, ref[j].y);
          tYCx += wYCx * glm::vec2(test[j].x, test[j].y);
          rCz += wCz * ref[j].z;
          tCz += wCz * test[j].z;
        }
        const std::size_t i = std::size_t(y) * w + x;
        refYCx[i] = rYCx;
        refCz[i] = rCz;
        testYCx[i] = tYCx;
        testCz[i] = tCz;
      }
  });
  const float cmax = maxColourDistance(), pccmax = kPc * cmax;
  std::vector<float> diff(n);
  // Vertical pass (rows of accumulators, same summation order per pixel), then the colour difference.
  tbb::parallel_for(Rows(0, h), [&](const Rows& rows) {
    std::vector<glm::vec2> rYCx(w), rCz(w), tYCx(w), tCz(w);
    for (int y = rows.begin(); y != rows.end(); ++y) {
      std::fill(rYCx.begin(), rYCx.end(), glm::vec2(0.0f));
      std::fill(rCz.begin(), rCz.end(), glm::vec2(0.0f));
      std::fill(tYCx.begin(), tYCx.end(), glm::vec2(0.0f));
      std::fill(tCz.begin(), tCz.end(), glm::vec2(0.0f));
      for (int iy = -r; iy <= r; ++iy) {
        const std::size_t row = std::size_t(clampIndex(y + iy, h)) * w;
        const glm::vec2 wYCx = f.yCx[iy + r], wCz = f.cz[iy + r];
        for (int x = 0; x < w; ++x) {
          rYCx[x] += wYCx * refYCx[row + x];
          tYCx[x] += wYCx * testYCx[row + x];
          rCz[x] += wCz * refCz[row + x];
          tCz[x] += wCz * testCz[row + x];
        }
      }
      for (int x = 0; x < w; ++x) {
        // Back to linear RGB, clamped to [0, 1], then L*a*b* with the Hunt adjustment.
        auto toHuntLab = [](const glm::vec2& yCx, const glm::vec2& cz) {
          const glm::vec3 yCxCz(yCx.x, yCx.y, cz.x + cz.y);
          return huntLab(glm::clamp(xyzToLinearRgb(yCxCzToXyz(yCxCz)), 0.0f, 1.0f));
        };
        float d = std::pow(hyab(toHuntLab(rYCx[x], rCz[x]), toHuntLab(tYCx[x], tCz[x])), kQc);
        // Remap to [0, 1]: [0, pc*cmax) -> [0, pt), [pc*cmax, cmax] -> [pt, 1].
        if (d < pccmax) d *= kPt / pccmax;
        else d = kPt + ((d - pccmax) / (cmax - pccmax)) * (1.0f - kPt);
        diff[std::size_t(y) * w + x] = d;
      }
    }
  });
  return diff;
}

/// Feature (edge and point) difference of the two images' achromatic channels, combined with the colour
/// difference @a colour into the FLIP error (written over @a colour).
void applyFeatureDifference(const std::vector<glm::vec3>& ref, const std::vector<glm::vec3>& test, int w, int h,
                            float ppd, std::vector<float>& colour) {
  const FeatureFilter f = makeFeatureFilter(ppd);
  const int r = f.radius;
  const std::size_t n = std::size_t(w) * std::size_t(h);
  // Horizontal pass over Y normalised to [0, 1]: (x-derivative, second x-derivative, Gaussian).
  std::vector<glm::vec3> refF(n), testF(n);
  tbb::parallel_for(Rows(0, h), [&](const Rows& rows) {
    for (int y = rows.begin(); y != rows.end(); ++y)
      for (int x = 0; x < w; ++x) {
        glm::vec3 rf(0.0f), tf(0.0f);
        for (int ix = -r; ix <= r; ++ix) {
          const std::size_t j = std::size_t(y) * w + clampIndex(x + ix, w);
          const glm::vec3 wt = f.weights[ix + r];
          const float yr = ref[j].x * (1.0f / 116.0f) + 16.0f / 116.0f;
          const float yt = test[j].x * (1.0f / 116.0f) + 16.0f / 116.0f;
          rf += glm::vec3(wt.y, wt.z, wt.x) * yr;
          tf += glm::vec3(wt.y, wt.z, wt.x) * yt;
        }
        refF[std::size_t(y) * w + x] = rf;
        testF[std::size_t(y) * w + x] = tf;
      }
  });
  // Vertical pass: Gaussian over the x-derivatives, derivatives over the x-Gaussian; then the differences.
  const float norm = 1.0f / std::sqrt(2.0f);
  tbb::parallel_for(Rows(0, h), [&](const Rows& rows) {
    // Per x: (dx, ddx, dy, ddy) for reference and test.
    std::vector<glm::vec4> ra(w), ta(w);
    for (int y = rows.begin(); y != rows.end(); ++y) {
      std::fill(ra.begin(), ra.end(), glm::vec4(0.0f));
      std::fill(ta.begin(), ta.end(), glm::vec4(0.0f));
      for (int iy = -r; iy <= r; ++iy) {
        const std::size_t row = std::size_t(clampIndex(y + iy, h)) * w;
        const glm::vec3 wt = f.weights[iy + r];
        const glm::vec4 weights(wt.x, wt.x, wt.y, wt.z);
        for (int x = 0; x < w; ++x) {
          const glm::vec3 a = refF[row + x], b = testF[row + x];
          ra[x] += weights * glm::vec4(a.x, a.y, a.z, a.z);
          ta[x] += weights * glm::vec4(b.x, b.y, b.z, b.z);
        }
      }
      for (int x = 0; x < w; ++x) {
        const glm::vec4 a = ra[x], b = ta[x];
        const float edgeRef = std::sqrt(a.x * a.x + a.z * a.z), edgeTest = std::sqrt(b.x * b.x + b.z * b.z);
        const float pointRef = std::sqrt(a.y * a.y + a.w * a.w), pointTest = std::sqrt(b.y * b.y + b.w * b.w);
        const float edgeDiff = std::fabs(edgeRef - edgeTest), pointDiff = std::fabs(pointRef - pointTest);
        const float feature = std::pow(norm * std::max(edgeDiff, pointDiff), kQf);
        float& e = colour[std::size_t(y) * w + x];
        e = std::pow(e, 1.0f - feature);
      }
    }
  });
}

} // namespace

double rmse(const std::vector<float>& a, const std::vector<float>& b, const std::vector<std::uint8_t>& mask) {
  return std::sqrt(meanOver("RMSE", a, b, mask, [](double d) { return d * d; }));
}

double meanAbsDifference(const std::vector<float>& a, const std::vector<float>& b,
                         const std::vector<std::uint8_t>& mask) {
  return meanOver("mean absolute difference", a, b, mask, [](double d) { return std::fabs(d); });
}

FlipResult flip(const std::vector<glm::vec3>& reference, const std::vector<glm::vec3>& test, int width, int height,
                double pixelsPerDegree) {
  if (width < 1 || height < 1)
    throw Error(fmt::format("FLIP: image size {}x{} is empty", width, height));
  const std::size_t n = std::size_t(width) * std::size_t(height);
  if (reference.size() != n || test.size() != n)
    throw Error(fmt::format("FLIP: a {}x{} image needs {} pixels, but the reference has {} and the test {}", width,
                            height, n, reference.size(), test.size()));
  if (!(pixelsPerDegree > 0.0 && pixelsPerDegree <= 1000.0))
    throw Error(fmt::format("FLIP: pixels per degree must be in (0, 1000], not {}", pixelsPerDegree));
  const float ppd = float(pixelsPerDegree);
  for (std::size_t i = 0; i < n; ++i)
    for (const auto* img : {&reference, &test}) {
      const glm::vec3& c = (*img)[i];
      if (std::isnan(c.x) || std::isnan(c.y) || std::isnan(c.z))
        throw Error(fmt::format("FLIP: the {} image has a NaN at pixel ({}, {})", img == &reference ? "reference" : "test",
                                i % std::size_t(width), i / std::size_t(width)));
    }

  // sRGB (clamped to [0, 1]) -> linear RGB -> XYZ -> YCxCz.
  std::vector<glm::vec3> ref(n), tst(n);
  tbb::parallel_for(tbb::blocked_range<std::size_t>(0, n, 4096), [&](const tbb::blocked_range<std::size_t>& r) {
    auto toYCxCz = [](const glm::vec3& s) {
      return xyzToYCxCz(linearRgbToXyz({srgbToLinear(s.x), srgbToLinear(s.y), srgbToLinear(s.z)}));
    };
    for (std::size_t i = r.begin(); i != r.end(); ++i) {
      ref[i] = toYCxCz(reference[i]);
      tst[i] = toYCxCz(test[i]);
    }
  });

  FlipResult result;
  result.errorMap = colourDifference(ref, tst, width, height, ppd);
  applyFeatureDifference(ref, tst, width, height, ppd, result.errorMap);
  double sum = 0.0;
  for (float e : result.errorMap) sum += e;
  result.mean = sum / double(n);
  return result;
}

double maskedMean(const FlipResult& r, const std::vector<std::uint8_t>& mask) {
  if (!mask.empty() && mask.size() != r.errorMap.size())
    throw Error(fmt::format("FLIP masked mean: the mask has {} values but the error map has {}", mask.size(),
                            r.errorMap.size()));
  double sum = 0.0;
  std::size_t count = 0;
  for (std::size_t i = 0; i < r.errorMap.size(); ++i)
    if (mask.empty() || mask[i]) {
      sum += r.errorMap[i];
      ++count;
    }
  if (count == 0) throw Error("FLIP masked mean: no pixel selected (empty error map or an all-zero mask)");
  return sum / double(count);
}

} // namespace rtsdf
