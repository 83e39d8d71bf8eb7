// Shared by C++ and GLSL: the bindings and push constants of SdfShadowPass (sdf_shadow_main.glsl and its
// variants), VolumeFillPass (volume_fill.comp) and VolumeUpdatePass (volume_update_main.glsl, which pushes
// RefineParams). The march itself is in SdfShadowMarch.h: the shaders that
// sample the field declare it at these bindings before including the march (its functions fetch through macros).
#ifndef RTSDF_RENDER_SDFSHADOW_SDFSHADOWPARAMS_H
#define RTSDF_RENDER_SDFSHADOW_SDFSHADOWPARAMS_H
#include "render/RenderParams.h"
#include "sdf/refine/RefineParams.h"

RTSDF_SHARED_BEGIN

/// sdf_shadow.comp (field: a sampled 3D texture), sdf_shadow_buffer.comp (field: a storage buffer),
/// sdf_shadow_cascade.comp (camera-centred cascade levels, bindings below) and
/// sdf_shadow_bricks.comp (field: the coarse SDF, with the brick pool's slots, parameters, value pages and the
/// fine-to-coarse tables after kSdfShadowBindingCount: the fine SDF as SdfPipeline's sparse state holds it).
const uint kSdfShadowBindingPositions = 0u;
const uint kSdfShadowBindingNormals = 1u;
const uint kSdfShadowBindingField = 2u;
const uint kSdfShadowBindingLights = 3u;
const uint kSdfShadowBindingVisibility = 4u;
const uint kSdfShadowBindingCount = 5u;
const uint kSdfShadowBindingBrickSlots = kSdfShadowBindingCount + 0u;  // uint per brick: its slot
const uint kSdfShadowBindingBrickParams = kSdfShadowBindingCount + 1u; // one RefineParams: grids, bricks, pages
const uint kSdfShadowBindingValuePages = kSdfShadowBindingCount + 2u;  // RTSDF_BRICK_PAGES pages of the values
const uint kSdfShadowBindingFineToCoarse = kSdfShadowBindingCount + 6u; // maskCoarseOfFine(): the band test
const uint kSdfShadowBindingBrickCount = kSdfShadowBindingCount + 7u;

/// sdf_shadow_cascade.comp (cascade levels: the field binding unused): the level table (CascadeFieldLevel per level,
/// finest first) and each level's dense fine SDF at its own binding (levels past the count bind level 0's again).
#define RTSDF_MAX_CASCADE_LEVELS 10
const uint kSdfShadowBindingCascadeLevels = kSdfShadowBindingCount + 0u;
const uint kSdfShadowBindingCascadeFields = kSdfShadowBindingCount + 1u;
const uint kSdfShadowBindingCascadeCount = kSdfShadowBindingCascadeFields + RTSDF_MAX_CASCADE_LEVELS;

/// One cascade level as the march samples it (CascadeSamplerCpu's rule, sampleSdf in SdfShadowMarch.h).
struct CascadeFieldLevel {
  vec4 originH; // xyz: world corner of the level's fine voxel (0,0,0) (frame-relative), w: its fine voxel size
  ivec4 dims;   // xyz: fine voxels per axis
  vec4 blend;   // x: the band at the level's margin over which it fades into the next coarser level (scene units)
};

/// How far p lies inside cascade level @a lv's box beyond one of its fine voxels (> 0: the level's whole trilinear
/// stencil lies in it), in scene units.
RTSDF_FN float insideLevel(CascadeFieldLevel lv, vec3 p) {
  float h = lv.originH.w;
  vec3 lo = vec3(lv.originH);
  vec3 hi = lo + vec3(lv.dims.x, lv.dims.y, lv.dims.z) * h;
  vec3 d = min(p - lo, hi - p);
  return min(d.x, min(d.y, d.z)) - h;
}

/// volume_fill.comp: the dense fine SDF (x fastest) into the 3D texture the march samples (a storage image).
const uint kVolumeFillBindingField = 0u;
const uint kVolumeFillBindingTexture = 1u;
const uint kVolumeFillBindingCount = 2u;

