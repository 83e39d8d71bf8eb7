#pragma once
/// @file GridSampling.h
/// @brief A level set's values and gradients at arbitrary world points, by OpenVDB's trilinear samplers: what a
///        caller holding points (a physics step, a renderer, a Python array) asks of a baked field.
#include <openvdb/openvdb.h>

#include <cstddef>

namespace rtsdf {

/// @brief Trilinear samples of @a grid (OpenVDB's BoxSampler) at world points, in parallel.
/// @param points @a count points, x y z after one another (3 * count numbers), in world units.
/// @param values receives @a count samples. At a voxel centre the sample is the voxel's value; between centres it
///        interpolates the eight around the point; where those are inactive it is the grid's background (+-band
///        of a level set), as the stored field is.
/// @note Real is float or double: the points are read and the values written in it, the interpolation runs in
///       the grid's float values. Non-finite points give NaN.
template <class Real>
void sampleWorldPoints(const openvdb::FloatGrid& grid, const Real* points, std::size_t count, Real* values);

/// @brief The world-space gradient of the same trilinear interpolant (OpenVDB's BoxStencil::gradient mapped by the
///        grid's transform) at world points, in parallel.
/// @param gradients receives 3 * @a count numbers, x y z after one another. Where the eight voxels around a point
///        are all background the gradient is 0; across a cell face the interpolant has a kink, and the gradient is
///        the one of the cell the point lies in (index coordinates rounded down).
/// @note As sampleWorldPoints: Real float or double, NaN for non-finite points.
template <class Real>
void gradientWorldPoints(const openvdb::FloatGrid& grid, const Real* points, std::size_t count, Real* gradients);

} // namespace rtsdf
