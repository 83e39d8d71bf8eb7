// Shared by C++ and GLSL: the coarse SDF's grid parameters, push constants, seed packing and the
// conservative triangle/voxel overlap test. The CPU copies call the very same functions.
#ifndef RTSDF_SDF_COARSE_COARSEPARAMS_H
#define RTSDF_SDF_COARSE_COARSEPARAMS_H
#include "gpu/shared/Common.h"

RTSDF_SHARED_BEGIN

/// Work-group shape of jump_flood.comp (x fastest in memory: a row of invocations reads contiguous seeds).
#define RTSDF_JFA_GROUP_X 8
#define RTSDF_JFA_GROUP_Y 8
#define RTSDF_JFA_GROUP_Z 2

/// Bindings of voxelize_chunks.comp, voxelize.comp, jump_flood.comp and coarse_distance.comp.
const uint kVoxelizeBindingCorners = 0u;        // triangle corners, 3 per triangle, in their mesh's space (read)
const uint kVoxelizeBindingSeeds = 1u;          // seeds (written where a triangle touches a voxel)
const uint kVoxelizeBindingInstances = 2u;      // VoxelizeInstance per instance, by firstInstanceTriangle (read)
const uint kVoxelizeBindingDispatch = 3u;       // voxelize.comp's two indirect dispatches (kVoxelizeDispatchWords)
const uint kVoxelizeBindingPlaced = 4u;         // every instance triangle's corners in voxel space (3 x vec4 each)
const uint kVoxelizeBindingLarge = 5u;          // the triangles with more than kVoxelizeFirstChunks chunks (listed)
const uint kVoxelizeBindingCount = 6u;
const uint kJumpFloodBindingSrc = 0u;           // nearest seeds after the previous step
const uint kJumpFloodBindingDst = 1u;           // nearest seeds after this step
const uint kJumpFloodBindingCount = 2u;
const uint kExactEdtBindingSrc = 0u;            // nearest seeds of the previous axis (or the seeds)
const uint kExactEdtBindingDst = 1u;            // nearest seeds after this axis; also the line's scratch stack
const uint kExactEdtBindingLists = 2u;          // the region's lists (its columns read where fromRegion)
const uint kExactEdtBindingCount = 3u;
const uint kCoarseDistanceBindingNearest = 0u;  // nearest seed per voxel
const uint kCoarseDistanceBindingDistance = 1u; // c per voxel (read: the last build's, then written)
const uint kCoarseDistanceBindingChanged = 2u;  // ChangedBox: grown to hold every voxel whose c changed
const uint kCoarseDistanceBindingBlockMax = 3u; // uint per block: at least the largest squared seed distance in it
const uint kCoarseDistanceBindingLists = 4u;    // the region's lists (its blocks read with kCoarseDistanceRegionOnly)
const uint kCoarseDistanceBindingChangedBlocks = 5u; // uint per block: changedBlockReach of its changed voxels, or'd
const uint kCoarseDistanceBindingCount = 6u;
const uint kCoarseRegionBindingBlockMax = 0u;   // the last build's block bounds (read)
const uint kCoarseRegionBindingRegion = 1u;     // CoarseRegion (written: the counts and dispatches)
const uint kCoarseRegionBindingLists = 2u;      // the region's lists (coarseRegionListWords), counted and listed
const uint kCoarseRegionBindingCount = 3u;
const uint kSeedShiftBindingSource = 0u;        // the seeds before the scroll (a copy: read)
const uint kSeedShiftBindingSeeds = 1u;         // the seeds moved by the shift, packed at their new voxels (written)
const uint kSeedShiftBindingCount = 2u;

/// The box of the coarse voxels whose value a build changed (coarse_distance.comp compares each voxel's new c with
/// the last build's, bit for bit): lo.xyz and hi.xyz inclusive; empty while lo.x > hi.x (reset to kChangedBoxEmpty).
struct ChangedBox {
  uvec4 lo;
  uvec4 hi;
};
const uint kChangedBoxEmptyLo = 0xFFFFFFFFu; // the reset value of lo (hi is reset to 0)

