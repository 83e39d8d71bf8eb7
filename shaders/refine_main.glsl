// The refinement shaders' body (refine_rays.comp, refine_closest.comp define RTSDF_REFINE_MODE first):
// RayRefinePass / ClosestRefinePass, for every fine voxel of the ray mask, refine the distance through the BVH.
//   rays mode (the paper): x rays uniform on the sphere, r_t = nearest hit, f_t = min(alpha f_{t-1} +
//   (1 - alpha) c^_t, r_t) with c^_t = c_t + beta + sqrt(3)/2 h_coarse (an upper bound: see below);
//   front/back-face hits, decayed by alpha, vote for the sign (more back-face hits: inside).
//   closest mode: f_t = exact distance by closest-point traversal; sign from the ray votes when x > 0,
//   else from the side of the closest triangle.
// The list holds the voxels MaskCompactPass chose to refine this frame (the others keep their values); a voxel new
// to the mask (kMaskFineFresh) restarts from c_t, the others blend with their last value, which fine[] holds.
#include "gpu/shared/Bvh.h"
#include "gpu/shared/Refine.h"

layout(local_size_x = RTSDF_REFINE_GROUP) in;
layout(push_constant) uniform Push { RefineParams params; };
#include "bvh_bindings.glsl"
layout(std430, binding = kRefineBindingMask) readonly buffer Mask { uint mask[]; };
layout(std430, binding = kRefineBindingFine) buffer Fine { float fine[]; };
layout(std430, binding = kRefineBindingVotes) buffer Votes { uint votes[]; };
layout(std430, binding = kRefineBindingMaskCounts) readonly buffer MaskCounts { uint maskCounts[]; };
layout(std430, binding = kRefineBindingCoarse) readonly buffer Coarse { float coarse[]; };

#include "coarse_upsample.glsl"

#include "bvh_traverse.glsl"

void main() {
  uint k = gl_GlobalInvocationID.x + gl_GlobalInvocationID.y * gl_NumWorkGroups.x * gl_WorkGroupSize.x;
  if (k >= maskCounts[kMaskCountFine]) return;
  uint packed = mask[k];
  ivec3 v = ivec3(int(packed & 1023u), int((packed >> 10) & 1023u), int((packed >> 20) & 1023u));
  ivec3 fd = params.fineDims.xyz;
  uint i = uint((v.z * fd.y + v.y) * fd.x + v.x);
  vec3 p = params.fineOriginH.xyz + (vec3(v) + 0.5) * params.fineOriginH.w;

  // The coarse SDF as an upper bound of the distance: the nearest seed voxel touches the surface within half
  // its diagonal, and c_t took beta off. (With the paper's c_t itself the blend under-estimates, and rays,
  // which can only over-estimate, could never lower f.)
  float c = upsampleCoarseAt(v) + params.beta + 0.8660254 / params.coarseOriginInvH.w;
  bool fresh = (packed & kMaskFineFresh) != 0u;
  float bound = fresh ? c : params.alpha * abs(fine[i]) + (1.0 - params.alpha) * c;
  vec2 vote = fresh ? vec2(0.0) : params.alpha * unpackHalf2x16(votes[i]);

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
  fine[i] = inside ? -f : f;
  votes[i] = packHalf2x16(min(vote, vec2(60000.0)));
}
