#version 450
#extension GL_GOOGLE_include_directive : require
// ShadowMapPass (lookup): PCF visibility of every light at every G-buffer pixel (shadowMapLookup in
// render/shadowmap/ShadowMapLookup.h, shared with the CPU copy).
#include "render/shadowmap/ShadowMapParams.h"
layout(std430, binding = kShadowLookupBindingDepth) readonly buffer Depth { float depthMaps[]; }; // all lights' maps, 6 N^2 each
uint gMapBase = 0u;
#define RTSDF_DEPTH_FETCH(i) depthMaps[gMapBase + uint(i)]
#include "render/shadowmap/ShadowMapLookup.h"
layout(push_constant) uniform Push { ShadowMapParams pushMap; }; // image size and number of lights

layout(local_size_x = 8, local_size_y = 8) in;
layout(std430, binding = kShadowLookupBindingPositions) readonly buffer Positions { vec4 positions[]; };
layout(std430, binding = kShadowLookupBindingNormals) readonly buffer Normals { vec4 normals[]; };
layout(std430, binding = kShadowLookupBindingLights) readonly buffer Lights { GpuLight lights[]; };
layout(std430, binding = kShadowLookupBindingMaps) readonly buffer Maps { ShadowMapParams maps[]; };
layout(std430, binding = kShadowLookupBindingVisibility) writeonly buffer Visibility { float visibility[]; };

void main() {
  uvec2 px = gl_GlobalInvocationID.xy;
  if (px.x >= uint(pushMap.image.x) || px.y >= uint(pushMap.image.y)) return;
  uint i = px.y * uint(pushMap.image.x) + px.x;
  uint pixels = uint(pushMap.image.x * pushMap.image.y);
  vec4 pos = positions[i];
  for (int l = 0; l < pushMap.info.w; ++l) {
    uint res = uint(maps[l].info.x);
    gMapBase = uint(l) * 6u * res * res;
    float v = pos.w >= 0.0 ? shadowMapLookup(maps[l], lights[l], pos.xyz, normals[i].xyz) : 1.0;
    visibility[uint(l) * pixels + i] = v;
  }
}