/// volume_update_*.comp: the texels of the fine voxels an SdfPipeline frame wrote (DenseFineWrites), from the dense
/// fine SDF into the 3D texture, over the pipeline's own lists.
const uint kVolumeUpdateBindingField = 0u;       // the dense fine SDF, x fastest
const uint kVolumeUpdateBindingTexture = 1u;     // the 3D texture (a storage image)
const uint kVolumeUpdateBindingBlockList = 2u;   // UpsampleBlocksPass's list (UpsampleBlockListHeader, then blocks)
const uint kVolumeUpdateBindingFineBegins = 3u;  // upsampleBlockFineBegins of the grids
const uint kVolumeUpdateBindingRefineList = 4u;  // the mask's refine list (coarse voxels and flags)
const uint kVolumeUpdateBindingMaskCounts = 5u;  // the mask's counts: the refinement's dispatch, the list's length
const uint kVolumeUpdateBindingFineRanges = 6u;  // maskFineRanges of the grids
const uint kVolumeUpdateBindingCount = 7u;

/// How the SDF soft shadow turns the march into a visibility.
const uint kPenumbraClassic = 0u;  // min over samples of h / (w t): the classic estimate (outer penumbra)
const uint kPenumbraImproved = 1u; // triangulated between consecutive samples (fewer banding artifacts)
const uint kPenumbraCentered = 2u; // marches on inside occluders (signed h), penumbra centred on the
                                   // geometric shadow boundary like a real area light's
const uint kPenumbraUmbra = 3u;    // lightSamples centred marches towards jittered points of the light's
                                   // disc, each over its share of the cone, averaged (the SDF-simulated umbra)

/// Push constants of sdf_shadow.comp (and its CPU copy).
struct SdfShadowParams {
  vec4 gridOriginH; // xyz: world corner of fine voxel (0,0,0), w: voxel size
  ivec4 gridDims;   // xyz: fine voxels per axis, w: number of lights
  ivec4 image;      // x: width, y: height, z: frame number (jitter), w: seed
  float epsilon;    // a sample closer than this is a hit; also where the march starts (scene units, >= one voxel)
  float bias;       // subtracted from every SDF sample: thin surfaces cannot leak light (scene units)
  float maxStep;    // longest step (against banding where h is large)
  float normalOffset; // the march starts this far off the surface along its normal
  uint maxSteps;
  uint penumbra;    // kPenumbra*
  float jitter;     // 0: start at epsilon; 1: start spread over [0.25, 1.25] epsilon per pixel and frame, probes
                    // and umbra samples turned per pixel and frame
  float minStep;    // shortest step: the march samples h at least this densely near occluders
  uint lateralProbes; // centred and umbra: SDF samples around the cone where the ray came closest to an
                      // occluder (tells a plate crossing the whole cone from an edge; 0: off)
  uint lightSamples;  // umbra: marches per pixel, light and frame (>= 1)
  float contactReach; // > 0: mark the pixels where something other than the receiver's own plane lies within
                      // this distance (sdfShadowMarch's contact) for ContactShadowPass; 0: the pass does not run
  uint cascadeLevels; // 0: one box (gridOriginH, gridDims); else the march samples this many cascade levels
                      // (CascadeFieldLevel), gridOriginH's voxel being level 0's
};

/// SdfShadowPass adds this to the visibility of the pixels (and lights) whose contact rays ContactShadowPass is to
/// trace; that pass takes it off again (the visibility itself is in [0, 1]).
const float kContactPending = 2.0f;

/// A pixel's mark for ContactShadowPass: its visibility v (in (0, 1]) plus kContactPending times the scale of the
/// contact rays' reach: 1 for one box; with cascade levels 2^i for a receiver in level i, whose field is that much
/// coarser (marchParamsAt scales the march's contact test alike), so the rays reach as far as the march looked.
RTSDF_FN float contactMark(float v, float reachScale) { return v + kContactPending * reachScale; }
/// The reach scale contactMark stored in @a marked (>= kContactPending), a power of two; the visibility is
/// marked - kContactPending * scale. (marked / kContactPending lies in [scale, scale + 1/2]: a quarter added before
/// the floor keeps a log2 a little short of a whole number from losing a level.)
RTSDF_FN float contactReachScale(float marked) { return exp2(floor(log2(marked / kContactPending) + 0.25f)); }

RTSDF_SHARED_END

#endif