/// A build over what changed (CoarseSdfBuilder::record with a change box): where a moving instance's seeds may have
/// changed, box S, a voxel's nearest seed can change only if S lies within its old seed distance D (a nearer new
/// seed lies in S; a removed nearest one did). CoarseDistancePass keeps, per block of RTSDF_COARSE_BLOCK^3 voxels, an
/// upper bound of D^2 in the block (kCoarseDistanceBindingBlockMax: raised as voxels change, reset by a full build),
/// and CoarseRegionPass lists the region, the blocks that S lies within that bound of, and the columns of blocks
/// (along z) holding one; ExactEdtPass's z lines then run over the listed columns and CoarseDistancePass over the
/// listed blocks alone, from indirect dispatches it writes. (The blocks' bounding box was most of a level where cars
/// far apart moved: open air's long seed distances reach a cone of blocks above each car.)
#define RTSDF_COARSE_BLOCK 4
/// Work-group size of coarse_region.comp (one invocation per block).
#define RTSDF_COARSE_REGION_GROUP 64

/// The region of a build over what changed: counts.x blocks and counts.y block columns listed (coarseRegionListWords,
/// whose counts these are, copied), counts.z the voxels of the listed blocks; and the indirect dispatches of
/// ExactEdtPass's z lines (one invocation per line of a listed column) and of CoarseDistancePass
/// (RTSDF_COARSE_REGION_BLOCKS_PER_GROUP listed blocks per group, the groups in rows of kCoarseRegionGroupsX); no
/// groups (x = 0) for an empty region. In host memory (a frame's statistics read it), written by one invocation:
/// the lists' counting atomics stay in device memory.
struct CoarseRegion {
  uvec4 counts;
  uvec4 edtGroups;
  uvec4 distanceGroups;
};
/// CoarseDistancePass over listed blocks: a work group (RTSDF_JFA_GROUP_X * Y * Z invocations) takes this many.
#define RTSDF_COARSE_REGION_BLOCKS_PER_GROUP 2
/// The groups of an indirect dispatch over listed blocks per row along x (every device allows 65535).
const uint kCoarseRegionGroupsX = 32768u;

/// Push constants of coarse_region.comp.
/// The most boxes of changed seeds one build over a change takes (a scroll's entered and left seeds and the moving
/// instances' box).
#define RTSDF_COARSE_MAX_CHANGES 3
struct CoarseRegionParams {
  ivec4 dims;     // xyz: voxels per axis; w: the phase (RTSDF_COARSE_REGION_GROW or RTSDF_COARSE_REGION_DISPATCH)
  ivec4 changeLo[RTSDF_COARSE_MAX_CHANGES]; // xyz: the boxes S, inclusive (empty where any lo > hi); they may lie
  ivec4 changeHi[RTSDF_COARSE_MAX_CHANGES]; // beyond the grid (the seeds a scroll took out of it)
};
#define RTSDF_COARSE_REGION_GROW 0     // one invocation per block: those S reaches listed
#define RTSDF_COARSE_REGION_DISPATCH 1 // one invocation: the region's indirect dispatches

/// Blocks per axis of a grid of @a dims voxels.
RTSDF_FN ivec3 coarseBlockDims(ivec3 dims) { return (dims + ivec3(RTSDF_COARSE_BLOCK - 1)) / RTSDF_COARSE_BLOCK; }
RTSDF_FN uint coarseBlockIndex(ivec3 v, ivec3 blockDims) {
  ivec3 b = v / RTSDF_COARSE_BLOCK;
  return uint((b.z * blockDims.y + b.y) * blockDims.x + b.x);
}
/// The bit of the neighbour offset @a d (each component -1, 0 or 1) in a block's changed-voxel mark.
RTSDF_FN uint changedReachBit(ivec3 d) { return 1u << uint((d.z + 1) * 9 + (d.y + 1) * 3 + (d.x + 1)); }

/// The blocks a coarse voxel at @a local in its block (0..RTSDF_COARSE_BLOCK - 1 per axis) lies within one voxel of,
/// as changedReachBit of their offsets: its own, and a neighbour's where it lies at the face, edge or corner they
/// share. CoarseDistancePass ors this into the block's mark (kCoarseDistanceBindingChangedBlocks) where the voxel's
/// value changed; the fine voxels a changed coarse voxel's upsampling reaches (their cells and the cell holding them
/// lie within one coarse voxel of it) lie in those blocks (UpsampleBlocksPass).
RTSDF_FN uint changedBlockReach(ivec3 local) {
  ivec3 lo = ivec3(local.x == 0 ? -1 : 0, local.y == 0 ? -1 : 0, local.z == 0 ? -1 : 0);
  ivec3 hi = ivec3(local.x == RTSDF_COARSE_BLOCK - 1 ? 1 : 0, local.y == RTSDF_COARSE_BLOCK - 1 ? 1 : 0,
                   local.z == RTSDF_COARSE_BLOCK - 1 ? 1 : 0);
  uint bits = 0u;
  for (int dz = lo.z; dz <= hi.z; ++dz)
    for (int dy = lo.y; dy <= hi.y; ++dy)
      for (int dx = lo.x; dx <= hi.x; ++dx) bits |= changedReachBit(ivec3(dx, dy, dz));
  return bits;
}

