#version 450
#extension GL_GOOGLE_include_directive : require
// ComposePass: the picture for a window, one packed 8-bit pixel per invocation (render/compose/ComposeParams.h has the
// colours): the lit scene, a slice through the fine SDF or the ray mask, or the lit scene tinted by the cascade level
// the march samples at each point, under a strip of text.
#include "render/compose/ComposeParams.h"

layout(local_size_x = 8, local_size_y = 8) in;
layout(std430, binding = kComposeBindingPositions) readonly buffer Positions { vec4 positions[]; };
layout(std430, binding = kComposeBindingNormals) readonly buffer Normals { vec4 normals[]; };
layout(std430, binding = kComposeBindingVisibility) readonly buffer Visibility { float visibility[]; };
layout(std430, binding = kComposeBindingLights) readonly buffer Lights { GpuLight lights[]; };
layout(std430, binding = kComposeBindingFine) readonly buffer Fine { float fine[]; };
layout(std430, binding = kComposeBindingCoarse) readonly buffer Coarse { float coarse[]; };
layout(std430, binding = kComposeBindingOverlay) readonly buffer Overlay { uint overlay[]; };
layout(std430, binding = kComposeBindingParams) readonly buffer Params { ComposeParams params; };
layout(std430, binding = kComposeBindingOutput) writeonly buffer Pixels { uint pixels[]; };

float fineAt(ivec3 v) {
  ivec3 d = params.fineDims.xyz;
  return fine[uint(v.x) + uint(d.x) * (uint(v.y) + uint(d.y) * uint(v.z))];
}

/// The slice's colour at frame point p, or vec3(-1) where p lies outside the fine grid.
vec3 sliceAt(vec3 p) {
  vec3 g = (p - params.fineOriginH.xyz) / params.fineOriginH.w;
  ivec3 d = params.fineDims.xyz;
  if (any(lessThan(g, vec3(0.0f))) || any(greaterThan(g, vec3(d - 1)))) return vec3(-1.0f);
  if (params.image.w == kViewMask) {
    ivec3 c = clamp(ivec3(floor((p - params.coarseOriginH.xyz) / params.coarseOriginH.w + 0.5f)), ivec3(0),
                    params.coarseDims.xyz - 1);
    ivec3 cd = params.coarseDims.xyz;
    float cv = coarse[uint(c.x) + uint(cd.x) * (uint(c.y) + uint(cd.y) * uint(c.z))];
    return maskColor(abs(cv) <= params.slice.y);
  }
  ivec3 i = min(ivec3(floor(g)), d - 2);
  vec3 f = g - vec3(i);
  float v = trilinear(fineAt(i), fineAt(i + ivec3(1, 0, 0)), fineAt(i + ivec3(0, 1, 0)), fineAt(i + ivec3(1, 1, 0)),
                      fineAt(i + ivec3(0, 0, 1)), fineAt(i + ivec3(1, 0, 1)), fineAt(i + ivec3(0, 1, 1)),
                      fineAt(i + ivec3(1, 1, 1)), f);
  return sliceColor(v, params.slice.z, params.fineOriginH.w);
}

void main() {
  ivec2 px = ivec2(gl_GlobalInvocationID.xy);
  int w = params.image.x, h = params.image.y;
  if (px.x >= w || px.y >= h) return;
  uint i = uint(px.y * w + px.x), count = uint(w * h);
  vec4 pos = positions[i], nrm = normals[i];
  vec3 c = skyColor();
  if (pos.w >= 0.0f) {
    vec3 e = ambientLight();
    for (int l = 0; l < params.image.z; ++l)
      e += lightIrradiance(lights[l], pos.xyz, nrm.xyz, visibility[uint(l) * count + i]);
    c = instanceAlbedo(int(nrm.w)) * e;
  }
  vec3 display = vec3(displayEncode(c.x), displayEncode(c.y), displayEncode(c.z));
  if (params.image.w == kViewLevels && params.cascade.x > 0 && pos.w >= 0.0f)
    display = levelTint(display, finestLevelAt(params, pos.xyz));
  if ((params.image.w == kViewSlice || params.image.w == kViewMask) && params.fineDims.x > 1) {
    vec3 dir = cameraDirection(params.camera, float(px.x) + 0.5f, float(px.y) + 0.5f);
    float t = slicePlaneDistance(params, dir, pos.w);
    if (t > 0.0f) {
      vec3 s = sliceAt(params.camera.position.xyz + t * dir);
      if (s.x >= 0.0f) display = s;
    }
  }
  if (px.y < params.fineDims.w) {
    uint coverage = (overlay[i >> 2] >> (8u * (i & 3u))) & 0xFFu;
    display = coverage != 0u ? vec3(1.0f) : display * 0.3f;
  }
  pixels[i] = packDisplayColor(display, params.coarseDims.w);
}
