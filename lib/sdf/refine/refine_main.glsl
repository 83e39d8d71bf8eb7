#version 450
#extension GL_GOOGLE_include_directive : require
#extension GL_EXT_control_flow_attributes : require
// The refinement shaders (refine_rays.comp, refine_closest*.comp): this one source compiled with RTSDF_REFINE_MODE
// and the variant's defines (lib/Shaders.cmake's table).
// RayRefinePass / ClosestRefinePass, for every fine voxel of the ray mask, refine the distance through the BVH.
//   rays mode (the paper): x rays uniform on the sphere, r_t = nearest hit, f_t = min(alpha f_{t-1} +
//   (1 - alpha) c^_t, r_t) with c^_t = c_t + beta + sqrt(3)/2 h_coarse (an upper bound: see below);
//   front/back-face hits, decayed by alpha, vote for the sign (more back-face hits: inside).
//   closest mode: f_t = exact distance by closest-point traversal; sign from the side of the closest triangle, or
//   from the ray votes (x > 0) where that side is in doubt (kSignVoteFacing).
//   closest mode: where the nearest surface is an open mesh's, the exact field's rule signs (open_winding.glsl): the
//   winding number w >= 1/2 at a rim and anywhere on a mesh of several pieces, elsewhere the nearest triangle's side
//   (with or without sign rays: rays escaping through the openings are no guide). Where the walked winding number lies
//   within kWindingExactBand of 1/2, the voxel is listed for WindingExactPass, which sums every triangle after this
//   pass and stores the side that sum gives.
//   Both modes: where that says outside, a point inside a closed piece that overlaps another is inside
//   (piece_union.glsl: closed pieces through each other are a union, as in the exact field).
// The list holds the coarse voxels MaskCompactPass chose to refine this frame (the others keep their values);
// each is expanded into the fine voxels under it (maskFineRanges), cut into params.refineParts boxes of at most
// params.partBox.xyz fine voxels, one invocation per box (a short loop: at most 8 voxels, or a run along z of
// the fine/coarse ratio + 1). On CPU devices (kRefineSpreadGroups) the groups take the list in spreadStride's order, so
// that each of lavapipe's threads, which runs one contiguous run of the groups, gets a share of every part of it.
// A voxel new to the mask (kMaskFineFresh) restarts from c_t, the others blend with their last value, which the brick
// pool holds (the sparse fine state), and so, with FineStorage::Dense, does the dense fine SDF; a voxel whose brick
// found no slot (a full pool) is left alone.
// Closest mode's cell search (RTSDF_CELL_SEARCH): one BVH walk per box collects every triangle that can be nearest
// to any voxel of it (collectCellCandidates), and each voxel tests only those, with the same triangle test and tie
// rule as closestPoint, so the distances are the same; a voxel the candidates may not answer walks on its own.
// Closest mode: of a coarse voxel listed only for a moving instance (kMaskMovedOnly), a fine voxel that no swept box
// comes within its last distance of keeps its value (movedBoxBeyond), unwalked; a box of voxels that all keep theirs
// walks nothing. With sign rays it keeps its votes too: it casts none this frame, as a settled voxel does, and those
// it has vote right whatever moved (a ray's first hit is a back face from inside a closed surface, a front face
// from outside).
#include "bvh/GpuBvhLayout.h"
#include "sdf/refine/RefineParams.h"
#ifndef RTSDF_REFINE_MODE
#error "compile with RTSDF_REFINE_MODE defined (RTSDF_REFINE_RAYS or RTSDF_REFINE_CLOSEST)"
#endif
// The closest shaders' variants (refine_closest*.comp, ClosestRefinePass::Variant; lavapipe runs the code behind a
// branch, masked, even where no lane takes it, so what a pipeline never runs is compiled out): RTSDF_SIGN_RAYS 0 when
// the sign comes from the closest triangle's side alone (x = 0); RTSDF_CELL_SEARCH 1 for ClosestSearch::Cell
// (refineCellBox); the BVH walk's shape by device (RTSDF_POINT_WALK_WHILE_WHILE, bvh_traverse.glsl).
#ifndef RTSDF_SIGN_RAYS
#define RTSDF_SIGN_RAYS 1
#endif
#ifndef RTSDF_CELL_SEARCH
#define RTSDF_CELL_SEARCH 0
#endif