/// The cell at linear index @a i of a grid of @a dims cells, x fastest (a block among coarseBlockDims, a voxel in one).
RTSDF_FN ivec3 linearCell(uint i, ivec3 dims) {
  int k = int(i);
  return ivec3(k % dims.x, k / dims.x % dims.y, k / (dims.x * dims.y));
}

/// The region's lists in one buffer of words: [0, 4) the counts (as CoarseRegion::counts), [4, 4 + C) a mark per
/// block column (bx + by * blocks along x), [4 + C, 4 + 2C) the listed columns, [4 + 2C, 4 + 2C + B) the listed
/// blocks (coarseBlockIndex), where C and B are the grid's block columns and blocks; the counts and marks zeroed
/// before a region is listed (coarseRegionZeroedWords). Both lists in no particular order.
RTSDF_FN uint coarseRegionColumnCount(ivec3 dims) {
  ivec3 bd = coarseBlockDims(dims);
  return uint(bd.x * bd.y);
}
const uint kCoarseRegionCountWords = 4u;
RTSDF_FN uint coarseRegionColumnsAt(ivec3 dims) { return kCoarseRegionCountWords + coarseRegionColumnCount(dims); }
RTSDF_FN uint coarseRegionBlocksAt(ivec3 dims) {
  return kCoarseRegionCountWords + 2u * coarseRegionColumnCount(dims);
}
RTSDF_FN uint coarseRegionZeroedWords(ivec3 dims) { return coarseRegionColumnsAt(dims); }
RTSDF_FN uint coarseRegionListWords(ivec3 dims) {
  ivec3 bd = coarseBlockDims(dims);
  return coarseRegionBlocksAt(dims) + uint(bd.x * bd.y * bd.z);
}

/// Whether box @a changeLo..changeHi (S) lies within the seed distance of some voxel of the block with voxels @a lo..hi
/// whose squared seed distances are at most @a maxD2 (0xFFFFFFFF: a voxel without a seed, an empty scene): the
/// squared gap between the boxes, in whole voxels, at most maxD2. Integers only: the CPU copy decides alike.
RTSDF_FN bool coarseBlockReached(ivec3 lo, ivec3 hi, ivec3 changeLo, ivec3 changeHi, uint maxD2) {
  if (changeLo.x > changeHi.x || changeLo.y > changeHi.y || changeLo.z > changeHi.z) return false;
  if (maxD2 == 0xFFFFFFFFu) return true;
  ivec3 gap = max(max(changeLo - hi, lo - changeHi), ivec3(0));
  return uint(gap.x * gap.x + gap.y * gap.y + gap.z * gap.z) <= maxD2;
}

/// No seed (empty voxel) in a seed or nearest-seed buffer.
const uint kNoSeed = 0xFFFFFFFFu;
/// Seeds pack their voxel coordinates in 10 bits per axis: grids up to 1024 voxels per axis.
const int kMaxSeedAxis = 1024;

/// Push constants of voxelize_clear.comp, voxelize_chunks.comp and voxelize.comp.
struct VoxelizeParams {
  vec4 originInvH;     // xyz: corner of lattice cell (0,0,0) in the instances' frame, w: 1 / voxel size
  ivec4 dims;          // xyz: voxels per axis
  ivec4 clipLo;        // xyz: the box of voxels the pass writes, inclusive: the whole grid (0 .. dims - 1), or in a
  ivec4 clipHi;        //      build over a change its box (the seeds outside it are the last build's); empty: lo > hi
  uint triangleCount;  // every instance's triangles together
  uint chunkSize;      // voxels of a triangle's range handled by one invocation (keeps loops short)
  uint instanceCount;
  uint maxChunkGroups; // the most groups voxelize.comp runs along y (<= kVoxelizeMaxChunkGroups)
  uint largePass;      // voxelize.comp: 0 the triangles not listed, 1 the listed ones (kVoxelizeBindingLarge)
  uint pad0, pad1, pad2;
  ivec4 cornerCell;    // xyz: the lattice cell of the grid's voxel (0,0,0): 0 where the lattice is the grid's own; a
                       // cascade level's is the world's (CoarseSdfSettings::seedLatticeCell), so that a voxel's seed
                       // depends on its world voxel alone, wherever the grid lies
};

