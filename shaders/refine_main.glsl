// The refinement shaders' body (refine_rays.comp, refine_closest.comp define RTSDF_REFINE_MODE first):
// RayRefinePass / ClosestRefinePass, for every fine voxel of the ray mask, refine the distance through the BVH.
//   rays mode (the paper): x rays uniform on the sphere, r_t = nearest hit, f_t = min(alpha f_{t-1} +
//   (1 - alpha) c^_t, r_t) with c^_t = c_t + beta + sqrt(3)/2 h_coarse (an upper bound: see below);
//   front/back-face hits, decayed by alpha, vote for the sign (more back-face hits: inside).
//   closest mode: f_t = exact distance by closest-point traversal; sign from the ray votes when x > 0,
//   else from the side of the closest triangle.
// The list holds the coarse voxels MaskCompactPass chose to refine this frame (the others keep their values);
// each is expanded into the fine voxels under it (maskFineRanges), cut into params.refineParts boxes of at most
// params.partBox.xyz fine voxels, one invocation per box (a short loop: at most 27 voxels, or a run along z of
// the fine/coarse ratio + 1). A voxel new to the mask (kMaskFineFresh) restarts from c_t, the others blend with
// their last value, which the brick pool holds (the sparse fine state), and so, with FineStorage::Dense, does
// the dense fine SDF; a voxel whose brick found no slot (a full pool) is left alone.
// Closest mode with kRefineCellSearch: one BVH walk per box collects every triangle that can be nearest to any
// voxel of it (collectCellCandidates), and each voxel tests only those, with the same triangle test and tie rule
// as closestPoint, so the distances are the same; a box whose candidates overflow walks per voxel.
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

#if RTSDF_REFINE_MODE == RTSDF_REFINE_CLOSEST
// The box's candidates (collectCellCandidates): instance slot, leaf-order triangle and distance to the box's
// centre m. Private to the invocation.
uint cellInstance[RTSDF_CELL_CANDIDATES];
uint cellLeaf[RTSDF_CELL_CANDIDATES];
float cellDistance[RTSDF_CELL_CANDIDATES];
uint cellCount = 0u;
bool cellOverflow = false;
float cellKeep = 0.0; // candidates farther than this from m cannot be nearest to a voxel of the box

// Collect every triangle that can be nearest to a fine voxel centre q of the box, whose centres lie within rho of
// m. With D the distance to the surface, D(q) <= D(m) + rho, so q's nearest triangle T has |T - m| <= D(q) + rho
// <= D(m) + 2 rho. The walk is closestPoint's from m with the search widened by 2 rho (running best >= D(m), so
// nothing needed is culled); a triangle within that reach is kept, and one beyond the final reach dropped when
// the list needs room. More than RTSDF_CELL_CANDIDATES within reach: cellOverflow, the voxels walk on their own.
void collectCellCandidates(vec3 m, float rho, float radius) {
  ClosestQuery s = closestBegin(m, radius);
  // 2 rho, rounded up: the distances at q and at m are each within a few ulps of the true ones.
  float widen = 2.0 * rho * (1.0 + 1.0e-5) + 4.0 * s.ulp4;
  cellCount = 0u;
  cellOverflow = false;
  RTSDF_TLAS_WALK_BEGIN(tn, cellOverflow || boxDistance(m, tn.lo.xyz, tn.hi.xyz) > closestReach(s) + widen, inst)
    vec3 mo = xformPoint(inst.worldToObject, m);
    RTSDF_POINT_WALK_BEGIN(inst, mo, closestReach(s) + widen, !cellOverflow, leaf)
      vec3 a, b, c;
      worldTriangle(inst, leaf, a, b, c);
      float dist = length(m - closestOnTriangle(m, a, b, c));
      if (dist < s.best) { s.best = dist; s.found = true; }
      if (dist > closestReach(s) + widen) continue;
      uint at = cellCount;
      if (at == uint(RTSDF_CELL_CANDIDATES)) {
        // Full: take the place of a candidate the walk has since moved out of reach, if there is one.
        float keep = closestReach(s) + widen;
        for (uint j = 0u; j < uint(RTSDF_CELL_CANDIDATES); ++j)
          if (cellDistance[j] > keep) at = j;
        if (at == uint(RTSDF_CELL_CANDIDATES)) { cellOverflow = true; break; }
      } else {
        ++cellCount;
      }
      cellInstance[at] = tlasSlot;
      cellLeaf[at] = leaf;
      cellDistance[at] = dist;
    RTSDF_POINT_WALK_END
  RTSDF_TLAS_WALK_END
  cellKeep = closestReach(s) + widen;
  cellOverflow = cellOverflow || !s.found;
}

// closestPoint(p, maxDist, hit) over the box's candidates: the same answer when p is a voxel centre of the box.
bool closestAmongCandidates(vec3 p, float maxDist, out BvhHit hit) {
  ClosestQuery s = closestBegin(p, maxDist);
  for (uint k = 0u; k < cellCount; ++k) {
    if (cellDistance[k] > cellKeep) continue;
    BvhInstance inst = instances[cellInstance[k]];
    vec3 a, b, c;
    worldTriangle(inst, cellLeaf[k], a, b, c);
    closestTriangle(s, a, b, c, inst.mirrored, inst.instanceId, cellLeaf[k]);
  }
  return closestEnd(s, hit);
}
#endif

