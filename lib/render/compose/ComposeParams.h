// Shared by C++ and GLSL: the parameters, bindings and colours of compose.comp (ComposePass), the picture made
// on the GPU for a window: the shaded scene (composeImage's lighting, displayImage's exposure, sRGB-encoded
// bytes, as writePng rounds them), or a horizontal slice through the fine SDF or the ray mask, or the shaded scene
// tinted by the cascade level that shades each point, under a strip of text. Its CPU copy (composePixelsCpu) calls
// the same functions.
#ifndef RTSDF_RENDER_COMPOSE_COMPOSEPARAMS_H
#define RTSDF_RENDER_COMPOSE_COMPOSEPARAMS_H
#include "render/RenderParams.h"
#include "render/sdfshadow/SdfShadowParams.h"

#ifdef __cplusplus
#include <cmath>
#endif

RTSDF_SHARED_BEGIN
#ifdef __cplusplus
using std::exp;
using std::pow;
#endif

/// What the picture shows.
const uint kViewShaded = 0u; // the lit scene with its shadows
const uint kViewSlice = 1u;  // the fine SDF on a horizontal plane (blue outside, orange inside, contours)
const uint kViewMask = 2u;   // the ray mask on a horizontal plane (yellow: coarse voxels with |c| <= d)
const uint kViewLevels = 3u; // the lit scene tinted by the cascade level the march samples at each point

/// Byte order of the packed pixels (the swapchain's format).
const uint kComposeRgba = 0u;
const uint kComposeBgra = 1u;

/// compose.comp's parameters (a storage buffer: more than push constants hold).
struct ComposeParams {
  CameraParams camera; // the frame's camera (the slice plane's rays), relative to the frame origin
  ivec4 image;         // x: width, y: height, z: number of lights, w: view (kView*)
  ivec4 fineDims;      // xyz: fine voxels per axis (0: no SDF); w: rows of the text strip at the top (0: none)
  vec4 fineOriginH;    // xyz: fine voxel (0,0,0) in the frame, w: fine voxel size
  ivec4 coarseDims;    // xyz: coarse voxels per axis; w: byte order (kCompose*)
  vec4 coarseOriginH;  // xyz: coarse voxel (0,0,0) in the frame, w: coarse voxel size
  vec4 slice;          // x: the plane's height (frame y), y: band d, z: distance between contour lines
  ivec4 cascade;       // x: cascade levels in levels[] (0: one box)
  CascadeFieldLevel levels[RTSDF_MAX_CASCADE_LEVELS]; // finest first, as SdfShadowPass's table
};

const uint kComposeBindingPositions = 0u;
const uint kComposeBindingNormals = 1u;
const uint kComposeBindingVisibility = 2u; // light-major, width * height floats per light
const uint kComposeBindingLights = 3u;
const uint kComposeBindingFine = 4u;       // dense fine SDF, x fastest
const uint kComposeBindingCoarse = 5u;     // dense coarse SDF, x fastest
const uint kComposeBindingOverlay = 6u;    // the text strip: one byte per pixel (0: none), four per uint
const uint kComposeBindingParams = 7u;
const uint kComposeBindingOutput = 8u;     // one packed 8-bit pixel per uint
const uint kComposeBindingCount = 9u;

/// A soft palette: instances told apart, none too dark for shadows to show.
RTSDF_FN vec3 instanceAlbedo(int instance) {
  if (instance < 0) return vec3(0.0f);
  int k = instance % 6;
  if (k == 0) return vec3(0.80f, 0.78f, 0.74f);
  if (k == 1) return vec3(0.70f, 0.55f, 0.45f);
  if (k == 2) return vec3(0.55f, 0.65f, 0.75f);
  if (k == 3) return vec3(0.60f, 0.72f, 0.55f);
  if (k == 4) return vec3(0.78f, 0.70f, 0.50f);
  return vec3(0.68f, 0.60f, 0.72f);
}

/// Linear background and ambient light of the composed picture.
RTSDF_FN vec3 skyColor() { return vec3(0.35f, 0.42f, 0.52f); }
RTSDF_FN vec3 ambientLight() { return vec3(0.06f, 0.065f, 0.075f); }

/// What light @a l brings to a Lambertian point @a p with normal @a n where its visibility is @a visibility.
RTSDF_FN vec3 lightIrradiance(GpuLight l, vec3 p, vec3 n, float visibility) {
  vec3 dir;
  float atten = 1.0f;
  if (uint(l.position.w) == kLightDirectional) {
    dir = vec3(l.position);
  } else {
    vec3 d = vec3(l.position) - p;
    float d2 = max(dot(d, d), 1e-8f);
    dir = d / sqrt(d2);
    atten = 1.0f / d2;
  }
  return vec3(l.color) * (max(0.0f, dot(n, dir)) * atten * visibility);
}