/// VoxelizePass in two indirect dispatches, so that one large triangle (a level's ground spans the grid: hundreds of
/// a GPU's chunks) no longer sets how many chunks every triangle's invocations are dispatched for, almost all of
/// them with nothing to do. voxelize_chunks.comp fills the dispatch buffer: the first dispatch runs the triangles
/// of at most kVoxelizeFirstChunks chunks, as many chunks of each as the most of them needs; a triangle with more
/// is listed (kVoxelizeBindingLarge), and the second dispatch runs the listed triangles only. Words of the buffer:
/// the first dispatch's group counts (x written by the host), the listed triangles' count, the second dispatch's
/// group counts, a pad.
const uint kVoxelizeFirstChunks = 8u;
const uint kVoxelizeDispatchFirst = 0u;  // x: groups of 64 triangles; y: the most chunks of one not listed; z: 1
const uint kVoxelizeLargeCount = 3u;     // the triangles listed for the second dispatch
const uint kVoxelizeDispatchLarge = 4u;  // x: groups of 64 listed; y, z: their most chunks (in layers along z)
const uint kVoxelizeDispatchWords = 8u;

/// One placed mesh for the voxelization: its transform and where its triangles lie, so the GPU transforms
/// mesh-space corners itself (the host uploads transforms, never triangles, per frame).
struct VoxelizeInstance {
  vec4 objectToFrame[3];      // rows of the 3x4 matrix into the grid's frame (the BVH's objectToWorld)
  uint firstTriangle;         // its mesh's first triangle in the corner buffer
  uint triangleCount;
  uint firstInstanceTriangle; // its first triangle among all instances' triangles (ascending by instance)
  uint pad0;
};

/// The most work groups a dispatch may count along y on any device (Vulkan's minimum of
/// maxComputeWorkGroupCount): voxelize.comp takes the chunks of larger ranges in layers along z.
const uint kVoxelizeMaxChunkGroups = 65535u;
/// The fewest groups along y a caller may ask for: 1024^3 / 4096 chunks in layers of 8 stay within 65535 along z.
const uint kVoxelizeMinChunkGroups = 8u;

/// Voxels per VoxelizePass invocation by default: on a CPU device (lavapipe) and on a GPU. An H100 spent 2.15 ms
/// of a 2.5 ms frame voxelizing the default scene with 4096: its floor's few invocations looped alone; of 64,
/// 256, 1024 and 4096, 64 was the fastest there and 4096 on lavapipe (docs/results.md).
const uint kVoxelizeChunkVoxelsCpu = 4096u;
const uint kVoxelizeChunkVoxelsGpu = 64u;

/// Push constants of seed_shift.comp: the seeds or nearest seeds of a grid that scrolled by @a shift voxels (voxel v
/// takes what v + shift held, a seed u moved to u - shift), none where the voxel entered or the seed left the grid.
struct SeedShiftParams {
  ivec4 dims;
  ivec4 shift;
};

/// Push constants of jump_flood.comp.
struct JumpFloodParams {
  ivec4 dims;
  int step;
  int pad0, pad1, pad2;
};

/// Work-group size of exact_edt.comp: invocations along the first line coordinate (x for the y and z passes, so a
/// group reads and writes contiguous voxels).
#define RTSDF_EDT_GROUP_X 64

/// Push constants of exact_edt.comp: one invocation per line of the grid along @a axis.
struct ExactEdtParams {
  ivec4 dims;
  int axis;            // 0: lines along x (indexed by y, z); 1: along y (x, z); 2: along z (x, y)
  int fromRegion;      // 1: the z lines of the CoarseRegion's listed columns (z lines only); 0: those of @a lines
  int pad0, pad1;
  ivec4 lines;         // the lines run: a in [x, z), b in [y, w)
};

/// Push constants of coarse_distance.comp.
struct CoarseDistanceParams {
  ivec4 dims;
  float voxelSize;
  float beta;          // subtracted from the distance: surfaces become thin negative shells
  float emptyDistance; // value where no seed exists at all (empty scene)
  uint flags;          // kCoarseDistanceRegionOnly | kCoarseDistanceKeepBounds
};
/// CoarseDistanceParams::flags: the voxels of the CoarseRegion's listed blocks only (from its distanceGroups); the
/// block bounds raised (a build that keeps its transform for builds over a change; others skip the work).
const uint kCoarseDistanceRegionOnly = 1u;
const uint kCoarseDistanceKeepBounds = 2u;

