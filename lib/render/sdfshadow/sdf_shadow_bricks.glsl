// The fine SDF fetched from SdfPipeline's sparse state (GpuBrickField), for sdf_shadow_bricks.comp and
// sdf_shadow_umbra_bricks.comp (sdf_shadow_main.glsl with RTSDF_SHADOW_FIELD_BRICKS): fine voxel v is the pool's
// value where it lies under the band (|c| <= d at its coarse slab) and its brick has a slot, else the coarse SDF
// upsampled at v: the values the dense fine SDF holds, bit for bit. Include after SdfShadowParams.h, before
// SdfShadowMarch.h.
#include "sdf/refine/RefineParams.h"
layout(std430, binding = kSdfShadowBindingField) readonly buffer Coarse { float coarse[]; };
layout(std430, binding = kSdfShadowBindingBrickSlots) readonly buffer BrickSlots { uint brickSlots[]; };
layout(std430, binding = kSdfShadowBindingBrickParams) readonly buffer BrickField { RefineParams field; };
layout(std430, binding = kSdfShadowBindingFineToCoarse) readonly buffer FineToCoarse { int fineToCoarse[]; };
#define RTSDF_POOL_PARAMS field
#define RTSDF_UPSAMPLE_PARAMS field
#define RTSDF_VALUE_PAGES kSdfShadowBindingValuePages
#define RTSDF_POOL_READONLY
#include "sdf/mask/brick_pool.glsl"
#include "sdf/refine/coarse_upsample.glsl"

// The fine SDF at linear fine index i (x fastest).
float fetchBrickField(int i) {
  ivec3 fd = field.fineDims.xyz;
  ivec3 v = ivec3(i % fd.x, i / fd.x % fd.y, i / (fd.x * fd.y));
  uint slot = brickSlots[brickIndexOf(v, field.brickDims.xyz)];
  if (slot != kNoBrick) { // the band test only inside bricks: elsewhere no voxel is under the band
    ivec3 c = ivec3(fineToCoarse[v.x], fineToCoarse[fd.x + v.y], fineToCoarse[fd.x + fd.y + v.z]);
    ivec3 cd = field.coarseDims.xyz;
    if (all(greaterThanEqual(c, ivec3(0))) && abs(coarse[(c.z * cd.y + c.y) * cd.x + c.x]) <= field.band)
      return loadValue(slot, brickLocalOf(v));
  }
  return upsampleCoarseAt(v);
}
#define RTSDF_SDF_FETCH(i) fetchBrickField(i)
