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

// One trilinear filter per level's buffer and one switch per sample. The switch's cost grows with its cases (on
// lavapipe a march over 2 levels took 0.37 s with 4 cases, 1.0 s with 10, 1.8 s with a 10-case switch per fetch), so
// the shader is built twice: RTSDF_CASCADE_CASES 4 (up to 4 levels) and 10.
#if RTSDF_CASCADE_CASES != 4 && RTSDF_CASCADE_CASES != RTSDF_MAX_CASCADE_LEVELS
#error "define RTSDF_CASCADE_CASES as 4 or RTSDF_MAX_CASCADE_LEVELS"
#endif
#include "render/sdfshadow/DenseGridSampler.h"
#define RTSDF_LEVEL_FETCH_0(level, i) level0.v[i]
#define RTSDF_LEVEL_FETCH_1(level, i) level1.v[i]
#define RTSDF_LEVEL_FETCH_2(level, i) level2.v[i]
#define RTSDF_LEVEL_FETCH_3(level, i) level3.v[i]
RTSDF_DEFINE_DENSE_SAMPLER(sampleLevel0, RTSDF_LEVEL_FETCH_0)
RTSDF_DEFINE_DENSE_SAMPLER(sampleLevel1, RTSDF_LEVEL_FETCH_1)
RTSDF_DEFINE_DENSE_SAMPLER(sampleLevel2, RTSDF_LEVEL_FETCH_2)
RTSDF_DEFINE_DENSE_SAMPLER(sampleLevel3, RTSDF_LEVEL_FETCH_3)
#if RTSDF_CASCADE_CASES > 4
#define RTSDF_LEVEL_FETCH_4(level, i) level4.v[i]
#define RTSDF_LEVEL_FETCH_5(level, i) level5.v[i]
#define RTSDF_LEVEL_FETCH_6(level, i) level6.v[i]
#define RTSDF_LEVEL_FETCH_7(level, i) level7.v[i]
#define RTSDF_LEVEL_FETCH_8(level, i) level8.v[i]
#define RTSDF_LEVEL_FETCH_9(level, i) level9.v[i]
RTSDF_DEFINE_DENSE_SAMPLER(sampleLevel4, RTSDF_LEVEL_FETCH_4)
RTSDF_DEFINE_DENSE_SAMPLER(sampleLevel5, RTSDF_LEVEL_FETCH_5)
RTSDF_DEFINE_DENSE_SAMPLER(sampleLevel6, RTSDF_LEVEL_FETCH_6)
RTSDF_DEFINE_DENSE_SAMPLER(sampleLevel7, RTSDF_LEVEL_FETCH_7)
RTSDF_DEFINE_DENSE_SAMPLER(sampleLevel8, RTSDF_LEVEL_FETCH_8)
RTSDF_DEFINE_DENSE_SAMPLER(sampleLevel9, RTSDF_LEVEL_FETCH_9)
#endif

float sampleLevelGrid(int level, vec4 originH, ivec4 dims, vec3 p) {
  switch (level) {
  case 0: return sampleLevel0(level, originH, dims, p);
  case 1: return sampleLevel1(level, originH, dims, p);
  case 2: return sampleLevel2(level, originH, dims, p);
#if RTSDF_CASCADE_CASES > 4
  case 3: return sampleLevel3(level, originH, dims, p);
  case 4: return sampleLevel4(level, originH, dims, p);
  case 5: return sampleLevel5(level, originH, dims, p);
  case 6: return sampleLevel6(level, originH, dims, p);
  case 7: return sampleLevel7(level, originH, dims, p);
  case 8: return sampleLevel8(level, originH, dims, p);
  default: return sampleLevel9(level, originH, dims, p);
#else
  default: return sampleLevel3(level, originH, dims, p);
#endif
  }
}
#define RTSDF_SDF_LEVEL_SAMPLE(level, originH, dims, p) sampleLevelGrid(level, originH, dims, p)
#define RTSDF_CASCADE_LEVEL(i) levels[i]