RTSDF_FN uint packSeed(ivec3 c) { return uint(c.x) | (uint(c.y) << 10) | (uint(c.z) << 20); }
RTSDF_FN ivec3 unpackSeed(uint s) { return ivec3(int(s & 1023u), int((s >> 10) & 1023u), int((s >> 20) & 1023u)); }
RTSDF_FN int distance2(ivec3 a, ivec3 b) {
  ivec3 d = a - b;
  return d.x * d.x + d.y * d.y + d.z * d.z;
}

/// Index-space position of a world point: voxel (i,j,k) covers [i, i+1] x [j, j+1] x [k, k+1].
RTSDF_FN vec3 toVoxelSpace(vec3 p, vec4 originInvH) {
  RTSDF_PRECISE vec3 t = (p - vec3(originInvH.x, originInvH.y, originInvH.z)) * originInvH.w;
  return t;
}

/// a*b - c*d without fused multiply-add (a 'precise' result in GLSL), so both sides round alike.
RTSDF_FN float diffOfProducts(float a, float b, float c, float d) {
  RTSDF_PRECISE float r = a * b - c * d;
  return r;
}

/// Separating-axis test of one axis: projections p0..p2 of the triangle against the box radius r.
RTSDF_FN bool separated(float p0, float p1, float p2, float r) {
  return min(p0, min(p1, p2)) > r || max(p0, max(p1, p2)) < -r;
}

/// Conservative triangle/box overlap (Akenine-Moller's separating axes): vertices relative to the box
/// centre, box half-size h. Touching counts as overlap. Only +, -, *, abs, min, max: exact IEEE operations,
/// so GPU and CPU agree bit for bit.
RTSDF_FN bool triangleOverlapsBox(vec3 v0, vec3 v1, vec3 v2, float h) {
  // The box's face normals: the triangle's bounds.
  if (separated(v0.x, v1.x, v2.x, h) || separated(v0.y, v1.y, v2.y, h) || separated(v0.z, v1.z, v2.z, h)) return false;
  RTSDF_PRECISE vec3 e0 = v1 - v0;
  RTSDF_PRECISE vec3 e1 = v2 - v1;
  RTSDF_PRECISE vec3 e2 = v0 - v2;
  // The triangle's plane.
  RTSDF_PRECISE vec3 n = vec3(diffOfProducts(e0.y, e1.z, e0.z, e1.y), diffOfProducts(e0.z, e1.x, e0.x, e1.z),
                              diffOfProducts(e0.x, e1.y, e0.y, e1.x));
  RTSDF_PRECISE float d = (n.x * v0.x + n.y * v0.y) + n.z * v0.z;
  RTSDF_PRECISE float rn = h * (abs(n.x) + abs(n.y) + abs(n.z));
  if (d > rn || d < -rn) return false;
  // The nine cross products of box axes and triangle edges.
  for (int i = 0; i < 3; ++i) {
    RTSDF_PRECISE vec3 e = i == 0 ? e0 : (i == 1 ? e1 : e2);
    // x cross e = (0, -e.z, e.y)
    RTSDF_PRECISE float rx = h * (abs(e.z) + abs(e.y));
    if (separated(diffOfProducts(e.y, v0.z, e.z, v0.y), diffOfProducts(e.y, v1.z, e.z, v1.y),
                  diffOfProducts(e.y, v2.z, e.z, v2.y), rx))
      return false;
    // y cross e = (e.z, 0, -e.x)
    RTSDF_PRECISE float ry = h * (abs(e.z) + abs(e.x));
    if (separated(diffOfProducts(e.z, v0.x, e.x, v0.z), diffOfProducts(e.z, v1.x, e.x, v1.z),
                  diffOfProducts(e.z, v2.x, e.x, v2.z), ry))
      return false;
    // z cross e = (-e.y, e.x, 0)
    RTSDF_PRECISE float rz = h * (abs(e.y) + abs(e.x));
    if (separated(diffOfProducts(e.x, v0.y, e.y, v0.x), diffOfProducts(e.x, v1.y, e.y, v1.x),
                  diffOfProducts(e.x, v2.y, e.y, v2.x), rz))
      return false;
  }
  return true;
}

