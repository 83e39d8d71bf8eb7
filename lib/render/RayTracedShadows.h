#pragma once
/// @file RayTracedShadows.h
/// @brief The renderer's ground truth on the CPU: primary visibility and distributed ray-traced soft shadows
///        through Embree, over the exact scene triangles.
#include "render/RenderTypes.h"
#include "scene/SceneGeometry.h"
#include "util/JobControl.h"

#include <cstdint>
#include <vector>

namespace rtsdf {

/// @brief Primary visibility through Embree (rtcIntersect1) for every pixel's camera ray: direction
///        gpu::shared::cameraDirection(camera, x + 0.5, y + 0.5), origin camera.position, t in [0, inf).
/// GBuffer (lib/render/RenderTypes.h): position.xyz = hit, position.w = t (-1 on a miss); normal.xyz = unit
/// geometric normal turned towards the camera, normal.w = index of the hit mesh in geometry.meshes (== the scene's
/// instance index) as a float, -1 on a miss. Parallel over rows with TBB.
/// @param geometry the world-space triangles (buildSceneGeometry); a scene without triangles gives only misses.
/// @param camera the camera (makeCameraParams); its size is the G-buffer's.
/// @note The hit point is origin + t * direction in float; the normal is the triangle's own (from its corners,
///       computed in double), not Embree's Ng.
/// @throw Error when the camera's image size is not positive, or when Embree fails.
GBuffer traceGBuffer(const SceneGeometry& geometry, const gpu::shared::CameraParams& camera);

/// @brief Settings of the distributed ray tracer.
struct RayTracedShadowSettings {
  int samples = 256;          ///< shadow rays per pixel and light (stratified over the light), >= 1
  std::uint32_t seed = 1;
  double normalOffset = -1.0; ///< shadow-ray origin offset along the normal; < 0: 1e-4 x the scene's largest extent
};

/// @brief Visibility of each light at each G-buffer pixel: the fraction of shadow rays, spread uniformly over the
///        light's solid angle (a cone of the angular radius around the direction for directional lights, the cone
///        subtended by the sphere for sphere lights; a zero radius gives one exact direction), that reach the light
///        unoccluded. Pixels without a hit get 1. A point inside a sphere light gets 1. Parallel (TBB), deterministic
///        for a seed (per-pixel random streams, e.g. a PCG hash of pixel and sample; results must not depend on thread
///        scheduling).
/// @param geometry the world-space triangles the G-buffer was traced against.
/// @param lights the lights; Light::direction is the direction a directional light travels.
/// @param gbuffer primary visibility (traceGBuffer or any renderer's); rays start at position.xyz offset by
///        settings.normalOffset along normal.xyz.
/// @param settings samples, seed and the ray offset.
/// @return visibility[light][pixel] in [0, 1], a multiple of 1 / samples (of 1 for a zero-radius light).
/// @note Sampling: sample i of N takes the i-th of N equal-area rings of the light's cone (jittered within the
///       ring) and an azimuth from a golden-ratio sequence with a random rotation per pixel -- a randomised
///       sunflower (Vogel) pattern, unbiased for every N and far less noisy than independent samples. The random
///       numbers are PCG hashes of (seed, light, pixel, sample).
/// @note A shadow ray is blocked by any triangle in (0, distance to the light) -- for a sphere light, the
///       distance to the sphere's near surface along the ray. No cosine weighting; directions below the surface
///       are blocked by the surface's own mesh where that mesh is closed.
/// @throw Error on samples < 1 or a G-buffer whose size does not match, a non-finite normalOffset, an invalid
///        light (non-finite values, a zero direction, an angular radius outside [0, pi/2), a negative radius),
///        or when Embree fails; Interrupted when @a control asks to stop.
/// @param control progress ("ray tracing", rows of pixels done) and stop requests, polled per row from the worker
///        threads; null: neither.
LightVisibility rayTracedVisibility(const SceneGeometry& geometry, const std::vector<Light>& lights,
                                    const GBuffer& gbuffer, const RayTracedShadowSettings& settings = {},
                                    const JobControl* control = nullptr);

} // namespace rtsdf