// c^_t at fine voxel v: the upsampled coarse SDF plus the shell and half a coarse diagonal.
float coarseBoundAt(ivec3 v) { return upsampleCoarseAt(v) + params.beta + 0.8660254 / params.coarseOriginInvH.w; }

// The blended upper bound of the distance from c^_t (c: the upsampled coarse SDF plus the shell) and the voxel's last
// value.
float refineBound(float c, bool fresh, uint slot, uint local) {
  return fresh ? c : params.alpha * abs(loadValue(slot, local)) + (1.0 - params.alpha) * c;
}

// Closest mode's search radius: the bound plus a coarse cell diagonal (trilinear upsampling of the bound may fall
// short).
float closestRadius(float bound) { return bound + 1.7320508 / params.coarseOriginInvH.w; }

// Refine fine voxel v (fresh: new to the mask) in its brick slot at offset local.
void refineVoxel(ivec3 v, bool fresh, uint slot, uint local) {
  ivec3 fd = params.fineDims.xyz;
  uint i = uint((v.z * fd.y + v.y) * fd.x + v.x);
  vec3 p = params.fineOriginH.xyz + (vec3(v) + 0.5) * params.fineOriginH.w;

  // The coarse SDF as an upper bound of the distance: the nearest seed voxel touches the surface within half
  // its diagonal, and c_t took beta off. (With the paper's c_t itself the blend under-estimates, and rays,
  // which can only over-estimate, could never lower f.)
  float bound = refineBound(coarseBoundAt(v), fresh, slot, local);
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
    BvhHit hit;
    float radius = closestRadius(bound);
    bool near = (params.coarseDims.w & kRefineCellSearch) != 0 && !cellOverflow ? closestAmongCandidates(p, radius, hit)
                                                                                : closestPoint(p, radius, hit);
    f = near ? hit.point.w : radius;
    inside = params.rays > 0u ? vote.y > vote.x : (hit.point.w >= 0.0 && hit.frontFace == 0u);
  }
#else
  f = min(bound, nearest);
  inside = vote.y > vote.x;
#endif
  storeValue(slot, local, inside ? -f : f);
  if ((params.coarseDims.w & kRefineWriteDense) != 0) dense[i] = inside ? -f : f;
  storeVotes(slot, local, packHalf2x16(min(vote, vec2(60000.0))));
}

// Refine the fine voxels of box 'part' of coarse voxel c (parts x fastest, params.partBox.xyz voxels each).
void refineBox(uint ci, uint part, bool fresh) {
  ivec3 cd = params.coarseDims.xyz;
  ivec3 c = ivec3(int(ci % uint(cd.x)), int(ci / uint(cd.x) % uint(cd.y)), int(ci / uint(cd.x * cd.y)));
  ivec2 rx = fineRanges[c.x], ry = fineRanges[cd.x + c.y], rz = fineRanges[cd.x + cd.y + c.z];
  uint partsX = uint(params.brickDims.w), partsY = uint(params.partBox.w);
  ivec3 box = params.partBox.xyz;
  ivec3 lo = ivec3(rx.x, ry.x, rz.x) + box * ivec3(part % partsX, part / partsX % partsY, part / (partsX * partsY));
  ivec3 hi = min(lo + box - 1, ivec3(rx.y, ry.y, rz.y));
  if (any(greaterThan(lo, hi))) return;
  // One loop over the box (x fastest), not three nested: lavapipe runs a loop nest around the walk slower.
  ivec3 size = hi - lo + 1;
  int voxels = size.x * size.y * size.z;
#if RTSDF_REFINE_MODE == RTSDF_REFINE_CLOSEST
  if ((params.coarseDims.w & kRefineCellSearch) != 0) {
    float h = params.fineOriginH.w;
    vec3 first = params.fineOriginH.xyz + (vec3(lo) + 0.5) * h, last = params.fineOriginH.xyz + (vec3(hi) + 0.5) * h;
    vec3 m = 0.5 * (first + last);
    // D(m) <= c^ at the coarse voxel's centre + the way from there to m: where the walk finds nothing that near,
    // the bound did not hold and the box's voxels walk on their own.
    vec3 centre = params.coarseOriginInvH.xyz + (vec3(c) + 0.5) / params.coarseOriginInvH.w;
    float radius = coarse[ci] + params.beta + 0.8660254 / params.coarseOriginInvH.w + length(m - centre);
    collectCellCandidates(m, 0.5 * length(last - first), radius * (1.0 + 1.0e-5));
  }
#endif
  for (int j = 0; j < voxels; ++j) {
    ivec3 v = lo + ivec3(j % size.x, j / size.x % size.y, j / (size.x * size.y));
    uint slot = brickSlots[brickIndexOf(v, params.brickDims.xyz)];
    if (slot != kNoBrick) refineVoxel(v, fresh, slot, brickLocalOf(v));
  }
}

void main() {
  uint k = gl_GlobalInvocationID.x + gl_GlobalInvocationID.y * gl_NumWorkGroups.x * gl_WorkGroupSize.x;
  uint parts = params.refineParts;
  uint e = k / parts;
  if (e >= maskCounts[kMaskCountRefineList]) return;
  uint entry = refineList[e];
  refineBox(entry & kMaskFineCoords, k % parts, (entry & kMaskFineFresh) != 0u);
}