/// The voxels whose boxes may touch a triangle with voxel-space corners t0..t2, clamped to the box @a clipLo..clipHi
/// (inclusive; the grid's 0 .. dims - 1 or a part of it): one voxel of margin around the bounds, the overlap test
/// decides. Empty (a component of lo above hi) where the triangle's range misses the box.
RTSDF_FN ivec3 voxelRangeLo(vec3 t0, vec3 t1, vec3 t2, ivec3 clipLo) {
  return max(ivec3(floor(min(t0, min(t1, t2)))) - ivec3(1), clipLo);
}
RTSDF_FN ivec3 voxelRangeHi(vec3 t0, vec3 t1, vec3 t2, ivec3 clipHi) {
  return min(ivec3(floor(max(t0, max(t1, t2)))) + ivec3(1), clipHi);
}

/// A mesh-space point in the instances' frame: rows r0..r2 of a 3x4 matrix, the sums in one fixed order
/// without fused multiply-add, so the GPU and the CPU copy place every corner alike.
RTSDF_FN vec3 transformToFrame(vec4 r0, vec4 r1, vec4 r2, vec3 p) {
  RTSDF_PRECISE float x = ((r0.x * p.x + r0.y * p.y) + r0.z * p.z) + r0.w;
  RTSDF_PRECISE float y = ((r1.x * p.x + r1.y * p.y) + r1.z * p.z) + r1.w;
  RTSDF_PRECISE float z = ((r2.x * p.x + r2.y * p.y) + r2.z * p.z) + r2.w;
  return vec3(x, y, z);
}

/// The chunks of @a chunkSize voxels that the range of the triangle with voxel-space corners t0..t2 needs inside the
/// box @a clipLo..clipHi.
RTSDF_FN uint voxelRangeChunks(vec3 t0, vec3 t1, vec3 t2, ivec3 clipLo, ivec3 clipHi, uint chunkSize) {
  ivec3 n = voxelRangeHi(t0, t1, t2, clipHi) - voxelRangeLo(t0, t1, t2, clipLo) + ivec3(1);
  if (n.x <= 0 || n.y <= 0 || n.z <= 0) return 0u;
  uint voxels = uint(n.x) * uint(n.y) * uint(n.z); // at most 1024^3: fits
  return (voxels + chunkSize - 1u) / chunkSize;
}

/// Whether voxel @a v overlaps the triangle with voxel-space corners t0..t2.
RTSDF_FN bool voxelOverlaps(ivec3 v, vec3 t0, vec3 t1, vec3 t2) {
  RTSDF_PRECISE vec3 c = vec3(v) + vec3(0.5);
  return triangleOverlapsBox(t0 - c, t1 - c, t2 - c, 0.5);
}

/// One jump-flooding update: keep the nearer of @a best and @a candidate (ties: the smaller packed seed).
RTSDF_FN uint nearerSeed(ivec3 p, uint best, uint candidate) {
  if (candidate == kNoSeed) return best;
  if (best == kNoSeed) return candidate;
  int db = distance2(p, unpackSeed(best));
  int dc = distance2(p, unpackSeed(candidate));
  return (dc < db || (dc == db && candidate < best)) ? candidate : best;
}

/// The line of exact_edt.comp's invocation (a, b) for @a axis: the voxel at position 0 (a, b are its coordinates
/// on the other two axes, lowest first) and the index step between consecutive voxels; n: the line's length.
RTSDF_FN ivec3 edtLineStart(int axis, int a, int b) {
  return axis == 0 ? ivec3(0, a, b) : (axis == 1 ? ivec3(a, 0, b) : ivec3(a, b, 0));
}
RTSDF_FN int edtLineStride(ivec3 dims, int axis) { return axis == 0 ? 1 : (axis == 1 ? dims.x : dims.x * dims.y); }

/// Meijster's separation of the parabolas rooted at line positions i < u with heights gi, gu (squared distances
/// to their seeds off the line): the last integer position where i is at least as near as u. Integer
/// arithmetic only (floor division), so it is exact on both sides.
RTSDF_FN int edtSeparation(int i, int gi, int u, int gu) {
  int num = u * u - i * i + gu - gi;
  int den = 2 * (u - i);
  return num >= 0 ? num / den : -((-num + den - 1) / den);
}

/// A scratch stack entry of the envelope: the parabola's line position s and the first position t it owns.
RTSDF_FN uint packEdtEntry(int s, int t) { return uint(s) | (uint(t) << 16); }
RTSDF_FN int edtEntrySeed(uint e) { return int(e & 0xFFFFu); }
RTSDF_FN int edtEntryStart(uint e) { return int(e >> 16); }

RTSDF_SHARED_END

#endif
