// Shared by C++ and GLSL: the PCF lookup of shadow_lookup.comp and its CPU copy (shadowMapLookupCpu). The includer
// defines RTSDF_DEPTH_FETCH(index within a light's map) first.
#ifndef RTSDF_RENDER_SHADOWMAP_SHADOWMAPLOOKUP_H
#define RTSDF_RENDER_SHADOWMAP_SHADOWMAPLOOKUP_H
#include "render/shadowmap/ShadowMapParams.h"

#ifndef RTSDF_DEPTH_FETCH
#error "define RTSDF_DEPTH_FETCH before including ShadowMapLookup.h"
#endif

RTSDF_SHARED_BEGIN

/// Percentage-closer filtered visibility of light l (map m, depths from RTSDF_DEPTH_FETCH(index within this
/// light's map)) at surface point p with unit normal n: the fraction of the (2r+1)^2 texels around p's texel
/// whose stored depth is not nearer to the light than p.
RTSDF_FN float shadowMapLookup(ShadowMapParams m, GpuLight l, vec3 p, vec3 n) {
  int res = m.info.x;
  int r = m.image.z;
  float depth;
  float texel;
  float cosTheta;
  uint face = 0u;
  float s, t;
  if (uint(l.position.w) == kLightDirectional) {
    texel = 2.0f * m.center.w / float(res);
    cosTheta = dot(n, vec3(m.lightAxis));
    vec3 q = p + n * texel;
    vec3 rel = q - vec3(m.center);
    s = dot(rel, vec3(m.right)) / m.center.w;
    t = dot(rel, vec3(m.up)) / m.center.w;
    depth = m.lightAxis.w - dot(rel, vec3(m.lightAxis));
  } else {
    vec3 toP = p - vec3(l.position);
    float dist = length(toP);
    if (dist <= l.size.x || dist == 0.0f) return 1.0f;
    texel = 2.0f * dist / float(res);
    cosTheta = dot(n, -toP / dist);
    vec3 q = p + n * texel;
    vec3 dq = q - vec3(l.position);
    depth = length(dq);
    face = cubeFace(dq, s, t);
  }
  if (abs(s) > 1.0f || abs(t) > 1.0f) return 1.0f; // outside the map: nothing there casts a shadow
  int cx = clamp(int(floor((s * 0.5f + 0.5f) * float(res))), 0, res - 1);
  int cy = clamp(int(floor((t * 0.5f + 0.5f) * float(res))), 0, res - 1);
  // Slope-scaled: a surface at a grazing angle to the light changes depth fast across one texel.
  float c = clamp(abs(cosTheta), 0.05f, 1.0f);
  float bias = m.depthBias * texel * (1.0f + min(sqrt(1.0f - c * c) / c, 8.0f));
  int lit = 0, total = 0;
  for (int dy = -r; dy <= r; ++dy)
    for (int dx = -r; dx <= r; ++dx) {
      int x = clamp(cx + dx, 0, res - 1), y = clamp(cy + dy, 0, res - 1);
      float stored = RTSDF_DEPTH_FETCH(int(face) * res * res + y * res + x);
      lit += stored >= depth - bias ? 1 : 0;
      ++total;
    }
  return float(lit) / float(total);
}

RTSDF_SHARED_END

#endif
