#version 450
#extension GL_GOOGLE_include_directive : require
// ShadowMapPass (build): one light's depth map, one ray per texel through the BVH from the light (what
// rasterizing the scene from the light gives at texel centres). Directional lights: an orthographic map
// over the scene; sphere lights: a cube map around the centre (gl_GlobalInvocationID.z is the face).
#include "bvh/GpuBvhLayout.h"
#include "render/shadowmap/ShadowMapParams.h"

layout(local_size_x = 8, local_size_y = 8) in;
layout(push_constant) uniform Push { ShadowMapParams map; };
#include "sdf/scenebvh/bvh_bindings.glsl"
layout(std430, binding = kShadowMapBindingLights) readonly buffer Lights { GpuLight lights[]; };
layout(std430, binding = kShadowMapBindingDepth) writeonly buffer Depth { float depth[]; }; // all lights' maps, 6 N^2 each

#include "sdf/scenebvh/bvh_traverse.glsl"

void main() {
  uvec3 g = gl_GlobalInvocationID;
  uint n = uint(map.info.x);
  if (g.x >= n || g.y >= n) return;
  GpuLight l = lights[map.info.y];
  vec3 o, d;
  shadowMapRay(map, l, g.x, g.y, g.z, o, d);
  BvhHit h;
  float t = traceNearest(o, d, 0.0, 3.0e38, h) ? h.point.w : 3.0e38;
  depth[uint(map.info.y) * 6u * n * n + g.z * n * n + g.y * n + g.x] = t;
}
