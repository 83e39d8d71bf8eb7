#version 450
#extension GL_GOOGLE_include_directive : require
// SdfShadowPass: per pixel and light, sphere-trace the fine SDF towards the light (sdfShadowMarch, or sdfShadowUmbra
// with RTSDF_SHADOW_UMBRA, in render/sdfshadow/SdfShadowMarch.h, shared with the CPU copy). Visibility is written
// light-major; where the march found something within params.contactReach of the receiver (its contact flag),
// marked for ContactShadowPass (contactMark: kContactPending times the reach's scale added). One source, ten shaders
// (lib/Shaders.cmake's table): the field as a 3D texture, one hardware-filtered (trilinear) fetch per step
// (RTSDF_SHADOW_FIELD_TEXTURE: sdf_shadow.comp), as a dense storage buffer filtered here exactly as the CPU copy
// filters it, 8 fetches per step (RTSDF_SHADOW_FIELD_BUFFER: sdf_shadow_buffer.comp), sampled from the brick pool and
// the coarse SDF, the sparse fine state (RTSDF_SHADOW_FIELD_BRICKS: sdf_shadow_bricks.comp), or from camera-centred
// cascade levels, each a dense buffer filtered here (RTSDF_SHADOW_FIELD_CASCADE: sdf_shadow_cascade4.comp for up to
// 4 levels, sdf_shadow_cascade.comp for up to 10); each also with RTSDF_SHADOW_UMBRA (sdf_shadow_umbra*.comp:
// several marches per pixel and light).
#include "render/sdfshadow/SdfShadowParams.h"
#if defined(RTSDF_SHADOW_FIELD_TEXTURE)
layout(binding = kSdfShadowBindingField) uniform sampler3D fieldTexture;
#define RTSDF_SDF_TEXTURE(uvw) textureLod(fieldTexture, uvw, 0.0).r
#elif defined(RTSDF_SHADOW_FIELD_BUFFER)
layout(std430, binding = kSdfShadowBindingField) readonly buffer Field { float field[]; };
#define RTSDF_SDF_FETCH(i) field[i]
#elif defined(RTSDF_SHADOW_FIELD_BRICKS)
#include "sdf_shadow_bricks.glsl"
#elif defined(RTSDF_SHADOW_FIELD_CASCADE)
#include "sdf_shadow_cascade.glsl"
#else
#error "define RTSDF_SHADOW_FIELD_TEXTURE, _BUFFER, _BRICKS or _CASCADE"
#endif
#include "render/sdfshadow/SdfShadowMarch.h"

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
  vec3 lo, hi;
  marchBox(params, lo, hi);
  float jitter = pixelJitter(i, uint(params.image.z), uint(params.image.w));
  SdfShadowParams at = marchParamsAt(params, pos.xyz);
  for (int l = 0; l < params.gridDims.w; ++l) {
    float v = 1.0;
    vec3 L;
    float tMax, w;
    if (pos.w >= 0.0 && lightGeometry(lights[l], pos.xyz, lo, hi, L, tMax, w)) {
      bool contact = false;
#ifdef RTSDF_SHADOW_UMBRA
      v = sdfShadowUmbra(at, pos.xyz, n, L, tMax, w, jitter, contact);
#else
      v = sdfShadowMarch(at, params.penumbra, pos.xyz, n, L, tMax, w, jitter, contact);
#endif
      if (contact && v > 0.0) v = contactMark(v, at.gridOriginH.w / params.gridOriginH.w);
    }
    visibility[uint(l) * pixels + i] = v;
  }
}
