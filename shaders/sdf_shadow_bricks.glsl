// The fine SDF fetched from SdfPipeline's sparse state (GpuBrickField), for sdf_shadow_bricks.comp and
// sdf_shadow_umbra_bricks.comp: fine voxel v is the pool's value where its brick has a slot (BrickFillPass filled
// the voxels outside the band), else the coarse SDF upsampled at v, so the march samples the values a dense
// resolve holds, bit for bit. Include before sdf_shadow_main.glsl, after RenderBindings.h.
#include "gpu/shared/Refine.h"
layout(std430, binding = kSdfShadowBindingField) readonly buffer Coarse { float coarse[]; };
layout(std430, binding = kSdfShadowBindingBrickSlots) readonly buffer BrickSlots { uint brickSlots[]; };
layout(std430, binding = kSdfShadowBindingBrickParams) readonly buffer BrickField { RefineParams field; };
#define RTSDF_POOL_PARAMS field
#define RTSDF_UPSAMPLE_PARAMS field
#define RTSDF_VALUE_PAGES kSdfShadowBindingValuePages
#define RTSDF_POOL_READONLY
#include "brick_pool.glsl"
#include "coarse_upsample.glsl"

// The fine SDF at linear fine index i (x fastest).
float fetchBrickField(int i) {
  ivec3 fd = field.fineDims.xyz;
  ivec3 v = ivec3(i % fd.x, i / fd.x % fd.y, i / (fd.x * fd.y));
  uint slot = brickSlots[brickIndexOf(v, field.brickDims.xyz)];
  return slot != kNoBrick ? loadValue(slot, brickLocalOf(v)) : upsampleCoarseAt(v);
}
#define RTSDF_SDF_FETCH(i) fetchBrickField(i)
