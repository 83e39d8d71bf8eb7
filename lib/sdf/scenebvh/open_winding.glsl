// Open meshes keep the exact field's winding number (sdf/scenebvh/OpenPieceParams.h): openSignRule tells how the
// exact field signs a point whose nearest surface is a given triangle of an instance (its side, or the winding number:
// windingSigns), openWindingNumber the winding number there. The winding number sums the solid angles of the
// instance's bottom level in object space, clusters far from the point by their dipoles. Include after
// bvh_traverse.glsl, with RTSDF_OPEN_FLAGS and RTSDF_WINDING_NODES defined as the bindings of GpuSceneBvh's
// openFlags() and windingNodes() buffers.
#include "sdf/scenebvh/OpenPieceParams.h"

// Per leaf-ordered triangle: kOpen* flags (0: a closed mesh's).
layout(std430, binding = RTSDF_OPEN_FLAGS) readonly buffer OpenFlags { uint openFlags[]; };
// Per bottom-level node (blasNodes' index): its triangles' dipole.
layout(std430, binding = RTSDF_WINDING_NODES) readonly buffer WindingNodes { WindingNode windingNodes[]; };

// The winding number of inst's mesh at object-space point po, clusters farther than 'ratio' radii by their dipoles.
float windingNumberAt(BvhInstance inst, vec3 po, float ratio) {
  float sum = 0.0;
  uint stack[RTSDF_BVH_STACK];
  int sp = 0;
  stack[sp++] = inst.blasRoot;
  while (sp > 0 && RTSDF_LOOP_STEP) {
    uint i = stack[--sp];
    WindingNode wn = windingNodes[i];
    if (windingFar(po, wn, ratio)) {
      sum += dipoleSolidAngle(po, wn);
      continue;
    }
    BvhNode n = blasNodes[i];
    uint cnt = nodeCount(n);
    if (cnt == 0u) {
      stack[sp++] = nodeFirst(n) + 1u;
      stack[sp++] = nodeFirst(n);
      continue;
    }
    for (uint k = 0u; k < cnt && RTSDF_LOOP_STEP; ++k) {
      uint tri = nodeFirst(n) + k;
      sum += triangleSolidAngle(po, corners[3u * tri].xyz, corners[3u * tri + 1u].xyz, corners[3u * tri + 2u].xyz);
    }
  }
  return sum * 0.07957747155; // 1 / 4 pi
}

// How the exact field signs world point p (the BVH's frame), whose nearest surface is leaf-ordered triangle 'leaf' of
// the instance in slot 'slot' (cheap: the triangle's flags and the feature nearest to p): kOpenRuleClosed (a closed
// mesh: the refinement's own rule), kOpenRuleSide (an open mesh where the nearest triangle's side holds) or
// kOpenRuleWinding (the winding number).
const uint kOpenRuleClosed = 0u, kOpenRuleSide = 1u, kOpenRuleWinding = 2u;
uint openSignRule(vec3 p, uint slot, uint leaf) {
  uint flags = openFlags[leaf];
  if (flags == 0u) return kOpenRuleClosed;
  vec3 a, b, c;
  worldTriangle(instances[slot], leaf, a, b, c);
  return windingSigns(flags, nearestFeature(p, a, b, c)) ? kOpenRuleWinding : kOpenRuleSide;
}

// The winding number of the mesh of the instance in slot 'slot' at world point p; near 1/2 a second, finer walk
// decides (kWindingRecheckBand). Still within kWindingExactBand of 1/2, the caller sends the point to the exact sum
// (WindingExactPass).
float openWindingNumber(vec3 p, uint slot) {
  BvhInstance inst = instances[slot];
  vec3 po = xformPoint(inst.worldToObject, p);
  float w = windingNumberAt(inst, po, kWindingFarRatio);
  if (abs(w - 0.5) < kWindingRecheckBand) w = windingNumberAt(inst, po, kWindingRecheckFarRatio);
  return w;
}
