#pragma once
/// @file AnalyticPenumbra.h
/// @brief Closed-form soft shadows for checking the renderers: the visible fraction of a sun disc behind an
///        opaque sphere, exact on the sphere (not a tessellation of it).
#include <glm/glm.hpp>

namespace rtsdf {

/// @brief 1 - cos(@a x), without cancellation for small x (a cap of angular radius x covers 2 pi (1 - cos x) sr).
double oneMinusCos(double x);

/// @brief Solid angle (steradians) of the intersection of two spherical caps on the unit sphere.
/// @param alpha angular radius of the first cap, radians, in [0, pi/2].
/// @param beta angular radius of the second cap, radians, in [0, pi/2].
/// @param gamma angle between the caps' centre directions, radians, in [0, pi].
/// @note Disjoint caps give 0; a cap inside the other gives the smaller cap's solid angle 2 pi (1 - cos r).
///       Otherwise the lens is two cap sectors minus the kite of the spherical triangle with sides
///       (alpha, beta, gamma) -- the closed form of Tovchigrechko & Vakser (2001) / Mazonka (2012),
///       Omega = 2 (pi - C - B cos(alpha) - A cos(beta)), evaluated in the algebraically equal but cancellation-free
///       form 2 ((1 - cos alpha) B + (1 - cos beta) A - E) with half-angle formulas for the triangle's angles
///       and L'Huilier's theorem for its excess E, so it stays accurate for caps of any size (relative error
///       about 1e-12 down to radii of 1e-6 rad).
/// @throw Error when an angle is not finite or outside its range.
double capIntersectionSolidAngle(double alpha, double beta, double gamma);

/// @brief Exact fraction of a directional light's disc (angular radius @a angularRadius around unit direction
///        @a toLight) seen from @a p past an opaque sphere (@a center, @a radius): 1 - the solid angle of the
///        intersection of the two spherical caps / the light's solid angle. angularRadius == 0: 0 or 1 (hard).
///        p inside the sphere: 0.
/// @param p the receiving point.
/// @param toLight direction towards the light (the opposite of Light::direction); normalised here.
/// @param angularRadius the sun's angular radius in radians, in [0, pi/2].
/// @param center the occluding sphere's centre.
/// @param radius the occluding sphere's radius, >= 0 (0: nothing occludes).
/// @return visibility in [0, 1]; the light is weighted uniformly over its solid angle (no cosine term), which
///         is what rayTracedVisibility estimates.
/// @note With angularRadius == 0 a ray exactly tangent to the sphere counts as visible.
/// @throw Error when an input is not finite, @a toLight is zero, or a radius is out of range.
double sunVisibilityPastSphere(const glm::dvec3& p, const glm::dvec3& toLight, double angularRadius,
                               const glm::dvec3& center, double radius);

} // namespace rtsdf
