#version 450
#extension GL_GOOGLE_include_directive : require
// ContactShadowPass: per pixel and light, a few short rays through the scene's BVH over the first voxels off the
// surface, towards points of the light's disc (lightDiscDirection); the visibility SdfShadowPass wrote is lowered
// to the fraction of them that nothing blocks. The SDF cannot hold what lies within a voxel of the receiver
// (contacts, creases, a gap under a wall thinner than a voxel): there the BVH answers exactly, and short rays are
// cheap (the walk culls every box the short segment misses). Only the pixels SdfShadowPass marked (kContactPending:
// lit, and its march saw something nearer than the receiver's own plane) trace rays; the pass unmarks them.
#include "bvh/GpuBvhLayout.h"
#include "render/contactshadow/ContactShadowParams.h"

layout(local_size_x = 8, local_size_y = 8) in;
layout(push_constant) uniform Push { ContactShadowParams params; };
#include "sdf/scenebvh/bvh_bindings.glsl"
layout(std430, binding = kContactShadowBindingPositions) readonly buffer Positions { vec4 positions[]; };
layout(std430, binding = kContactShadowBindingNormals) readonly buffer Normals { vec4 normals[]; };
layout(std430, binding = kContactShadowBindingLights) readonly buffer Lights { GpuLight lights[]; };
layout(std430, binding = kContactShadowBindingVisibility) buffer Visibility { float visibility[]; };

#include "sdf/scenebvh/bvh_traverse.glsl"

void main() {
  uvec2 px = gl_GlobalInvocationID.xy;
  if (px.x >= uint(params.image.x) || px.y >= uint(params.image.y)) return;
  uint i = px.y * uint(params.image.x) + px.x;
  uint pixels = uint(params.image.x * params.image.y);
  vec4 pos = positions[i];
  if (pos.w < 0.0) return;
  vec3 o = pos.xyz + normals[i].xyz * params.normalOffset;
  float turn = contactRayTurn(params, i);
  for (uint l = 0u; l < params.lights; ++l) {
    uint at = l * pixels + i;
    float marked = visibility[at];
    vec3 L;
    float tMax, w;
    if (marked < kContactPending || !lightGeometry(lights[l], pos.xyz, vec3(-3.0e38), vec3(3.0e38), L, tMax, w))
      continue;
    float scale = contactReachScale(marked); // 1 for one box; 2^i for a receiver in cascade level i
    float v = marked - kContactPending * scale;
    float reach = min(params.distance * scale, tMax);
    uint open = 0u;
    for (uint k = 0u; k < params.rays; ++k)
      open += occludedWithin(o, lightDiscDirection(L, w, k, params.rays, turn), reach) ? 0u : 1u;
    visibility[at] = min(v, float(open) / float(params.rays));
  }
}