/// displayImage's exposure curve, then the sRGB transfer function (IEC 61966-2-1).
RTSDF_FN float displayEncode(float linear) {
  float v = clamp(1.0f - exp(-max(linear, 0.0f)), 0.0f, 1.0f);
  return v <= 0.0031308f ? 12.92f * v : 1.055f * pow(v, 1.0f / 2.4f) - 0.055f;
}

/// Trilinear interpolation of the eight corners c[x + 2y + 4z] at fraction @a f.
RTSDF_FN float trilinear(float c000, float c100, float c010, float c110, float c001, float c101, float c011,
                         float c111, vec3 f) {
  float x00 = c000 + (c100 - c000) * f.x, x10 = c010 + (c110 - c010) * f.x;
  float x01 = c001 + (c101 - c001) * f.x, x11 = c011 + (c111 - c011) * f.x;
  float y0 = x00 + (x10 - x00) * f.y, y1 = x01 + (x11 - x01) * f.y;
  return y0 + (y1 - y0) * f.z;
}

/// The slice's colour (display-encoded) of signed distance @a d: blue outside, orange inside, fading with the
/// distance, darker contour lines every @a spacing, a white line on the surface (within half a @a voxel).
RTSDF_FN vec3 sliceColor(float d, float spacing, float voxel) {
  if (abs(d) < 0.5f * voxel) return vec3(0.95f);
  vec3 base = d > 0.0f ? vec3(0.30f, 0.55f, 0.90f) : vec3(0.90f, 0.55f, 0.25f);
  float phase = abs(d) / spacing;
  float line = phase - floor(phase) < 0.08f ? 0.55f : 1.0f;
  float fade = 1.0f - 0.6f * min(abs(d) / (8.0f * spacing), 1.0f);
  return base * (line * fade);
}

/// The mask view's colour: yellow in the ray mask, grey elsewhere on the plane.
RTSDF_FN vec3 maskColor(bool inMask) { return inMask ? vec3(0.95f, 0.80f, 0.20f) : vec3(0.35f, 0.36f, 0.40f); }

/// Display-encoded colour -> four bytes (alpha 255) in @a order.
RTSDF_FN uint packDisplayColor(vec3 c, uint order) {
  uint r = uint(clamp(c.x, 0.0f, 1.0f) * 255.0f + 0.5f);
  uint g = uint(clamp(c.y, 0.0f, 1.0f) * 255.0f + 0.5f);
  uint b = uint(clamp(c.z, 0.0f, 1.0f) * 255.0f + 0.5f);
  if (order == kComposeBgra) return b | (g << 8) | (r << 16) | (255u << 24);
  return r | (g << 8) | (b << 16) | (255u << 24);
}

/// Where the camera ray through pixel @a px meets the slice plane (y = params.slice.x), in front of the surface
/// the pixel sees (@a hitDistance, < 0: none): the distance along the ray, or -1.
RTSDF_FN float slicePlaneDistance(ComposeParams p, vec3 dir, float hitDistance) {
  if (abs(dir.y) < 1e-6f) return -1.0f;
  float t = (p.slice.x - p.camera.position.y) / dir.y;
  if (t <= 0.0f || (hitDistance >= 0.0f && t > hitDistance)) return -1.0f;
  return t;
}

/// The level view's tint of cascade level @a level (0: the finest): red, orange, yellow, green, cyan, blue, violet.
RTSDF_FN vec3 levelColor(int level) {
  int k = level % 7;
  if (k == 0) return vec3(0.90f, 0.25f, 0.20f);
  if (k == 1) return vec3(0.95f, 0.55f, 0.15f);
  if (k == 2) return vec3(0.95f, 0.85f, 0.20f);
  if (k == 3) return vec3(0.35f, 0.80f, 0.30f);
  if (k == 4) return vec3(0.25f, 0.80f, 0.85f);
  if (k == 5) return vec3(0.30f, 0.45f, 0.95f);
  return vec3(0.70f, 0.40f, 0.90f);
}

/// The level the SDF march samples at frame point @a pos: the finest whose box holds it beyond one of its fine voxels
/// (insideLevel, the march's rule), the outermost beyond every level.
RTSDF_FN int finestLevelAt(ComposeParams p, vec3 pos) {
  for (int i = 0; i < p.cascade.x; ++i)
    if (insideLevel(p.levels[i], pos) > 0.0f) return i;
  return p.cascade.x - 1;
}

/// The level view's colour: the shaded colour @a display half way to its level's tint.
RTSDF_FN vec3 levelTint(vec3 display, int level) { return 0.5f * display + 0.5f * levelColor(level); }

RTSDF_SHARED_END

#endif
