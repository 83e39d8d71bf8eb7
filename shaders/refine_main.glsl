// The refinement shaders' body (refine_rays.comp, refine_closest.comp define RTSDF_REFINE_MODE first):
// RayRefinePass / ClosestRefinePass, for every fine voxel of the ray mask, refine the distance through the BVH.
//   rays mode (the paper): x rays uniform on the sphere, r_t = nearest hit, f_t = min(alpha f_{t-1} +
//   (1 - alpha) c^_t, r_t) with c^_t = c_t + beta + sqrt(3)/2 h_coarse (an upper bound: see below);
//   front/back-face hits, decayed by alpha, vote for the sign (more back-face hits: inside).
//   closest mode: f_t = exact distance by closest-point traversal; sign from the ray votes when x > 0,
//   else from the side of the closest triangle.
// The list holds the coarse voxels MaskCompactPass chose to refine this frame (the others keep their values);
// each is expanded into the fine voxels under it (maskFineRanges): refineParts invocations per coarse voxel, one
// per (x, y) of its fine run, each walking the run along z (a short loop: at most the fine/coarse ratio + 1). A
// voxel new to the mask (kMaskFineFresh) restarts from c_t, the others blend with their last value, which the
// brick pool holds (the sparse fine state), and so, with FineStorage::Dense, does the dense fine SDF; a voxel whose
// brick found no slot (a full pool) is left alone.
#include "gpu/shared/Bvh.h"
#include "gpu/shared/Refine.h"

layout(local_size_x = RTSDF_REFINE_GROUP) in;
layout(push_constant) uniform Push { RefineParams params; };
#include "bvh_bindings.glsl"
layout(std430, binding = kRefineBindingRefineList) readonly buffer RefineList { uint refineList[]; };
layout(std430, binding = kRefineBindingMaskCounts) readonly buffer MaskCounts { uint maskCounts[]; };
layout(std430, binding = kRefineBindingCoarse) readonly buffer Coarse { float coarse[]; };
layout(std430, binding = kRefineBindingFineRanges) readonly buffer FineRanges { ivec2 fineRanges[]; };
layout(std430, binding = kRefineBindingBrickSlots) readonly buffer BrickSlots { uint brickSlots[]; };
layout(std430, binding = kRefineBindingDense) writeonly buffer Dense { float dense[]; };
#define RTSDF_VALUE_PAGES kRefineBindingValuePages
#define RTSDF_VOTE_PAGES kRefineBindingVotePages
#include "brick_pool.glsl"

#include "coarse_upsample.glsl"

#include "bvh_traverse.glsl"

// Refine fine voxel v (fresh: new to the mask) in its brick slot at offset local.
void refineVoxel(ivec3 v, bool fresh, uint slot, uint local) {
  ivec3 fd = params.fineDims.xyz;
  uint i = uint((v.z * fd.y + v.y) * fd.x + v.x);
  vec3 p = params.fineOriginH.xyz + (vec3(v) + 0.5) * params.fineOriginH.w;

  // The coarse SDF as an upper bound of the distance: the nearest seed voxel touches the surface within half
  // its diagonal, and c_t took beta off. (With the paper's c_t itself the blend under-estimates, and rays,
  // which can only over-estimate, could never lower f.)
  float c = upsampleCoarseAt(v) + params.beta + 0.8660254 / params.coarseOriginInvH.w;
  float bound = fresh ? c : params.alpha * abs(loadValue(slot, local)) + (1.0 - params.alpha) * c;
  vec2 vote = fresh ? vec2(0.0) : params.alpha * unpackHalf2x16(loadVotes(slot, local));

  // Rays are not cut short: the nearest hit of a ray from inside a closed surface is always a back face and
  // from outside always a front face, so every hit votes right. (A reach of twice the bound left deep
  // voxels with no hit at all, hence no vote and the outside sign: sign flips far from the surface.) Traversal
  // culls every box past the nearest hit found so far, so the longer reach costs little; the distance is min(bound, nearest) either way.
  float reach = 3.0e38;
  float front = 0.0, back = 0.0, nearest = 1.0 / 0.0;
  for (uint r = 0u; r < params.rays; ++r) {
    uint h = rayHash(i, params.frame, r, params.seed);
    float z = 1.0 - 2.0 * unitFloat(h);
    float phi = 6.28318530718 * unitFloat(pcgHash(h));
    float s = sqrt(max(0.0, 1.0 - z * z));
    BvhHit hit;
    if (traceNearest(p, vec3(s * cos(phi), s * sin(phi), z), 0.0, reach, hit)) {
      nearest = min(nearest, hit.point.w);
      if (hit.frontFace != 0u) front += 1.0; else back += 1.0;
    }
  }
  vote += vec2(front, back);

  float f;
  bool inside;
#if RTSDF_REFINE_MODE == RTSDF_REFINE_CLOSEST
  {
    // Search up to the bound plus a coarse cell diagonal (trilinear upsampling of the bound may fall short).
    BvhHit hit;
    float radius = bound + 1.7320508 / params.coarseOriginInvH.w;
    f = closestPoint(p, radius, hit) ? hit.point.w : radius;
    inside = params.rays > 0u ? vote.y > vote.x : (hit.point.w >= 0.0 && hit.frontFace == 0u);
  }
#else
  f = min(bound, nearest);
  inside = vote.y > vote.x;
#endif
  storeValue(slot, local, inside ? -f : f);
  if (params.coarseDims.w != 0) dense[i] = inside ? -f : f;
  storeVotes(slot, local, packHalf2x16(min(vote, vec2(60000.0))));
}

void main() {
  uint k = gl_GlobalInvocationID.x + gl_GlobalInvocationID.y * gl_NumWorkGroups.x * gl_WorkGroupSize.x;
  uint parts = params.refineParts;
  uint e = k / parts, part = k % parts;
  if (e >= maskCounts[kMaskCountRefineList]) return;
  uint entry = refineList[e];
  uint ci = entry & kMaskFineCoords;
  bool fresh = (entry & kMaskFineFresh) != 0u;
  ivec3 cd = params.coarseDims.xyz;
  ivec3 c = ivec3(int(ci % uint(cd.x)), int(ci / uint(cd.x) % uint(cd.y)), int(ci / uint(cd.x * cd.y)));
  ivec2 rx = fineRanges[c.x], ry = fineRanges[cd.x + c.y], rz = fineRanges[cd.x + cd.y + c.z];
  uint runX = uint(params.brickDims.w);
  int x = rx.x + int(part % runX), y = ry.x + int(part / runX);
  if (x > rx.y || y > ry.y) return;
  for (int z = rz.x; z <= rz.y; ++z) {
    ivec3 v = ivec3(x, y, z);
    uint slot = brickSlots[brickIndexOf(v, params.brickDims.xyz)];
    if (slot != kNoBrick) refineVoxel(v, fresh, slot, brickLocalOf(v));
  }
}
