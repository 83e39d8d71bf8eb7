// Shared by C++ and GLSL: what every stage of the renderer sees alike: the camera, the lights and the functions
// on them that the shaders and their CPU copies both evaluate (camera rays, the light's cone, the pixel jitter).
// Each stage's own parameters live in its folder (render/<stage>/*Params.h).
#ifndef RTSDF_RENDER_RENDERPARAMS_H
#define RTSDF_RENDER_RENDERPARAMS_H
#include "gpu/shared/Common.h"

RTSDF_SHARED_BEGIN

/// A pinhole camera, precomputed on the host: the ray through pixel (px, py) (pixel centres at +0.5, row 0
/// at the top of the image) has direction normalize(forward + sx * right + sy * up) with sx, sy in [-1, 1].
struct CameraParams {
  vec4 position; // xyz: eye
  vec4 forward;  // xyz: unit view direction
  vec4 right;    // xyz: unit right * tan(fov / 2) * aspect
  vec4 up;       // xyz: unit up * tan(fov / 2)
  ivec4 size;    // xy: image width, height in pixels
};

/// Light types.
const uint kLightDirectional = 0u;
const uint kLightSphere = 1u;

/// One light as the GPU sees it.
struct GpuLight {
  vec4 position; // xyz: unit direction towards the light (directional) or the sphere's centre; w: type
  vec4 color;    // rgb: colour * intensity
  vec4 size;     // x: tan(angular radius) (directional) or radius (sphere)
};

/// The ray direction through pixel coordinates (px, py) (not rounded: + 0.5 is the pixel centre).
RTSDF_FN vec3 cameraDirection(CameraParams c, float px, float py) {
  float sx = 2.0f * px / float(c.size.x) - 1.0f;
  float sy = 1.0f - 2.0f * py / float(c.size.y);
  return normalize(vec3(c.forward) + sx * vec3(c.right) + sy * vec3(c.up));
}

/// Distance along o + t d (d unit) at which the ray leaves the box [lo, hi] (0 when it starts outside and
/// never enters: nothing to march through).
RTSDF_FN float exitDistance(vec3 o, vec3 d, vec3 lo, vec3 hi) {
  float tExit = 3.0e38f;
  float tEnter = 0.0f;
  for (int a = 0; a < 3; ++a) {
    if (d[a] != 0.0f) {
      RTSDF_PRECISE float t0 = (lo[a] - o[a]) / d[a];
      RTSDF_PRECISE float t1 = (hi[a] - o[a]) / d[a];
      tEnter = max(tEnter, min(t0, t1));
      tExit = min(tExit, max(t0, t1));
    } else if (o[a] < lo[a] || o[a] > hi[a]) {
      return 0.0f;
    }
  }
  return tExit > tEnter ? tExit : 0.0f;
}

/// Two unit vectors u, v with (u, v, L) orthonormal: the plane across the light's cone around unit L.
RTSDF_FN void perpendicularBasis(vec3 L, RTSDF_OUT(vec3) u, RTSDF_OUT(vec3) v) {
  u = normalize(cross(L, abs(L.x) < 0.9f ? vec3(1.0f, 0.0f, 0.0f) : vec3(0.0f, 1.0f, 0.0f)));
  v = cross(L, u);
}

/// Direction towards light l from point p, the distance to march (tMax) and the tangent of its half-angle.
/// Returns false when p is inside a sphere light (fully lit).
RTSDF_FN bool lightGeometry(GpuLight l, vec3 p, vec3 gridLo, vec3 gridHi, RTSDF_OUT(vec3) L, RTSDF_OUT(float) tMax,
                            RTSDF_OUT(float) w) {
  if (uint(l.position.w) == kLightDirectional) {
    L = vec3(l.position);
    tMax = exitDistance(p, L, gridLo, gridHi);
    w = l.size.x;
    return true;
  }
  vec3 toC = vec3(l.position) - p;
  float dist = length(toC);
  float radius = l.size.x;
  L = dist > 0.0f ? toC / dist : vec3(0.0f, 1.0f, 0.0f);
  if (dist <= radius) { tMax = 0.0f; w = 0.0f; return false; }
  tMax = min(dist - radius, exitDistance(p, L, gridLo, gridHi));
  w = radius / sqrt(max(dist * dist - radius * radius, 1.0e-20f));
  return true;
}

/// Direction k of @a count towards the disc of a light seen along unit L with a half-angle of tangent w: the
/// k-th of count equal-area rings at its mid radius, azimuths on a golden-ratio (sunflower) spiral turned by
/// turn01. The umbra estimate's marches and the contact rays spread over the light this way.
RTSDF_FN vec3 lightDiscDirection(vec3 L, float w, uint k, uint count, float turn01) {
  if (!(w > 0.0f)) return L;
  vec3 u, v;
  perpendicularBasis(L, u, v);
  float radius = w * sqrt((float(k) + 0.5f) / float(count));
  float phi = 6.28318531f * (float(k) * 0.618033989f + turn01);
  return normalize(L + radius * (cos(phi) * u + sin(phi) * v));
}


/// The pixel's jitter in [0, 1) for frame @a frame: the shared PCG hash's top 24 bits (exact in a float, so the
/// same on both sides).
RTSDF_FN float pixelJitter(uint pixel, uint frame, uint seed) {
  return unitFloat(pcgHash(pixel * 1664525u + frame * 22695477u + seed * 2654435769u));
}

RTSDF_SHARED_END

#endif
