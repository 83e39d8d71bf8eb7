#version 450
#extension GL_GOOGLE_include_directive : require
// GBufferPass: primary visibility, one camera ray per pixel through the scene's BVH. Writes the hit point
// and ray distance, and the geometric normal (turned towards the camera) with the instance index.
#include "bvh/GpuBvhLayout.h"
#include "render/gbuffer/GBufferParams.h"

layout(local_size_x = 8, local_size_y = 8) in;
layout(push_constant) uniform Push { CameraParams camera; };
#include "sdf/scenebvh/bvh_bindings.glsl"
layout(std430, binding = kGBufferBindingPositions) writeonly buffer Positions { vec4 positions[]; };
layout(std430, binding = kGBufferBindingNormals) writeonly buffer Normals { vec4 normals[]; };

#include "sdf/scenebvh/bvh_traverse.glsl"

void main() {
  uvec2 px = gl_GlobalInvocationID.xy;
  if (px.x >= uint(camera.size.x) || px.y >= uint(camera.size.y)) return;
  uint i = px.y * uint(camera.size.x) + px.x;
  vec3 d = cameraDirection(camera, float(px.x) + 0.5, float(px.y) + 0.5);
  BvhHit h;
  if (!traceNearest(camera.position.xyz, d, 0.0, 3.0e38, h)) {
    positions[i] = vec4(0.0, 0.0, 0.0, -1.0);
    normals[i] = vec4(0.0, 0.0, 0.0, -1.0);
    return;
  }
  // Object-space normal of the leaf triangle, to world space by the inverse transpose (the rows of
  // worldToObject, transposed).
  vec3 a = corners[3u * h.leaf].xyz, b = corners[3u * h.leaf + 1u].xyz, c = corners[3u * h.leaf + 2u].xyz;
  vec3 no = cross(b - a, c - a);
  BvhInstance inst = instances[h.instance];
  vec3 nw = no.x * inst.worldToObject[0].xyz + no.y * inst.worldToObject[1].xyz + no.z * inst.worldToObject[2].xyz;
  nw = normalize(nw);
  if (dot(nw, d) > 0.0) nw = -nw;
  positions[i] = h.point;
  normals[i] = vec4(nw, float(h.instance));
}