layout(local_size_x = RTSDF_REFINE_GROUP) in;
layout(push_constant) uniform Push { RefineParams params; };
#include "sdf/scenebvh/bvh_bindings.glsl"
layout(std430, binding = kRefineBindingRefineList) readonly buffer RefineList { uint refineList[]; };
layout(std430, binding = kRefineBindingMaskCounts) readonly buffer MaskCounts { uint maskCounts[]; };
layout(std430, binding = kRefineBindingCoarse) readonly buffer Coarse { float coarse[]; };
layout(std430, binding = kRefineBindingFineRanges) readonly buffer FineRanges { ivec2 fineRanges[]; };
layout(std430, binding = kRefineBindingBrickSlots) readonly buffer BrickSlots { uint brickSlots[]; };
layout(std430, binding = kRefineBindingDense) writeonly buffer Dense { float dense[]; };
layout(std430, binding = kRefineBindingStats) buffer Stats { uint refineStats[]; };
// Closest mode: the voxels whose winding number the walks left near 1/2, for WindingExactPass (RefineParams.h).
layout(std430, binding = kRefineBindingWindingDoubts) buffer WindingDoubts { uvec4 doubtHeader; uvec4 doubts[]; };
layout(std430, binding = kRefineBindingMovedBoxes) readonly buffer MovedBoxes { MovedBox movedBoxes[]; };
#define RTSDF_VALUE_PAGES kRefineBindingValuePages
#define RTSDF_VOTE_PAGES kRefineBindingVotePages
#include "sdf/mask/brick_pool.glsl"

#include "coarse_upsample.glsl"

#include "sdf/scenebvh/bvh_traverse.glsl"
#define RTSDF_PIECE_OF kRefineBindingPieceOf
#define RTSDF_UNION_PIECES kRefineBindingUnionPieces
#include "sdf/scenebvh/piece_union.glsl"
#define RTSDF_OPEN_FLAGS kRefineBindingOpenFlags
#define RTSDF_WINDING_NODES kRefineBindingWindingNodes
#include "sdf/scenebvh/open_winding.glsl"

#if RTSDF_REFINE_MODE == RTSDF_REFINE_CLOSEST && RTSDF_CELL_SEARCH
// The box's candidates (collectCellCandidates): instance slot, leaf-order triangle and distance to the box's
// centre m. Private to the invocation.
uint cellInstance[RTSDF_CELL_CANDIDATES];
uint cellLeaf[RTSDF_CELL_CANDIDATES];
float cellDistance[RTSDF_CELL_CANDIDATES];
uint cellCount = 0u;
bool cellMissed = false; // the walk found nothing within its radius: the box's voxels walk on their own
vec3 cellCentre = vec3(0.0);
float cellKeep = 0.0;    // candidates farther than this from m cannot be nearest to a voxel of the box
float cellDropped = 0.0; // the nearest distance from m of a triangle in reach that the full list dropped (or inf)

// The box's voxel centres lie within its corners m + (+-e.x, +-e.y, +-e.z) (a box is at most 2 voxels per axis, so
// every voxel is a corner). cellLimit*: upper bounds of the distance to the surface at the corners, z low then z high,
// x fastest (kCornerX, kCornerY), from the surface points the walk has met, rounded up by the margin a tie and the
// rounding of both searches need.
vec3 cellHalf = vec3(0.0);
vec4 cellLimitLo = vec4(0.0), cellLimitHi = vec4(0.0);
float cellMargin = 0.0;
float cellReach = 0.0; // the largest corner limit plus the way from m to a corner: the walk's sphere around m
vec3 cellAxisX = vec3(0.0), cellAxisY = vec3(0.0), cellAxisZ = vec3(0.0); // e's axes in the instance's object space
const vec4 kCornerX = vec4(-1.0, 1.0, -1.0, 1.0), kCornerY = vec4(-1.0, -1.0, 1.0, 1.0);

// Lower the corners' bounds by surface point m + w.
void cellMeetSurface(vec3 w) {
  vec3 e = cellHalf;
  vec4 dx = kCornerX * e.x - w.x, dy = kCornerY * e.y - w.y;
  vec4 xy = dx * dx + dy * dy;
  float zl = -e.z - w.z, zh = e.z - w.z;
  cellLimitLo = min(cellLimitLo, sqrt(xy + zl * zl) * (1.0 + 2.0e-5) + cellMargin);
  cellLimitHi = min(cellLimitHi, sqrt(xy + zh * zh) * (1.0 + 2.0e-5) + cellMargin);
  vec4 top = max(cellLimitLo, cellLimitHi);
  cellReach = max(max(top.x, top.y), max(top.z, top.w)) + length(e) * (1.0 + 1.0e-5) + cellMargin;
}

