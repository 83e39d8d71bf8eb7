#include "render/AnalyticPenumbra.h"

#include "util/Bounds.h"
#include "util/Error.h"

#include <fmt/format.h>
#include <glm/gtc/constants.hpp>

#include <algorithm>
#include <cmath>

namespace rtsdf {

double oneMinusCos(double x) {
  const double s = std::sin(0.5 * x);
  return 2.0 * s * s;
}

double capIntersectionSolidAngle(double alpha, double beta, double gamma) {
  const double halfPi = glm::half_pi<double>(), pi = glm::pi<double>();
  if (!(alpha >= 0.0 && alpha <= halfPi) || !(beta >= 0.0 && beta <= halfPi))
    throw Error(fmt::format("cap intersection: cap radii {} and {} must be in [0, pi/2]", alpha, beta));
  if (!(gamma >= 0.0 && gamma <= pi))
    throw Error(fmt::format("cap intersection: separation {} must be in [0, pi]", gamma));

  if (gamma >= alpha + beta) return 0.0;                                          // disjoint (or touching)
  if (gamma <= std::abs(alpha - beta)) return 2.0 * pi * oneMinusCos(std::min(alpha, beta)); // one inside the other

  // Partial overlap: the caps' boundary circles cross at two points; with the two centres they form a kite of
  // two spherical triangles with sides (alpha, beta, gamma). The lens is the sector of cap alpha of angle 2B
  // plus the sector of cap beta of angle 2A minus the kite (twice the triangle's spherical excess E), where B is
  // the triangle's angle at the centre of cap alpha and A at the centre of cap beta.
  const double s = 0.5 * (alpha + beta + gamma); // < pi here since gamma < alpha + beta <= pi
  const double ss = std::max(0.0, std::sin(s));
  const double sa = std::max(0.0, std::sin(s - alpha));
  const double sb = std::max(0.0, std::sin(s - beta));
  const double sg = std::max(0.0, std::sin(s - gamma));
  const double angleB = 2.0 * std::atan2(std::sqrt(sa * sg), std::sqrt(ss * sb)); // opposite side beta
  const double angleA = 2.0 * std::atan2(std::sqrt(sb * sg), std::sqrt(ss * sa)); // opposite side alpha
  // L'Huilier: tan(E/4) = sqrt(tan(s/2) tan((s-a)/2) tan((s-b)/2) tan((s-c)/2)).
  const double t = std::tan(0.5 * s) * std::tan(0.5 * (s - alpha)) * std::tan(0.5 * (s - beta)) *
                   std::tan(0.5 * (s - gamma));
  const double excess = 4.0 * std::atan(std::sqrt(std::max(0.0, t)));
  const double omega = 2.0 * (oneMinusCos(alpha) * angleB + oneMinusCos(beta) * angleA - excess);
  return std::clamp(omega, 0.0, 2.0 * pi * oneMinusCos(std::min(alpha, beta)));
}

double sunVisibilityPastSphere(const glm::dvec3& p, const glm::dvec3& toLight, double angularRadius,
                               const glm::dvec3& center, double radius) {
  if (!isFinite(p) || !isFinite(toLight) || !isFinite(center) || !std::isfinite(radius) ||
      !std::isfinite(angularRadius))
    throw Error("sun visibility past a sphere: inputs must be finite");
  if (!(glm::length(toLight) > 0.0)) throw Error("sun visibility past a sphere: the light direction is zero");
  if (!(angularRadius >= 0.0 && angularRadius <= glm::half_pi<double>()))
    throw Error(fmt::format("sun visibility past a sphere: angular radius {} must be in [0, pi/2]", angularRadius));
  if (radius < 0.0) throw Error(fmt::format("sun visibility past a sphere: radius {} is negative", radius));
  if (radius == 0.0) return 1.0;

  const glm::dvec3 toCenter = center - p;
  const double d = glm::length(toCenter);
  if (d <= radius) return 0.0;
  const glm::dvec3 l = glm::normalize(toLight);
  // The angle between the two directions, accurate at 0 and pi alike.
  const double gamma = std::atan2(glm::length(glm::cross(toCenter, l)), glm::dot(toCenter, l));
  const double beta = std::asin(std::min(1.0, radius / d));
  if (angularRadius == 0.0) return gamma >= beta ? 1.0 : 0.0;

  const double lightSolidAngle = 2.0 * glm::pi<double>() * oneMinusCos(angularRadius);
  const double blocked = capIntersectionSolidAngle(angularRadius, beta, gamma);
  return std::clamp(1.0 - blocked / lightSolidAngle, 0.0, 1.0);
}

} // namespace rtsdf
