// SdfShadowPass's body, shared by its two variants (sdf_shadow.comp: the fine SDF as a 3D texture;
// sdf_shadow_buffer.comp: as a dense buffer). Per pixel and light, sphere-trace the fine SDF towards the light
// (sdfShadowMarch, or sdfShadowUmbra in the umbra variants, in gpu/shared/Render.h, shared with the CPU
// reference). Visibility is written light-major; where the march found something within params.contactReach of
// the receiver (its contact flag), marked by kContactPending for ContactShadowPass.
#include "gpu/shared/Render.h"

layout(local_size_x = 8, local_size_y = 8) in;
layout(push_constant) uniform Push { SdfShadowParams params; };
layout(std430, binding = kSdfShadowBindingPositions) readonly buffer Positions { vec4 positions[]; };
layout(std430, binding = kSdfShadowBindingNormals) readonly buffer Normals { vec4 normals[]; };
layout(std430, binding = kSdfShadowBindingLights) readonly buffer Lights { GpuLight lights[]; };
layout(std430, binding = kSdfShadowBindingVisibility) writeonly buffer Visibility { float visibility[]; };

void main() {
  uvec2 px = gl_GlobalInvocationID.xy;
  if (px.x >= uint(params.image.x) || px.y >= uint(params.image.y)) return;
  uint i = px.y * uint(params.image.x) + px.x;
  uint pixels = uint(params.image.x * params.image.y);
  vec4 pos = positions[i];
  vec3 n = normals[i].xyz;
  vec3 lo = params.gridOriginH.xyz;
  vec3 hi = lo + vec3(params.gridDims.xyz) * params.gridOriginH.w;
  float jitter = pixelJitter(i, uint(params.image.z), uint(params.image.w));
  for (int l = 0; l < params.gridDims.w; ++l) {
    float v = 1.0;
    vec3 L;
    float tMax, w;
    if (pos.w >= 0.0 && lightGeometry(lights[l], pos.xyz, lo, hi, L, tMax, w)) {
      bool contact = false;
#ifdef RTSDF_SHADOW_UMBRA
      v = sdfShadowUmbra(params, pos.xyz, n, L, tMax, w, jitter, contact);
#else
      v = sdfShadowMarch(params, params.penumbra, pos.xyz, n, L, tMax, w, jitter, contact);
#endif
      if (contact && v > 0.0) v += kContactPending;
    }
    visibility[uint(l) * pixels + i] = v;
  }
}
