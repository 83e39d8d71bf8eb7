#pragma once
/// @file SdfShadowCpu.h
/// @brief The CPU copy of SdfShadowPass: the same march (render/sdfshadow/SdfShadowMarch.h) over the same field,
///        so the tests can compare GPU and CPU results on real scenes.
#include "render/RenderTypes.h"
#include "render/sdfshadow/SdfShadowParams.h"

#include <glm/glm.hpp>

#include <vector>

namespace rtsdf {

/// @brief SdfShadowPass on the CPU: the same march (sdfShadowMarch, or sdfShadowUmbra for kPenumbraUmbra) over the
///        same field for every pixel and light, and the same kContactPending marks where params.contactReach > 0.
LightVisibility sdfShadowsCpu(const GBuffer& gbuffer, const std::vector<float>& field,
                              const std::vector<gpu::shared::GpuLight>& lights,
                              const gpu::shared::SdfShadowParams& params);

/// @brief Camera-centred cascade levels as SdfShadowPass samples them (sdf_shadow_cascade.comp), on the CPU.
struct CascadeFieldCpu {
  std::vector<gpu::shared::CascadeFieldLevel> levels; ///< finest first (frame-relative, as uploaded)
  std::vector<std::vector<float>> fields;             ///< each level's dense fine SDF, x fastest
};

/// @brief SdfShadowPass over cascade levels (params.cascadeLevels of @a field's) on the CPU: the same march, which
///        samples the levels by the shared rule (sampleCascade).
/// @throw Error when @a field's levels and fields disagree with each other or with params.cascadeLevels.
LightVisibility sdfShadowsCpu(const GBuffer& gbuffer, const CascadeFieldCpu& field,
                              const std::vector<gpu::shared::GpuLight>& lights,
                              const gpu::shared::SdfShadowParams& params);

/// @brief The field the march samples at frame-relative point @a p (sampleSdf over the cascade levels).
/// @throw Error as the overload above.
float sampleCascadeFieldCpu(const CascadeFieldCpu& field, const gpu::shared::SdfShadowParams& params,
                            const glm::vec3& p);

} // namespace rtsdf