// Whether a convex set whose nearest point to m lies at distance len in direction u (proj: the corners' half extents
// along u, in the set's space; scale: its least world scale) lies beyond every corner's limit. The set lies in the
// half-space past that point, so its distance from corner m + d is at least len - d.u; where that exceeds the
// corner's bound on the surface distance (with the margin), no voxel of the box can have its nearest point or a tie
// there. Only for len >= |e|: nearer, the rounding of u could matter.
bool cellCornersBeyond(float len, vec3 proj, float scale) {
  if (scale * len < length(cellHalf)) return false;
  vec4 xy = kCornerX * proj.x + kCornerY * proj.y;
  return all(greaterThan(scale * (len - xy + proj.z), cellLimitLo)) &&
         all(greaterThan(scale * (len - xy - proj.z), cellLimitHi));
}

// A BVH node (object-space bounds lo, hi; po: m in object space) no voxel of the box needs.
bool cellNodeBeyond(vec3 po, vec3 lo, vec3 hi, float scale) {
  vec3 v = clamp(po, lo, hi) - po;
  float len = length(v);
  if (len == 0.0) return false;
  vec3 u = v / len;
  return cellCornersBeyond(len, vec3(dot(cellAxisX, u), dot(cellAxisY, u), dot(cellAxisZ, u)), scale);
}

// Collect every triangle that can be nearest to a fine voxel centre q of the box (or tie with it). Every triangle
// closest point from m met on the way bounds the distance at each corner; a node or triangle wholly past every
// corner's bound (cellCornersBeyond) is skipped. radius bounds D(m) from above: the corners start at radius + |e|
// (if the walk finds nothing within radius, the bound did not hold and cellMissed sends the voxels to walk alone). A
// full list keeps the nearest to m: the farthest of the list and the new one is dropped and cellDropped lowered to it
// (the farthest kept never exceeds cellDropped, so the walk culls there too); a voxel whose answer may lie that far
// walks on its own (closestAmongCandidates says which).
void collectCellCandidates(vec3 m, vec3 halfSize, float radius) {
  ClosestQuery s = closestBegin(m, radius);
  cellCount = 0u;
  cellDropped = 1.0 / 0.0;
  cellCentre = m;
  cellHalf = halfSize;
  cellMargin = 16.0 * s.ulp4;
  float start = (radius + length(halfSize)) * (1.0 + 2.0e-5) + cellMargin;
  cellLimitLo = vec4(start);
  cellLimitHi = vec4(start);
  cellReach = start + length(halfSize) * (1.0 + 1.0e-5) + cellMargin;
  RTSDF_TLAS_WALK_BEGIN(tn, boxDistance(m, tn.lo.xyz, tn.hi.xyz) > min(cellReach, cellDropped), inst)
    vec3 mo = xformPoint(inst.worldToObject, m);
    cellAxisX = halfSize.x * vec3(inst.worldToObject[0].x, inst.worldToObject[1].x, inst.worldToObject[2].x);
    cellAxisY = halfSize.y * vec3(inst.worldToObject[0].y, inst.worldToObject[1].y, inst.worldToObject[2].y);
    cellAxisZ = halfSize.z * vec3(inst.worldToObject[0].z, inst.worldToObject[1].z, inst.worldToObject[2].z);
    RTSDF_POINT_WALK_BEGIN(inst, mo, min(cellReach, cellDropped), cellNodeBeyond, true, leaf)
      vec3 a, b, c;
      worldTriangle(inst, leaf, a, b, c);
      vec3 w = closestOnTriangle(m, a, b, c) - m;
      float dist = length(w);
      if (dist < s.best) { s.best = dist; s.found = true; }
      if (dist > min(cellReach, cellDropped)) continue;
      cellMeetSurface(w);
      if (dist > 0.0 && cellCornersBeyond(dist, halfSize * (w / dist), 1.0)) continue;
      uint at = cellCount;
      if (at == uint(RTSDF_CELL_CANDIDATES)) {
        float farthest = -1.0;
        for (uint j = 0u; j < uint(RTSDF_CELL_CANDIDATES) && RTSDF_LOOP_STEP; ++j) // cut: cellMissed
          if (cellDistance[j] > farthest) { farthest = cellDistance[j]; at = j; }
        if (farthest <= cellReach) {
          if (dist >= farthest) { cellDropped = dist; continue; }
          cellDropped = farthest;
        }
      } else {
        ++cellCount;
      }
      cellInstance[at] = tlasSlot;
      cellLeaf[at] = leaf;
      cellDistance[at] = dist;
    RTSDF_POINT_WALK_END
  RTSDF_TLAS_WALK_END
  cellKeep = min(cellReach, cellDropped);
  cellMissed = !s.found;
}

