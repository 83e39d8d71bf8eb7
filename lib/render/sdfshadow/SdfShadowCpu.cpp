// The march fetches the field through these macros, defined before anything includes SdfShadowMarch.h. The pointers
// are set per call (worker threads only read them; one call at a time).
#include "render/sdfshadow/SdfShadowParams.h"
namespace {
const float* gField = nullptr;
const float* const* gLevelFields = nullptr;
const rtsdf::gpu::shared::CascadeFieldLevel* gLevels = nullptr;
} // namespace
#define RTSDF_SDF_FETCH(i) gField[i]
#define RTSDF_CASCADE_LEVEL(i) gLevels[i]
#include "render/sdfshadow/DenseGridSampler.h"
RTSDF_SHARED_BEGIN
#define RTSDF_LEVEL_FETCH(level, i) gLevelFields[level][i]
RTSDF_DEFINE_DENSE_SAMPLER(sampleLevelGrid, RTSDF_LEVEL_FETCH)
RTSDF_SHARED_END
#define RTSDF_SDF_LEVEL_SAMPLE(level, originH, dims, p) sampleLevelGrid(level, originH, dims, p)
#include "render/sdfshadow/SdfShadowMarch.h"
#include "render/sdfshadow/SdfShadowCpu.h"
#include "util/Error.h"

#include <fmt/format.h>
#include <tbb/parallel_for.h>

namespace rtsdf {
namespace sh = gpu::shared;

namespace {

/// Every pixel and light, with the field already behind the macros.
LightVisibility marchEveryPixel(const GBuffer& g, const std::vector<sh::GpuLight>& lights,
                                const sh::SdfShadowParams& params) {
  LightVisibility vis(lights.size(), std::vector<float>(g.pixelCount(), 1.0f));
  glm::vec3 lo, hi;
  sh::marchBox(params, lo, hi);
  tbb::parallel_for(0, g.height, [&](int y) {
    for (int x = 0; x < g.width; ++x) {
      const std::size_t i = std::size_t(y) * std::size_t(g.width) + std::size_t(x);
      if (!g.hit(i)) continue;
      const float jitter = sh::pixelJitter(std::uint32_t(i), std::uint32_t(params.image.z), std::uint32_t(params.image.w));
      for (std::size_t l = 0; l < lights.size(); ++l) {
        glm::vec3 L;
        float tMax, w;
        const glm::vec3 p(g.position[i]), n(g.normal[i]);
        if (!sh::lightGeometry(lights[l], p, lo, hi, L, tMax, w)) continue;
        const sh::SdfShadowParams at = sh::marchParamsAt(params, p);
        float& v = vis[l][i];
        bool contact = false;
        v = params.penumbra == sh::kPenumbraUmbra
                ? sh::sdfShadowUmbra(at, p, n, L, tMax, w, jitter, contact)
                : sh::sdfShadowMarch(at, params.penumbra, p, n, L, tMax, w, jitter, contact);
        if (contact && v > 0.0f) v = sh::contactMark(v, at.gridOriginH.w / params.gridOriginH.w);
      }
    }
  });
  return vis;
}

/// Points the macros at @a field's levels for as long as it lives.
class CascadeBinding {
public:
  CascadeBinding(const CascadeFieldCpu& field, const sh::SdfShadowParams& params) {
    const std::size_t n = field.levels.size();
    if (n == 0 || n != field.fields.size() || n != params.cascadeLevels)
      throw Error(fmt::format("cascade shading on the CPU: {} levels, {} fields, {} asked for", n,
                              field.fields.size(), params.cascadeLevels));
    for (std::size_t i = 0; i < n; ++i) {
      const glm::ivec4 d = field.levels[i].dims;
      if (field.fields[i].size() != std::size_t(d.x) * std::size_t(d.y) * std::size_t(d.z))
        throw Error(fmt::format("cascade shading on the CPU: level {} has {} values for {}x{}x{} voxels", i,
                                field.fields[i].size(), d.x, d.y, d.z));
      mPointers.push_back(field.fields[i].data());
    }
    gLevelFields = mPointers.data();
    gLevels = field.levels.data();
  }
  ~CascadeBinding() {
    gLevelFields = nullptr;
    gLevels = nullptr;
  }
  CascadeBinding(const CascadeBinding&) = delete;
  CascadeBinding& operator=(const CascadeBinding&) = delete;

private:
  std::vector<const float*> mPointers;
};

} // namespace

LightVisibility sdfShadowsCpu(const GBuffer& g, const std::vector<float>& field, const std::vector<sh::GpuLight>& lights,
                              const sh::SdfShadowParams& params) {
  if (params.cascadeLevels != 0u) throw Error("sdfShadowsCpu: the parameters ask for cascade levels; pass them");
  gField = field.data();
  return marchEveryPixel(g, lights, params);
}

LightVisibility sdfShadowsCpu(const GBuffer& g, const CascadeFieldCpu& field, const std::vector<sh::GpuLight>& lights,
                              const sh::SdfShadowParams& params) {
  const CascadeBinding bind(field, params);
  return marchEveryPixel(g, lights, params);
}

float sampleCascadeFieldCpu(const CascadeFieldCpu& field, const sh::SdfShadowParams& params, const glm::vec3& p) {
  const CascadeBinding bind(field, params);
  return sh::sampleSdf(params, p);
}

} // namespace rtsdf
