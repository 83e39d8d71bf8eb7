// Shared by C++ and GLSL: the bindings and push constants of shadow_map.comp and shadow_lookup.comp
// (ShadowMapPass) and the texel rays both they and the CPU copies (shadowMapDepthsCpu) follow. The PCF lookup is
// in ShadowMapLookup.h: it fetches the depths through a macro the includer defines.
#ifndef RTSDF_RENDER_SHADOWMAP_SHADOWMAPPARAMS_H
#define RTSDF_RENDER_SHADOWMAP_SHADOWMAPPARAMS_H
#include "bvh/GpuBvhLayout.h"
#include "render/RenderParams.h"

RTSDF_SHARED_BEGIN

/// shadow_map.comp: the scene BVH, then the lights and the depth maps it writes.
const uint kShadowMapBindingLights = kBvhBindingCount + 0u;
const uint kShadowMapBindingDepth = kBvhBindingCount + 1u;
const uint kShadowMapBindingCount = kBvhBindingCount + 2u;

/// shadow_lookup.comp.
const uint kShadowLookupBindingPositions = 0u;
const uint kShadowLookupBindingNormals = 1u;
const uint kShadowLookupBindingDepth = 2u;
const uint kShadowLookupBindingLights = 3u;
const uint kShadowLookupBindingMaps = 4u;
const uint kShadowLookupBindingVisibility = 5u;
const uint kShadowLookupBindingCount = 6u;

/// Push constants of shadow_map.comp (build) and shadow_lookup.comp.
struct ShadowMapParams {
  vec4 center;      // xyz: scene centre, w: half extent covered by a directional light's map
  vec4 lightAxis;   // xyz: unit direction towards the light (directional), w: distance of the map plane
  vec4 right;       // xyz: unit, directional maps' u axis
  vec4 up;          // xyz: unit, directional maps' v axis
  ivec4 info;       // x: map resolution N, y: light index, z: light type, w: number of lights
  ivec4 image;      // x: width, y: height, z: PCF radius in texels
  float depthBias;  // in texels (scaled by the texel's world size)
  float pad0, pad1, pad2;
};

/// Cube-map face f (0..5: +x, -x, +y, -y, +z, -z) of direction d and its face coordinates in [-1, 1]:
/// axis a = f / 2 holds the sign, axes (a + 1) % 3 and (a + 2) % 3 the coordinates s and t.
RTSDF_FN uint cubeFace(vec3 d, RTSDF_OUT(float) s, RTSDF_OUT(float) t) {
  vec3 ad = abs(d);
  uint a = (ad.x >= ad.y && ad.x >= ad.z) ? 0u : (ad.y >= ad.z ? 1u : 2u);
  float m = ad[a];
  s = d[(a + 1u) % 3u] / m;
  t = d[(a + 2u) % 3u] / m;
  return 2u * a + (d[a] < 0.0f ? 1u : 0u);
}
RTSDF_FN vec3 cubeDirection(uint face, float s, float t) {
  uint a = face / 2u;
  vec3 d = vec3(0.0f);
  d[a] = (face & 1u) != 0u ? -1.0f : 1.0f;
  d[(a + 1u) % 3u] = s;
  d[(a + 2u) % 3u] = t;
  return normalize(d);
}

/// The shadow ray of texel (x, y) of face @a face of a light's map: origin and unit direction; depth along it.
RTSDF_FN void shadowMapRay(ShadowMapParams m, GpuLight l, uint x, uint y, uint face, RTSDF_OUT(vec3) o,
                           RTSDF_OUT(vec3) d) {
  float n = float(m.info.x);
  float s = (2.0f * (float(x) + 0.5f) / n - 1.0f);
  float t = (2.0f * (float(y) + 0.5f) / n - 1.0f);
  if (uint(l.position.w) == kLightDirectional) {
    o = vec3(m.center) + vec3(m.right) * (s * m.center.w) + vec3(m.up) * (t * m.center.w) +
        vec3(m.lightAxis) * m.lightAxis.w;
    d = -vec3(m.lightAxis);
  } else {
    o = vec3(l.position);
    d = cubeDirection(face, s, t);
  }
}

RTSDF_SHARED_END

#endif
