// Shared by C++ and GLSL: the bindings of gbuffer.comp (GBufferPass); its push constants are the camera
// (render/RenderParams.h's CameraParams).
#ifndef RTSDF_RENDER_GBUFFER_GBUFFERPARAMS_H
#define RTSDF_RENDER_GBUFFER_GBUFFERPARAMS_H
#include "bvh/GpuBvhLayout.h"
#include "render/RenderParams.h"

RTSDF_SHARED_BEGIN

/// gbuffer.comp: the scene BVH (GpuBvhLayout.h's kBvhBinding*), then the G-buffer it writes.
const uint kGBufferBindingPositions = kBvhBindingCount + 0u;
const uint kGBufferBindingNormals = kBvhBindingCount + 1u;
const uint kGBufferBindingCount = kBvhBindingCount + 2u;

RTSDF_SHARED_END

#endif
