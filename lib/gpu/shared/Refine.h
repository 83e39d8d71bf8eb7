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

/// Bindings of refine_rays.comp and refine_closest.comp: the scene BVH (Bvh.h's kBvhBinding*), then these.
const uint kRefineBindingMask = kBvhBindingCount + 0u;      // packed fine voxels of the ray mask
const uint kRefineBindingFine = kBvhBindingCount + 1u;      // in: c_t upsampled; out: f_t signed
const uint kRefineBindingHistory = kBvhBindingCount + 2u;   // unsigned f_{t-1}
const uint kRefineBindingVotes = kBvhBindingCount + 3u;     // decayed (front, back) hits, two halves
const uint kRefineBindingLastFrame = kBvhBindingCount + 4u; // frame of the voxel's last refinement
const uint kRefineBindingCount = kBvhBindingCount + 5u;

/// Push constants of refine_upsample.comp and the refinement shaders.
struct RefineParams {
  vec4 fineOriginH;      // xyz: world corner of fine voxel (0,0,0), w: fine voxel size
  ivec4 fineDims;        // xyz: fine voxels per axis, w: masked voxels this frame
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
