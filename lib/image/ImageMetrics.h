#pragma once
/// @file ImageMetrics.h
/// @brief Image error: RMSE and mean absolute difference of channels, and LDR-FLIP of RGB images.
#include <glm/vec3.hpp>

#include <cstdint>
#include <vector>

namespace rtsdf {

/// @brief Root-mean-square difference of @a a and @a b over the pixels where @a mask is non-zero
///        (all pixels when the mask is empty).
/// @throw Error when the sizes of @a a, @a b (and a non-empty @a mask) differ, or no pixel is selected.
double rmse(const std::vector<float>& a, const std::vector<float>& b, const std::vector<std::uint8_t>& mask = {});

/// @brief Mean absolute difference of @a a and @a b; same contract as rmse.
double meanAbsDifference(const std::vector<float>& a, const std::vector<float>& b,
                         const std::vector<std::uint8_t>& mask = {});

/// @brief The output of flip(): the per-pixel error map and its mean.
struct FlipResult {
  double mean = 0.0;          ///< mean of errorMap over all pixels
  std::vector<float> errorMap;///< per pixel, in [0, 1], x fastest, row 0 at the top
};

/// @brief LDR-FLIP (Andersson et al., "FLIP: A Difference Evaluator for Alternating Images", HPG 2020),
///        following NVIDIA's reference implementation (github.com/NVlabs/flip, flip_evaluator/cpp/FLIP.h):
///        YCxCz opponent space, separable CSF filters, Hunt-adjusted HyAB colour difference, edge/point feature
///        difference, combined per pixel as dEc^(1 - dEf). Borders are clamped to edge.
/// @param reference, test sRGB-encoded RGB in [0, 1] (values outside are clamped), width*height pixels,
///        x fastest, row 0 at the top.
/// @param pixelsPerDegree viewing condition (default: 0.7 m from a 0.7 m wide 3840-pixel monitor, ~67 ppd).
/// @note Not symmetric in general: @a reference and @a test are not interchangeable.
/// @throw Error on size mismatch, empty images, a NaN value, or pixelsPerDegree outside (0, 1000].
FlipResult flip(const std::vector<glm::vec3>& reference, const std::vector<glm::vec3>& test, int width, int height,
                double pixelsPerDegree = 67.0);

/// @brief Mean FLIP over the pixels where @a mask is non-zero (the error map is computed on the whole image);
///        all pixels when @a mask is empty.
/// @throw Error when the mask's size differs from the error map's, or no pixel is selected.
double maskedMean(const FlipResult& r, const std::vector<std::uint8_t>& mask);

} // namespace rtsdf
