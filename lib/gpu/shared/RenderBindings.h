// Shared by C++ and GLSL: the binding indices of the renderer's shaders. Apart from Render.h because the
// shaders that sample the field declare it before including Render.h (its functions fetch through macros).
#ifndef RTSDF_GPU_SHARED_RENDERBINDINGS_H
#define RTSDF_GPU_SHARED_RENDERBINDINGS_H
#include "gpu/shared/Bvh.h"

RTSDF_SHARED_BEGIN

/// gbuffer.comp: the scene BVH (Bvh.h's kBvhBinding*), then the G-buffer it writes.
const uint kGBufferBindingPositions = kBvhBindingCount + 0u;
const uint kGBufferBindingNormals = kBvhBindingCount + 1u;
const uint kGBufferBindingCount = kBvhBindingCount + 2u;

/// sdf_shadow.comp (field: a sampled 3D texture), sdf_shadow_buffer.comp (field: a storage buffer) and
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

/// contact_shadow.comp: the scene BVH (Bvh.h's kBvhBinding*), then the G-buffer, the lights and the visibility it
/// lowers in place (light-major, as SdfShadowPass wrote it).
const uint kContactShadowBindingPositions = kBvhBindingCount + 0u;
const uint kContactShadowBindingNormals = kBvhBindingCount + 1u;
const uint kContactShadowBindingLights = kBvhBindingCount + 2u;
const uint kContactShadowBindingVisibility = kBvhBindingCount + 3u;
const uint kContactShadowBindingCount = kBvhBindingCount + 4u;

/// volume_fill.comp: the dense fine SDF (x fastest) into the 3D texture the march samples (a storage image).
const uint kVolumeFillBindingField = 0u;
const uint kVolumeFillBindingTexture = 1u;
const uint kVolumeFillBindingCount = 2u;

/// shadow_map.comp: the scene BVH, then the lights and the depth maps it writes.
const uint kShadowMapBindingLights = kBvhBindingCount + 0u;
const uint kShadowMapBindingDepth = kBvhBindingCount + 1u;
const uint kShadowMapBindingCount = kBvhBindingCount + 2u;

/// shadow_lookup.comp.
const uint kShadowLookupBindingPositions = 0u;
const uint kShadowLookupBindingNormals = 1u;
const uint kShadowLookupBindingDepth = 2u;
const uint kShadowLookupBindingLights = 3u;
const uint kShadowLookupBindingMaps = 4u;
const uint kShadowLookupBindingVisibility = 5u;
const uint kShadowLookupBindingCount = 6u;

/// taa.comp.
const uint kTaaBindingCurrent = 0u;
const uint kTaaBindingHistory = 1u; // in: the last output; out: this frame's
const uint kTaaBindingCount = 2u;

RTSDF_SHARED_END

#endif