// closestPoint(q_j, radius_j) for the box's 8 corner voxels q_j over its candidates, each triangle read once for all
// eight: the same answers, where complete[j] (nothing an answer depends on lay as far from m as a dropped triangle);
// else that voxel walks.
void closestAmongCandidates(inout ClosestQuery q[8], out bool complete[8]) {
  for (uint k = 0u; k < cellCount; ++k) {
    if (cellDistance[k] > cellKeep) continue;
    BvhInstance inst = instances[cellInstance[k]];
    uint leaf = cellLeaf[k];
    vec3 a, b, c;
    worldTriangle(inst, leaf, a, b, c);
    [[unroll]] for (int j = 0; j < 8; ++j) closestTriangle(q[j], a, b, c, inst.mirrored, inst.instanceId, leaf);
  }
  // The nearest triangle and its ties lie within closestReach of q, so within that + |q - m| of m (rounded up).
  [[unroll]] for (int j = 0; j < 8; ++j)
    complete[j] = closestReach(q[j]) + length(q[j].p - cellCentre) * (1.0 + 1.0e-5) + 4.0 * q[j].ulp4 < cellDropped;
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

// Fine voxel v's centre (world).
vec3 voxelCentre(ivec3 v) { return params.fineOriginH.xyz + (vec3(v) + 0.5) * params.fineOriginH.w; }

#define RTSDF_KEEPS_UNMOVED (RTSDF_REFINE_MODE == RTSDF_REFINE_CLOSEST)
#if RTSDF_KEEPS_UNMOVED
// Whether fine voxel v (in its brick slot at local) of a kMaskMovedOnly entry keeps its value: every box the instances
// swept lies beyond its last distance (movedKeepReach, movedBoxBeyond).
bool keptDespiteMotion(ivec3 v, uint slot, uint local) {
  vec3 q = voxelCentre(v);
  float reach = movedKeepReach(loadValue(slot, local), params.fineOriginH.w);
  uint boxes = uint(params.coarseDims.w >> kRefineMovedBoxesShift);
  for (uint b = 0u; b < boxes; ++b)
    if (!movedBoxBeyond(q, reach, movedBoxes[b])) return false;
  return true;
}
#endif

// The coarse SDF as an upper bound of the distance at fine voxel v (fresh: new to the mask; slot, local: its place in
// the brick pool), blended with its last value in rays mode: the nearest seed voxel touches the surface within half
// its diagonal, and c_t took beta off. (With the paper's c_t itself the blend under-estimates, and rays, which can
// only over-estimate, could never lower f.) Closest mode bounds its search by c^_t alone: the last value bounds the
// distance only while the surfaces near the voxel stay put, and a voxel refined again because an instance moved off
// it may now lie farther from everything than its last value plus the radius's slack (a coarse diagonal); nothing
// would lie within the radius, and the radius, a ghost of the instance's old pose, would be stored.
float voxelBound(ivec3 v, bool fresh, uint slot, uint local) {
#if RTSDF_REFINE_MODE == RTSDF_REFINE_CLOSEST
  return coarseBoundAt(v);
#else
  return refineBound(coarseBoundAt(v), fresh, slot, local);
#endif
}

// The sign votes at fine voxel v: its decayed history plus this frame's x rays (front-face hits, back-face hits), and
// the nearest hit of those rays (inf: none).
// Rays are not cut short: the nearest hit of a ray from inside a closed surface is always a back face and from
// outside always a front face, so every hit votes right. (A reach of twice the bound left deep voxels with no hit
// at all, hence no vote and the outside sign: sign flips far from the surface.) Traversal culls every box past the
// nearest hit found so far, so the longer reach costs little; the distance is min(bound, nearest) either way.
vec2 castRays(ivec3 v, bool fresh, uint slot, uint local, out float nearest) {
  ivec3 fd = params.fineDims.xyz;
  uint i = uint((v.z * fd.y + v.y) * fd.x + v.x);
  vec3 p = voxelCentre(v);
  vec2 vote = fresh ? vec2(0.0) : params.alpha * unpackHalf2x16(loadVotes(slot, local));
  float front = 0.0, back = 0.0;
  nearest = 1.0 / 0.0;
  for (uint r = 0u; r < params.rays && RTSDF_LOOP_STEP; ++r) {
    uint h = rayHash(i, params.frame, r, params.seed);
    float z = 1.0 - 2.0 * unitFloat(h);
    float phi = 6.28318530718 * unitFloat(pcgHash(h));
    float s = sqrt(max(0.0, 1.0 - z * z));
    BvhHit hit;
    if (traceNearest(p, vec3(s * cos(phi), s * sin(phi), z), 0.0, 3.0e38, hit)) {
      nearest = min(nearest, hit.point.w);
      if (hit.frontFace != 0u) front += 1.0; else back += 1.0;
    }
  }
  return vote + vec2(front, back);
}

// Write f_t (negative inside) and the votes of fine voxel v.
void storeVoxel(ivec3 v, uint slot, uint local, float f, bool inside, vec2 vote) {
  ivec3 fd = params.fineDims.xyz;
  storeValue(slot, local, inside ? -f : f);
  if (loopCut) atomicAdd(refineStats[kRefineStatCutVoxels], 1u); // the walks' budget ended: an upper bound
  if ((params.coarseDims.w & kRefineWriteDense) != 0) dense[uint((v.z * fd.y + v.y) * fd.x + v.x)] = inside ? -f : f;
#if RTSDF_SIGN_RAYS // without sign rays the closest triangle's side gives the sign: no vote is ever read
  storeVotes(slot, local, packHalf2x16(min(vote, vec2(60000.0))));
#endif
}

#if RTSDF_REFINE_MODE == RTSDF_REFINE_CLOSEST
// How fine voxel v, nearest to hit (near: a triangle was found), is signed where its nearest surface is an open mesh's
// (open_winding.glsl): kNoOpenSign on a closed mesh (the side or the votes), kOpenSideSign where the exact field takes
// the nearest triangle's side (the votes, escaping through the openings, are no guide there), else by the winding
// number (kWindingOutside, kWindingInside; with kWindingNearHalf where the exact sum must decide: windingSign).
const uint kNoOpenSign = 0u, kOpenSideSign = 1u, kWindingOutside = 2u, kWindingInside = 3u, kWindingNearHalf = 4u;
uint windingSign(float w) {
  return (w >= 0.5 ? kWindingInside : kWindingOutside) | (abs(w - 0.5) < kWindingExactBand ? kWindingNearHalf : 0u);
}
uint openSignAt(ivec3 v, bool near, BvhHit hit) {
  vec3 p = voxelCentre(v);
  uint rule = near ? openSignRule(p, hit.instance, hit.leaf) : kOpenRuleClosed;
  if (rule != kOpenRuleWinding) return rule == kOpenRuleSide ? kOpenSideSign : kNoOpenSign;
  return windingSign(openWindingNumber(p, hit.instance));
}

// List fine voxel v (brick slot, offset) for WindingExactPass, which signs it by the exact sum over the mesh of the
// instance in slot 'instance' (past the list's capacity it keeps the walked side, counted).
void listNearHalf(ivec3 v, uint slot, uint local, uint instance) {
  uint n = atomicAdd(refineStats[kRefineStatNearHalf], 1u);
  if (n >= kWindingExactCapacity) {
    atomicAdd(refineStats[kRefineStatNearHalfKept], 1u);
    return;
  }
  ivec3 fd = params.fineDims.xyz;
  doubts[n] = uvec4(uint((v.z * fd.y + v.y) * fd.x + v.x), slot, local, instance);
  atomicAdd(doubtHeader.x, 1u);
}

// Closest mode's end of fine voxel v, given the answer of its closest-point query of the given radius (facing: the
// answer's closestFacing): the distance (the radius where nothing lay within it) and the sign (as 'open' (openSignAt)
// says on an open mesh, else the closest triangle's side, or the rays' votes when x > 0 where the side is in doubt:
// kSignVoteFacing).
void finishClosest(ivec3 v, bool fresh, uint slot, uint local, float radius, bool near, BvhHit hit, float facing,
                   uint open) {
  float f = near ? hit.point.w : radius;
#if RTSDF_SIGN_RAYS
  float nearest;
  vec2 vote = castRays(v, fresh, slot, local, nearest);
  // With x = 0 after all (the host picks the _side variant then), or no vote yet, the side still gives the sign.
  bool bySide = params.rays == 0u || (near && facing >= kSignVoteFacing) || vote.x + vote.y == 0.0;
  bool inside = !bySide ? vote.y > vote.x : (hit.point.w >= 0.0 && hit.frontFace == 0u);
#else
  vec2 vote = vec2(0.0);
  bool bySide = true;
  bool inside = hit.point.w >= 0.0 && hit.frontFace == 0u;
#endif
  // An open mesh's nearest surface: the winding number signs where the exact field's rule says so (then neither the
  // side nor the votes, which escape through the openings, decide).
  bool byOpenRule = open != kNoOpenSign;
  bool nearHalf = (open & kWindingNearHalf) != 0u;
  open &= ~kWindingNearHalf;
  if (byOpenRule) inside = open == kOpenSideSign ? (hit.point.w >= 0.0 && hit.frontFace == 0u) : open == kWindingInside;
  // Closed pieces through each other are a union: a point the nearest triangle's side puts outside its piece may
  // still be inside another (hit.instance is the instance's slot: instances[] is in the scene's order). Votes that
  // say outside may be wrong about any piece (the first hit of a ray from inside a part may be another part's
  // front face), so then no piece is skipped.
  // A winding number near 1/2 may be on either side: the union is asked whatever it says, and where no other piece
  // holds the voxel, the exact sum decides after this pass.
  bool skipNearest = (bySide || byOpenRule) && near;
  if ((!inside || nearHalf) && unionHeader.x != 0u &&
      insideAnotherPiece(voxelCentre(v), skipNearest ? hit.instance : 0xFFFFFFFFu,
                         skipNearest ? pieceOf[hit.leaf] : kOpenPiece)) {
    inside = true;
    nearHalf = false;
  }
  if (nearHalf) listNearHalf(v, slot, local, hit.instance);
  storeVoxel(v, slot, local, f, inside, vote);
}
#endif

// Refine fine voxel v on its own (fresh: new to the mask) in its brick slot at offset local.
void refineVoxel(ivec3 v, bool fresh, uint slot, uint local) {
  loopCut = false; // set by this voxel's own walks
  float bound = voxelBound(v, fresh, slot, local);
#if RTSDF_REFINE_MODE == RTSDF_REFINE_CLOSEST
  float radius = closestRadius(bound);
  BvhHit hit;
  uint hidden = loopHide(2u); // the distance's walk leaves half of the voxel's share to its sign's
  bool near = closestPoint(voxelCentre(v), radius, hit);
  float facing = closestFacing;
  loopRestore(hidden);
  finishClosest(v, fresh, slot, local, radius, near, hit, facing, openSignAt(v, near, hit));
#else
  float nearest;
  vec2 vote = castRays(v, fresh, slot, local, nearest);
  // The votes, or inside any closed piece that overlaps another (the union; no nearest piece to skip).
  bool inside = vote.y > vote.x;
  if (!inside && unionHeader.x != 0u) inside = insideAnotherPiece(voxelCentre(v), 0xFFFFFFFFu, kOpenPiece);
  storeVoxel(v, slot, local, min(bound, nearest), inside, vote);
#endif
}

// Refine the fine voxels lo..hi one by one (x fastest; movedOnly: of a kMaskMovedOnly entry). One loop over the box,
// not three nested: lavapipe runs a loop nest around the walk slower.
void refineVoxels(ivec3 lo, ivec3 hi, bool fresh, bool movedOnly) {
  ivec3 size = hi - lo + 1;
  int voxels = size.x * size.y * size.z;
  uint kept = 0u;
  for (int j = 0; j < voxels; ++j) {
    ivec3 v = lo + ivec3(j % size.x, j / size.x % size.y, j / (size.x * size.y));
    uint slot = brickSlots[brickIndexOf(v, params.brickDims.xyz)];
    bool keep = false;
#if RTSDF_KEEPS_UNMOVED
    keep = movedOnly && slot != kNoBrick && keptDespiteMotion(v, slot, brickLocalOf(v));
    kept += keep ? 1u : 0u;
#endif
    uint hidden = loopHide(uint(voxels - j)); // an equal share of the loop budget left for each voxel left
    if (slot != kNoBrick && !keep) refineVoxel(v, fresh, slot, brickLocalOf(v));
    loopRestore(hidden);
  }
  if (kept != 0u) atomicAdd(refineStats[kRefineStatMovedKept], kept);
}

#if RTSDF_REFINE_MODE == RTSDF_REFINE_CLOSEST && RTSDF_CELL_SEARCH
// Closest mode's cell search over box lo..hi (at most 2 voxels per axis) of coarse voxel c (linear index ci): one walk
// collects the candidates, then each candidate is tested against the box's 8 corner voxels at once (a voxel of a
// 1-voxel axis is two corners: both give the same answer, the first is kept). The voxels the candidates may not
// answer walk on their own, in one loop after the others: on a SIMD machine (lavapipe) a walk inside the voxel loop
// would run, masked, once per voxel even where no voxel needs it.
void refineCellBox(uint ci, ivec3 c, ivec3 lo, ivec3 hi, bool fresh, bool movedOnly) {
  // The box's voxels with a slot (a 1-voxel axis's second corner repeats the first: left out), less those a
  // kMaskMovedOnly entry keeps: none left, no walk.
  uint slots[8];
  uint valid = 0u, kept = 0u;
  [[unroll]] for (int j = 0; j < 8; ++j) {
    ivec3 corner = lo + ivec3(j & 1, (j >> 1) & 1, j >> 2), v = min(corner, hi);
    slots[j] = brickSlots[brickIndexOf(v, params.brickDims.xyz)];
    if (any(greaterThan(corner, hi)) || slots[j] == kNoBrick) continue;
#if RTSDF_KEEPS_UNMOVED
    if (movedOnly && keptDespiteMotion(v, slots[j], brickLocalOf(v))) {
      kept |= 1u << j;
      continue;
    }
#endif
    valid |= 1u << j;
  }
  if (kept != 0u) atomicAdd(refineStats[kRefineStatMovedKept], uint(bitCount(kept)));
  if (valid == 0u) return;
  vec3 first = voxelCentre(lo), last = voxelCentre(hi);
  vec3 m = 0.5 * (first + last);
  // D(m) <= c^ at the coarse voxel's centre + the way from there to m: where the walk finds nothing that near,
  // the bound did not hold and the box's voxels walk on their own.
  vec3 centre = params.coarseOriginInvH.xyz + (vec3(c) + 0.5) / params.coarseOriginInvH.w;
  float radius = coarse[ci] + params.beta + 0.8660254 / params.coarseOriginInvH.w + length(m - centre);
  // The loop budget (CPU devices): a quarter of it for the shared walk, the rest shared by the voxels; a shared walk
  // the budget ended may have missed a triangle the candidates need, so then every voxel walks on its own.
  uint hidden = loopHide(4u);
  collectCellCandidates(m, 0.5 * (last - first), radius * (1.0 + 1.0e-5));
  loopRestore(hidden);
  if (loopCut) cellMissed = true;
  ClosestQuery q[8];
  float radii[8];
  [[unroll]] for (int j = 0; j < 8; ++j) {
    ivec3 v = min(lo + ivec3(j & 1, (j >> 1) & 1, j >> 2), hi);
    radii[j] = slots[j] != kNoBrick ? closestRadius(voxelBound(v, fresh, slots[j], brickLocalOf(v))) : 0.0;
    q[j] = closestBegin(voxelCentre(v), radii[j]);
  }
  bool complete[8];
  closestAmongCandidates(q, complete);
  BvhHit hits[8];
  bool nears[8];
  float facings[8];
  [[unroll]] for (int j = 0; j < 8; ++j) {
    nears[j] = closestEnd(q[j], hits[j]);
    facings[j] = q[j].facing;
  }
  // The voxels the candidates may not answer walk on their own, then the winding number is summed for those it signs,
  // then every voxel is finished: each in a loop of its own (a walk or a sum inside the voxel loop would run, masked,
  // once per voxel even where no voxel needs it), and finishClosest inlined once.
  uint alone = 0u, cut = 0u; // cut: the voxels whose own walks the loop budget ended
  for (int j = 0; j < 8; ++j)
    if ((valid & (1u << j)) != 0u && (cellMissed || !complete[j])) alone |= 1u << j;
  while (alone != 0u) {
    int j = findLSB(alone);
    uint share = loopHide(uint(bitCount(alone)) + 1u); // and a share for the signs' walks after
    alone &= alone - 1u;
    ivec3 v = lo + ivec3(j & 1, (j >> 1) & 1, j >> 2);
    loopCut = false;
    nears[j] = closestPoint(voxelCentre(v), radii[j], hits[j]);
    facings[j] = closestFacing;
    loopRestore(share);
    if (loopCut) cut |= 1u << j;
  }
  // open meshes: signed by the side; by the winding number; of those, inside; and near 1/2 (the exact sum decides)
  uint sided = 0u, windy = 0u, windIn = 0u, windHalf = 0u;
  for (int j = 0; j < 8; ++j) {
    ivec3 v = lo + ivec3(j & 1, (j >> 1) & 1, j >> 2);
    uint rule = (valid & (1u << j)) != 0u && nears[j] ? openSignRule(voxelCentre(v), hits[j].instance, hits[j].leaf)
                                                       : kOpenRuleClosed;
    if (rule == kOpenRuleSide) sided |= 1u << j;
    if (rule == kOpenRuleWinding) windy |= 1u << j;
  }
  for (uint left = windy; left != 0u;) {
    int j = findLSB(left);
    uint share = loopHide(uint(bitCount(left)) + 1u);
    left &= left - 1u;
    loopCut = false;
    uint sign = windingSign(openWindingNumber(voxelCentre(lo + ivec3(j & 1, (j >> 1) & 1, j >> 2)), hits[j].instance));
    if ((sign & ~kWindingNearHalf) == kWindingInside) windIn |= 1u << j;
    if ((sign & kWindingNearHalf) != 0u) windHalf |= 1u << j;
    loopRestore(share);
    if (loopCut) cut |= 1u << j;
  }
  for (int j = 0; j < 8; ++j) {
    if ((valid & (1u << j)) == 0u) continue;
    ivec3 v = lo + ivec3(j & 1, (j >> 1) & 1, j >> 2);
    uint bit = 1u << j;
    uint open = (sided & bit) != 0u ? kOpenSideSign
              : (windy & bit) == 0u ? kNoOpenSign
                                    : ((windIn & bit) != 0u ? kWindingInside : kWindingOutside) |
                                          ((windHalf & bit) != 0u ? kWindingNearHalf : 0u);
    uint share = loopHide(uint(bitCount(valid >> j))); // this voxel and those after it
    loopCut = (cut & bit) != 0u;
    finishClosest(v, fresh, slots[j], brickLocalOf(v), radii[j], nears[j], hits[j], facings[j], open);
    loopRestore(share);
  }
}
#endif

// A band voxel out of the view's reach (kMaskOutOfView): fine voxels lo..hi take the coarse SDF upsampled, in their
// brick where it has a slot (a brick the reach's edge cuts) and in the dense fine SDF, no votes: what the samplers
// and UpsamplePass give where no brick holds them.
void keepCoarse(ivec3 lo, ivec3 hi) {
  ivec3 size = hi - lo + 1, fd = params.fineDims.xyz;
  int voxels = size.x * size.y * size.z;
  for (int j = 0; j < voxels; ++j) {
    ivec3 v = lo + ivec3(j % size.x, j / size.x % size.y, j / (size.x * size.y));
    float f = upsampleCoarseAt(v);
    uint slot = brickSlots[brickIndexOf(v, params.brickDims.xyz)];
    if (slot != kNoBrick) {
      storeValue(slot, brickLocalOf(v), f);
#if RTSDF_SIGN_RAYS
      storeVotes(slot, brickLocalOf(v), 0u);
#endif
    }
    if ((params.coarseDims.w & kRefineWriteDense) != 0) dense[uint((v.z * fd.y + v.y) * fd.x + v.x)] = f;
  }
}

// Refine the fine voxels of box 'part' of coarse voxel ci (parts x fastest, params.partBox.xyz voxels each); out of
// the view's reach, keep the coarse SDF there.
void refineBox(uint ci, uint part, bool fresh, bool outOfView, bool movedOnly) {
  ivec3 cd = params.coarseDims.xyz;
  ivec3 c = ivec3(int(ci % uint(cd.x)), int(ci / uint(cd.x) % uint(cd.y)), int(ci / uint(cd.x * cd.y)));
  ivec3 lo, hi;
  if (!refinePartBox(params, fineRanges[c.x], fineRanges[cd.x + c.y], fineRanges[cd.x + cd.y + c.z], part, lo, hi))
    return;
  if (outOfView) {
    keepCoarse(lo, hi);
    return;
  }
#if RTSDF_REFINE_MODE == RTSDF_REFINE_CLOSEST && RTSDF_CELL_SEARCH
  if ((params.coarseDims.w & kRefineCellSearch) != 0) {
    refineCellBox(ci, c, lo, hi, fresh, movedOnly);
    return;
  }
#endif
  refineVoxels(lo, hi, fresh, movedOnly);
}

void main() {
  uint g = gl_WorkGroupID.x + gl_WorkGroupID.y * gl_NumWorkGroups.x;
  if ((params.coarseDims.w & kRefineSpreadGroups) != 0)
    g = g * maskCounts[kMaskCountSpreadStride] % (gl_NumWorkGroups.x * gl_NumWorkGroups.y); // spreadGroup
  uint k = g * gl_WorkGroupSize.x + gl_LocalInvocationID.x;
  uint parts = params.refineParts;
  uint e = k / parts;
  if (e >= maskCounts[kMaskCountRefineList]) return;
  uint entry = refineList[e];
  refineBox(entry & kMaskCoarseIndex, k % parts, (entry & kMaskFineFresh) != 0u, (entry & kMaskOutOfView) != 0u,
            (entry & kMaskMovedOnly) != 0u);
}
