// Shared by C++ and GLSL: the fine-SDF refinement's parameters, its random numbers (PCG hash, identical
// integer arithmetic on both sides) and the state it keeps per fine voxel.
#ifndef RTSDF_GPU_SHARED_REFINE_H
#define RTSDF_GPU_SHARED_REFINE_H
#include "gpu/shared/Bvh.h"

RTSDF_SHARED_BEGIN

/// Refinement modes: the shaders refine_rays.comp and refine_closest.comp are refine_main.glsl compiled with
/// RTSDF_REFINE_MODE set to one of these.
#define RTSDF_REFINE_RAYS 0    // the paper: x random rays per voxel per frame, nearest hit, decayed history
#define RTSDF_REFINE_CLOSEST 1 // exact closest-point distance through the same BVH, deterministic

/// Work-group shape of refine_upsample.comp (x fastest in memory; one invocation per run along z).
#define RTSDF_UPSAMPLE_GROUP_X 32
#define RTSDF_UPSAMPLE_GROUP_Y 2
/// Fine voxels along z per invocation of refine_upsample.comp.
#define RTSDF_UPSAMPLE_RUN_LENGTH 16
/// Work-group size of the refinement shaders (one invocation per masked fine voxel).
#define RTSDF_REFINE_GROUP 64

/// Bindings of refine_upsample.comp.
const uint kUpsampleBindingCoarse = 0u; // coarse SDF c_t (read)
const uint kUpsampleBindingFine = 1u;   // fine SDF (written: c_t upsampled everywhere)
const uint kUpsampleBindingCount = 2u;

/// Work-group shape of mask_compact.comp (one invocation per coarse voxel).
#define RTSDF_MASK_GROUP 4

/// Bindings of mask_compact.comp (MaskCompactPass) and mask_dispatch.comp (MaskDispatchPass, counts only).
const uint kMaskBindingCounts = 0u;     // MaskCounts words: the refinement's indirect dispatch, then the counters
const uint kMaskBindingCoarse = 1u;     // coarse SDF c_t (read)
const uint kMaskBindingFineRanges = 2u; // ivec2 per coarse index per axis (x entries, then y, then z): the fine
                                        // voxels [lo, hi] whose centres lie in that coarse slab
const uint kMaskBindingFineList = 3u;   // appended: packed fine voxels (10 bits per axis), in no order
const uint kMaskBindingCoarseList = 4u; // appended: (coarse linear index, floatBitsToUint(c)) per band voxel
const uint kMaskBindingCount = 5u;

/// Word indices of the counts buffer: a VkDispatchIndirectCommand for the refinement at offset 0, then the
/// counters mask_compact.comp appends with (reset to 0 before it runs).
const uint kMaskCountGroupsX = 0u;
const uint kMaskCountGroupsY = 1u;
const uint kMaskCountGroupsZ = 2u;
const uint kMaskCountFine = 3u;   // fine voxels appended
const uint kMaskCountCoarse = 4u; // coarse band voxels appended
const uint kMaskCountWords = 8u;

/// Push constants of mask_compact.comp and mask_dispatch.comp.
struct MaskParams {
  ivec4 coarseDims;    // xyz: coarse voxels per axis
  float band;          // d: a coarse voxel is in the band when |c| <= d (the CPU mirror's float comparison)
  uint fineCapacity;   // entries the fine list holds (appends beyond it are counted, not written)
  uint coarseCapacity; // entries the coarse list holds
  uint pad0;
};

/// The indirect dispatch of @a fineVoxels voxels in groups of RTSDF_REFINE_GROUP: at most 65535 groups along
/// x, the rest along y (the refinement flattens them); no groups at all for an empty mask.
RTSDF_FN uvec3 refineDispatch(uint fineVoxels) {
  uint groups = fineVoxels / uint(RTSDF_REFINE_GROUP) + (fineVoxels % uint(RTSDF_REFINE_GROUP) != 0u ? 1u : 0u);
  if (groups == 0u) return uvec3(0u, 0u, 1u);
  uint gx = min(groups, 65535u);
  return uvec3(gx, (groups + gx - 1u) / gx, 1u);
}

/// Bindings of refine_rays.comp and refine_closest.comp: the scene BVH (Bvh.h's kBvhBinding*), then these.
const uint kRefineBindingMask = kBvhBindingCount + 0u;      // packed fine voxels of the ray mask
const uint kRefineBindingFine = kBvhBindingCount + 1u;      // in: c_t upsampled; out: f_t signed
const uint kRefineBindingHistory = kBvhBindingCount + 2u;   // unsigned f_{t-1}
const uint kRefineBindingVotes = kBvhBindingCount + 3u;     // decayed (front, back) hits, two halves
const uint kRefineBindingLastFrame = kBvhBindingCount + 4u; // frame of the voxel's last refinement
const uint kRefineBindingMaskCounts = kBvhBindingCount + 5u; // MaskCounts words: the mask's size at kMaskCountFine
const uint kRefineBindingCount = kBvhBindingCount + 6u;

/// Push constants of refine_upsample.comp and the refinement shaders.
struct RefineParams {
  vec4 fineOriginH;      // xyz: world corner of fine voxel (0,0,0), w: fine voxel size
  ivec4 fineDims;        // xyz: fine voxels per axis, w: unused (the mask's size is read on the GPU)
  vec4 coarseOriginInvH; // xyz: world corner of coarse voxel (0,0,0), w: 1 / coarse voxel size
  ivec4 coarseDims;      // xyz: coarse voxels per axis
  float alpha;           // history decay
  uint rays;             // x, rays per masked voxel per frame
  uint frame;            // frame number (1, 2, ...): history older than frame - 1 is restarted
  uint seed;             // per-run random seed
  float beta;            // the coarse shell (closest mode widens its search by it)
  uint pad0, pad1, pad2;
};

/// The two uniform numbers in [0, 1) of ray @a ray of voxel @a voxel in frame @a frame.
RTSDF_FN uint rayHash(uint voxel, uint frame, uint ray, uint seed) {
  return pcgHash(voxel ^ pcgHash(frame * 0x9E3779B9u + pcgHash(ray + seed * 0x85EBCA6Bu)));
}

RTSDF_SHARED_END

#endif
