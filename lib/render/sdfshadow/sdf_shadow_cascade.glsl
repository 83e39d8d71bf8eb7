// The fine SDF of camera-centred cascade levels, for sdf_shadow_cascade.comp and sdf_shadow_umbra_cascade.comp
// (sdf_shadow_main.glsl with RTSDF_SHADOW_FIELD_CASCADE): the level table and each level's dense fine SDF at its own
// binding (a switch picks it: an array of buffers would need descriptor indexing). sampleSdf (SdfShadowMarch.h)
// blends the levels as CascadeSamplerCpu does. Include after SdfShadowParams.h, before SdfShadowMarch.h.
layout(std430, binding = kSdfShadowBindingCascadeLevels) readonly buffer CascadeLevels { CascadeFieldLevel levels[]; };
layout(std430, binding = kSdfShadowBindingCascadeFields + 0) readonly buffer Level0 { float v[]; } level0;
layout(std430, binding = kSdfShadowBindingCascadeFields + 1) readonly buffer Level1 { float v[]; } level1;
layout(std430, binding = kSdfShadowBindingCascadeFields + 2) readonly buffer Level2 { float v[]; } level2;
layout(std430, binding = kSdfShadowBindingCascadeFields + 3) readonly buffer Level3 { float v[]; } level3;
layout(std430, binding = kSdfShadowBindingCascadeFields + 4) readonly buffer Level4 { float v[]; } level4;
layout(std430, binding = kSdfShadowBindingCascadeFields + 5) readonly buffer Level5 { float v[]; } level5;
layout(std430, binding = kSdfShadowBindingCascadeFields + 6) readonly buffer Level6 { float v[]; } level6;
layout(std430, binding = kSdfShadowBindingCascadeFields + 7) readonly buffer Level7 { float v[]; } level7;
layout(std430, binding = kSdfShadowBindingCascadeFields + 8) readonly buffer Level8 { float v[]; } level8;
layout(std430, binding = kSdfShadowBindingCascadeFields + 9) readonly buffer Level9 { float v[]; } level9;
#if RTSDF_MAX_CASCADE_LEVELS != 10
#error "one buffer block per cascade level: RTSDF_MAX_CASCADE_LEVELS changed"
#endif

float fetchLevel(int level, int i) {
  switch (level) {
  case 0: return level0.v[i];
  case 1: return level1.v[i];
  case 2: return level2.v[i];
  case 3: return level3.v[i];
  case 4: return level4.v[i];
  case 5: return level5.v[i];
  case 6: return level6.v[i];
  case 7: return level7.v[i];
  case 8: return level8.v[i];
  default: return level9.v[i];
  }
}
#define RTSDF_SDF_LEVEL_FETCH(level, i) fetchLevel(level, i)
#define RTSDF_CASCADE_LEVEL(i) levels[i]
