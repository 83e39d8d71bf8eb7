#pragma once
/// @file ContactShadowCpu.h
/// @brief The CPU copy of ContactShadowPass: the same rays (render/contactshadow/ContactShadowParams.h), traced by
///        Embree.
#include "render/RenderTypes.h"
#include "render/contactshadow/ContactShadowParams.h"
#include "scene/SceneGeometry.h"

#include <vector>

namespace rtsdf {

/// @brief ContactShadowPass on the CPU: at every pixel and light that @a visibility marks (kContactPending added by
///        sdfShadowsCpu), params.rays short rays from the surface point (offset params.normalOffset along the normal)
///        towards the light's disc (lightDiscDirection, turned by the pixel's jitter as the shader turns them), each
///        blocked by any triangle within min(params.distance, the distance to the light) (Embree, through
///        ExactDistanceField::intersect); the mark is taken off and the visibility lowered to the fraction of rays
///        left open.
/// @param geometry the triangles in the G-buffer's frame (buildSceneGeometry with the G-buffer's origin).
/// @param visibility in: sdfShadowsCpu's; out: the pass's.
/// @note A ray that grazes an edge may hit in one tracer and not in the other (Embree's watertight test against the
///       shader's Moller-Trumbore): compare with a tolerance on the number of pixels.
/// @throw Error when the parameters, lights and visibility do not match the G-buffer.
void contactShadowsCpu(const SceneGeometry& geometry, const GBuffer& gbuffer,
                       const std::vector<gpu::shared::GpuLight>& lights, const gpu::shared::ContactShadowParams& params,
                       LightVisibility& visibility);

} // namespace rtsdf
