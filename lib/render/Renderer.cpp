#include "render/Renderer.h"

#include "render/compose/ComposeParams.h"
#include "image/ImageMetrics.h"
#include "scene/SceneGeometry.h"
#include "image/ImageIO.h"
#include "util/Error.h"

#include <fmt/format.h>
#include <spdlog/spdlog.h>

#include <algorithm>
#include <chrono>
#include <cmath>

namespace rtsdf {
using gpu::Buffer;
namespace sh = gpu::shared;

void RenderSettings::validate() const {
  validateKnobs(*this);
  validateKnobs(sdf);
  validateKnobs(shadowMap);
  validateKnobs(taa);
  validateKnobs(rayTraced);
  if (technique == ShadowTechnique::Sdf) pipeline.validate();
}

std::vector<sh::ShadowMapParams> makeShadowMapParams(const std::vector<sh::GpuLight>& lights, const Bounds& bounds,
                                                     const ShadowMapSettings& s, int width, int height) {
  std::vector<sh::ShadowMapParams> maps;
  const glm::dvec3 c = bounds.center();
  const double radius = std::max(0.5 * glm::length(bounds.extent()), 1e-6);
  for (std::size_t l = 0; l < lights.size(); ++l) {
    sh::ShadowMapParams m{};
    m.center = glm::vec4(glm::vec3(c), float(radius));
    const glm::dvec3 L = glm::normalize(glm::dvec3(glm::vec3(lights[l].position)));
    const glm::dvec3 helper = std::abs(L.y) < 0.9 ? glm::dvec3(0, 1, 0) : glm::dvec3(1, 0, 0);
    const glm::dvec3 right = glm::normalize(glm::cross(helper, L)), up = glm::cross(L, right);
    m.lightAxis = glm::vec4(glm::vec3(L), float(radius * 1.05)); // the map plane lies just outside the scene
    m.right = glm::vec4(glm::vec3(right), 0.0f);
    m.up = glm::vec4(glm::vec3(up), 0.0f);
    m.info = glm::ivec4(s.resolution, int(l), int(lights[l].position.w), int(lights.size()));
    m.image = glm::ivec4(width, height, s.pcfRadius, 0);
    m.depthBias = float(s.depthBiasTexels);
    maps.push_back(m);
  }
  return maps;
}

std::string lightChannelName(const Scene& scene, std::size_t light) {
  const std::string& n = scene.lights.at(light).name;
  return n.empty() ? fmt::format("light{}", light) : n;
}

namespace {
using gpu::kStorage;

void checkRenderable(const Scene& scene) {
  if (!scene.hasCamera) throw Error(fmt::format("{}: the scene has no camera to render from", scene.path));
  if (scene.lights.empty()) throw Error(fmt::format("{}: the scene has no light to cast shadows", scene.path));
}

GBuffer downloadGBuffer(const gpu::VulkanContext& ctx, const GpuGBuffer& g, const glm::dvec3& frameOrigin) {
  GBuffer out;
  out.origin = frameOrigin;
  out.width = g.width;
  out.height = g.height;
  out.position.resize(out.pixelCount());
  out.normal.resize(out.pixelCount());
  download(ctx, g.position, out.position.data(), out.position.size() * sizeof(glm::vec4));
  download(ctx, g.normal, out.normal.data(), out.normal.size() * sizeof(glm::vec4));
  return out;
}

LightVisibility downloadVisibility(const gpu::VulkanContext& ctx, const Buffer& b, std::size_t lights,
                                   std::size_t pixels) {
  std::vector<float> all(lights * pixels);
  download(ctx, b, all.data(), all.size() * 4);
  LightVisibility v(lights);
  for (std::size_t l = 0; l < lights; ++l)
    v[l].assign(all.begin() + std::ptrdiff_t(l * pixels), all.begin() + std::ptrdiff_t((l + 1) * pixels));
  return v;
}
} // namespace

struct Renderer::Gpu {
  GBufferPass gbufferPass;
  SdfShadowPass sdfShadowPass;
  ContactShadowPass contactShadowPass;
  ShadowMapPass shadowMapPass;
  TaaPass taaPass;
  gpu::GpuProfiler profiler;
  GpuGBuffer gbuffer;
  Buffer lights, visibility, history, depth, maps;
  Buffer cascadeLevels;           ///< cascades: a CascadeFieldLevel per level
  gpu::SampledVolume fineTexture; ///< SdfSampling::Texture: the fine SDF for hardware-filtered sampling
  bool textureCurrent = false;    ///< fineTexture holds the fine SDF as the last frame left it
  std::uint32_t textureFrame = 0; ///< the SdfPipeline frame whose fine SDF fineTexture holds
  Gpu(const gpu::VulkanContext& ctx, bool umbra)
      : gbufferPass(ctx), sdfShadowPass(ctx, umbra), contactShadowPass(ctx), shadowMapPass(ctx), taaPass(ctx),
        profiler(ctx) {}
};

Renderer::Renderer(const gpu::VulkanContext& ctx, const Scene& scene, const Bounds& sdfBounds,
                   const RenderSettings& settings, double firstFrameTime)
    : mCtx(ctx), mScene(scene), mSettings(settings), mBounds(sdfBounds) {
  if (settings.technique == ShadowTechnique::RayTraced)
    throw Error("the GPU renderer draws sdf or shadowmap shadows; ray tracing runs on the CPU (renderRayTraced)");
  settings.validate();
  checkRenderable(scene);
  // The GPU works near the scene: the SDF's frame (its fine grid's corner, SdfPipeline::frameOrigin()), or the
  // corner of the bounds for shadow maps and cascades (whose levels move with the camera). Known before anything is
  // allocated, so a bad camera is refused first.
  const bool cascaded = settings.technique == ShadowTechnique::Sdf && settings.pipeline.cascades > 1;
  if (settings.technique == ShadowTechnique::Sdf && !cascaded)
    mFrameOrigin = pipelineGrids(sdfBounds, settings.pipeline).second.origin;
  else
    mFrameOrigin = sdfBounds.empty() ? glm::dvec3(0.0) : sdfBounds.min;
  mCamera = makeCameraParams(scene.camera, settings.width, settings.height, mFrameOrigin);
  mEye = scene.cameraAt(firstFrameTime);
  mLights = makeGpuLights(scene.lights, mFrameOrigin);
  if (settings.technique == ShadowTechnique::Sdf) {
    // Sampling the bricks needs no dense fine SDF; the other ways sample one.
    PipelineSettings ps = settings.pipeline;
    ps.fineStorage = settings.sdf.sampling == SdfSampling::Bricks ? FineStorage::Sparse : FineStorage::Dense;
    if (cascaded) {
      if (settings.sdf.sampling == SdfSampling::Bricks)
        throw SettingError("SDF sampling", "bricks with cascades: each level is sampled from its dense fine buffer "
                                           "(texture or buffer sampling)");
      const CascadeShape shape = cascadeShapeFor(sdfBounds, mEye.position, ps);
      mCascades = std::make_unique<CascadeSet>(
          ctx, scene, CascadeLayout::around(mEye.position, shape, cascadeLookAhead(mEye, shape.levelZeroExtent)), ps);
      mBvh = std::make_unique<GpuSceneBvh>(ctx, scene, mFrameOrigin);
    } else {
      mSdf = std::make_unique<SdfPipeline>(ctx, scene, sdfBounds, ps);
    }
  }
  const bool umbra = settings.technique == ShadowTechnique::Sdf && settings.sdf.penumbra == PenumbraEstimate::Umbra;
  mGpu = std::make_unique<Gpu>(ctx, umbra);
  const std::size_t pixels = std::size_t(settings.width) * std::size_t(settings.height);
  mGpu->gbuffer.reserve(ctx, settings.width, settings.height);
  mGpu->lights = Buffer(ctx, mLights.size() * sizeof(sh::GpuLight), kStorage, Buffer::Memory::Device, "lights");
  upload(ctx, mGpu->lights, mLights.data(), mLights.size() * sizeof(sh::GpuLight));
  const VkDeviceSize visBytes = VkDeviceSize(pixels * mLights.size() * 4);
  mGpu->visibility = Buffer(ctx, visBytes, kStorage, Buffer::Memory::Device, "visibility");
  mGpu->history = Buffer(ctx, visBytes, kStorage, Buffer::Memory::Device, "TAA history");
  if (mSdf || mCascades) {
    const GridSpec f = (mSdf ? mSdf->fineSpec() : mCascades->layout().levels.at(0).fine).inFrame(mFrameOrigin);
    mSampling = mCascades ? SdfSampling::Buffer : settings.sdf.sampling;
    if (mCascades)
      mGpu->cascadeLevels = Buffer(ctx, sizeof(sh::CascadeFieldLevel) * std::size_t(mCascades->levels()), kStorage,
                                   Buffer::Memory::Device, "cascade levels");
    if (mSampling == SdfSampling::Texture && !gpu::SampledVolume::supported(ctx)) {
      spdlog::warn("{} cannot filter R32_SFLOAT 3D textures: SDF shadows sample the fine buffer instead",
                   ctx.info().name);
      mSampling = SdfSampling::Buffer;
    }
    if (mSampling == SdfSampling::Texture)
      mGpu->fineTexture = gpu::SampledVolume(ctx, glm::uvec3(f.dims), "fine SDF texture");
    sh::SdfShadowParams& p = mSdfParams;
    p.gridOriginH = glm::vec4(glm::vec3(f.origin), float(f.voxelSize));
    p.gridDims = glm::ivec4(f.dims, int(mLights.size()));
    p.image = glm::ivec4(settings.width, settings.height, 0, int(settings.pipeline.seed));
    p.epsilon = float(settings.sdf.epsilonVoxels * f.voxelSize);
    p.bias = float(settings.sdf.biasVoxels * f.voxelSize);
    p.minStep = float(settings.sdf.minStepVoxels * f.voxelSize);
    p.maxStep = float(std::max({settings.sdf.maxStep.sceneUnits(f.voxelSize), double(p.epsilon), double(p.minStep)}));
    const double normalOffset = settings.sdf.normalOffset.sceneUnits(f.voxelSize);
    p.normalOffset = float(normalOffset >= 0.0 ? normalOffset : double(p.bias));
    p.maxSteps = std::uint32_t(settings.sdf.maxSteps);
    p.penumbra = settings.sdf.penumbra == PenumbraEstimate::Classic    ? sh::kPenumbraClassic
                 : settings.sdf.penumbra == PenumbraEstimate::Improved ? sh::kPenumbraImproved
                 : settings.sdf.penumbra == PenumbraEstimate::Umbra    ? sh::kPenumbraUmbra
                                                                       : sh::kPenumbraCentered;
    p.jitter = settings.sdf.jitter ? 1.0f : 0.0f;
    p.lateralProbes = std::uint32_t(settings.sdf.lateralProbes);
    p.lightSamples = std::uint32_t(settings.sdf.lightSamples);
    p.cascadeLevels = mCascades ? std::uint32_t(mCascades->levels()) : 0u;
    sh::ContactShadowParams& c = mContactParams;
    c.image = p.image;
    c.lights = std::uint32_t(mLights.size());
    c.rays = settings.sdf.contactVoxels > 0.0 ? std::uint32_t(settings.sdf.contactRays) : 0u;
    c.distance = float(settings.sdf.contactVoxels * f.voxelSize);
    // As the truth's shadow rays start (rayTracedVisibility): 1e-4 of the scene off the surface, clear of the
    // receiver's own triangle and still inside a gap a fraction of a voxel wide.
    c.normalOffset = float(1e-4 * sdfBounds.maxExtent());
    c.jitter = p.jitter;
    p.contactReach = c.rays > 0u ? c.distance : 0.0f;
  } else {
    mBvh = std::make_unique<GpuSceneBvh>(ctx, scene, mFrameOrigin);
    mMapParams = makeShadowMapParams(mLights, buildSceneGeometry(scene, 0.0, mFrameOrigin).bounds, settings.shadowMap,
                                     settings.width, settings.height);
    const std::size_t n = std::size_t(settings.shadowMap.resolution);
    const std::size_t bytes = mLights.size() * 6 * n * n * 4;
    if (bytes > ctx.info().maxStorageBufferRange)
      throw SettingError("shadow map resolution",
                         fmt::format("shadow map resolution {}: {} light(s) need {} MiB of depth maps, more than the "
                                     "device's storage buffer limit ({} MiB)",
                                     n, mLights.size(), bytes >> 20, ctx.info().maxStorageBufferRange >> 20));
    mGpu->depth = Buffer(ctx, bytes, kStorage, Buffer::Memory::Device, "shadow maps");
    mGpu->maps = Buffer(ctx, mMapParams.size() * sizeof(sh::ShadowMapParams), kStorage, Buffer::Memory::Device,
                        "shadow map parameters");
    upload(ctx, mGpu->maps, mMapParams.data(), mMapParams.size() * sizeof(sh::ShadowMapParams));
  }
}

Renderer::~Renderer() = default;

RenderedFrame Renderer::renderFrame(double time, bool readBack) {
  RenderedFrame out;
  out.time = time;
  ++mFrame;
  if (mFollowsSceneCamera && !mScene.cameraPath.empty())
    mCamera = makeCameraParams(mScene.cameraAt(time), mSettings.width, mSettings.height, mFrameOrigin);
  if (mFollowsSceneCamera) mEye = mScene.cameraAt(time);
  const GpuSceneBvh* bvh = nullptr;
  if (mSdf) {
    out.sdf = mSdf->runFrame(time);
    out.passMs = out.sdf.passMs;
    bvh = &mSdf->bvh();
  } else if (mCascades) {
    const double extent = mCascades->layout().shape.levelZeroExtent;
    out.cascadeMove = mCascades->moveTo(mEye.position, cascadeLookAhead(mEye, extent));
    mCascades->setView(mEye, double(mSettings.width) / mSettings.height);
    const bool moved = !out.cascadeMove.moved.empty();
    out.levels = mCascades->runFrame(time);
    out.sdf = sumFrameStats(out.levels);
    out.passMs = out.sdf.passMs;
    mBvh->update(time);
    bvh = mBvh.get();
    if (moved || mCascadeLevels.empty()) uploadCascadeLevels(); // the table changes only when a level moves
  } else {
    // Shadow maps cover the scene as it is now (the maps' frame follows the moving instances' bounds).
    mBvh->update(time);
    bvh = mBvh.get();
    // The top level's root box bounds every instance at this time: no need to transform the meshes again.
    const sh::BvhNode& root = mBvh->top().nodes.at(0);
    Bounds now;
    now.add(glm::dvec3(glm::vec3(root.lo)));
    now.add(glm::dvec3(glm::vec3(root.hi)));
    mMapParams = makeShadowMapParams(mLights, now, mSettings.shadowMap, mSettings.width, mSettings.height);
    upload(mCtx, mGpu->maps, mMapParams.data(), mMapParams.size() * sizeof(sh::ShadowMapParams));
  }
  gpu::CommandBuffer cmd(mCtx);
  Gpu& g = *mGpu;
  g.profiler.reset(cmd.handle());
  g.gbufferPass.execute(cmd.handle(), &g.profiler, {*bvh}, {g.gbuffer}, mCamera);
  if (mCascades) {
    mSdfParams.image.z = mFrame;
    GpuCascadeField levels{g.cascadeLevels, {}};
    for (int i = 0; i < mCascades->levels(); ++i) levels.fields.push_back(&mCascades->level(i).fineBuffer());
    g.sdfShadowPass.execute(cmd.handle(), &g.profiler,
                            {g.gbuffer, *levels.fields[0], nullptr, g.lights, nullptr, false, &levels},
                            {g.visibility}, mSdfParams);
  } else if (mSdf) {
    mSdfParams.image.z = mFrame;
    const gpu::SampledVolume* texture = mSampling == SdfSampling::Texture ? &g.fineTexture : nullptr;
    if (mSampling == SdfSampling::Bricks) {
      const GpuBrickField bricks = mSdf->brickField();
      g.sdfShadowPass.execute(cmd.handle(), &g.profiler, {g.gbuffer, bricks.coarse, nullptr, g.lights, &bricks},
                              {g.visibility}, mSdfParams);
    } else {
      // The 3D texture is filled only when the frame changed the fine SDF (a static scene's frames do not), and
      // where it held the frame before's, on a GPU only where this one wrote it (SdfShadowPass::Inputs::fillOnly).
      const bool fill = texture && (!g.textureCurrent || out.sdf.fieldChanged);
      const DenseFineWrites& writes = mSdf->lastFineWrites();
      const bool follows = g.textureCurrent && writes.frame == g.textureFrame + 1;
      g.sdfShadowPass.execute(cmd.handle(), &g.profiler,
                              {g.gbuffer, mSdf->fineBuffer(), texture, g.lights, nullptr, fill, nullptr,
                               follows ? &writes : nullptr},
                              {g.visibility}, mSdfParams);
      g.textureCurrent = texture != nullptr;
      g.textureFrame = writes.frame;
    }
  }
  if (mSdf || mCascades) {
    mContactParams.image.z = mFrame;
    if (mContactParams.rays > 0u)
      g.contactShadowPass.execute(cmd.handle(), &g.profiler, {*bvh, g.gbuffer, g.lights}, {g.visibility},
                                  mContactParams);
  } else {
    g.shadowMapPass.execute(cmd.handle(), &g.profiler, {*bvh, g.gbuffer, g.lights, g.maps}, {g.depth, g.visibility},
                            mMapParams);
  }
  if (mSettings.taa.enabled) {
    sh::TaaParams t{};
    t.image = glm::ivec4(mSettings.width, mSettings.height, int(mLights.size()), mFrame);
    t.blend = float(mSettings.taa.blend);
    t.clampHistory = mSettings.taa.clampHistory ? 1u : 0u;
    g.taaPass.execute(cmd.handle(), &g.profiler, {g.visibility}, {g.history}, t);
  }
  cmd.submitAndWait();
  for (const auto& r : g.profiler.results()) out.passMs.push_back(r);
  if (readBack) {
    out.gbuffer = downloadGBuffer(mCtx, g.gbuffer, mFrameOrigin);
    out.visibility = downloadVisibility(mCtx, mSettings.taa.enabled ? g.history : g.visibility, mLights.size(),
                                        out.gbuffer.pixelCount());
  }
  return out;
}

void Renderer::setCamera(const Camera& camera) {
  mCamera = makeCameraParams(camera, mSettings.width, mSettings.height, mFrameOrigin);
  mEye = camera;
  mFollowsSceneCamera = false;
}

glm::dvec3 cascadeLookAhead(const Camera& eye, double levelZeroExtent) {
  const glm::dvec3 forward = eye.target - eye.position;
  const double length = glm::length(forward);
  if (!(length > 0.0)) return glm::dvec3(0.0);
  return forward / length * (kCascadeLookAhead * levelZeroExtent);
}

void Renderer::uploadCascadeLevels() {
  mCascadeLevels.clear();
  for (const CascadeLevel& level : mCascades->layout().levels) {
    const GridSpec f = level.fine.inFrame(mFrameOrigin);
    sh::CascadeFieldLevel l{};
    l.originH = glm::vec4(glm::vec3(f.origin), float(f.voxelSize));
    l.dims = glm::ivec4(f.dims, 0);
    l.blend = glm::vec4(float(kCascadeBlendVoxels * f.voxelSize), 0.0f, 0.0f, 0.0f);
    mCascadeLevels.push_back(l);
  }
  upload(mCtx, mGpu->cascadeLevels, mCascadeLevels.data(), mCascadeLevels.size() * sizeof(sh::CascadeFieldLevel));
}

CascadeFieldCpu Renderer::cascadeField() const {
  if (!mCascades) throw Error("the renderer has no cascade levels (cascades 1)");
  CascadeFieldCpu out;
  out.levels = mCascadeLevels;
  for (int i = 0; i < mCascades->levels(); ++i) out.fields.push_back(mCascades->level(i).fineField());
  return out;
}

const GpuGBuffer& Renderer::gpuGBuffer() const { return mGpu->gbuffer; }
const Buffer& Renderer::gpuVisibility() const { return mSettings.taa.enabled ? mGpu->history : mGpu->visibility; }
const Buffer& Renderer::gpuLightBuffer() const { return mGpu->lights; }

std::vector<float> Renderer::shadowMapDepths() const {
  if (!mGpu->depth) return {};
  std::vector<float> d(mGpu->depth.size() / 4);
  download(mCtx, mGpu->depth, d.data(), d.size() * 4);
  return d;
}

LightVisibility Renderer::rawVisibility() const {
  return downloadVisibility(mCtx, mGpu->visibility, mLights.size(),
                            std::size_t(mSettings.width) * std::size_t(mSettings.height));
}

RenderedFrame renderRayTraced(const Scene& scene, double time, const RenderSettings& settings,
                              const JobControl* control) {
  settings.validate();
  checkRenderable(scene);
  RenderedFrame out;
  out.time = time;
  const SceneGeometry geo = buildSceneGeometry(scene, time);
  const auto t0 = std::chrono::steady_clock::now();
  out.gbuffer = traceGBuffer(geo, makeCameraParams(scene.cameraAt(time), settings.width, settings.height));
  const auto t1 = std::chrono::steady_clock::now();
  out.visibility = rayTracedVisibility(geo, scene.lights, out.gbuffer, settings.rayTraced, control);
  const auto t2 = std::chrono::steady_clock::now();
  out.passMs = {{"RayTracedGBuffer (CPU)", std::chrono::duration<double, std::milli>(t1 - t0).count()},
                {"RayTracedShadows (CPU)", std::chrono::duration<double, std::milli>(t2 - t1).count()}};
  return out;
}

std::vector<std::uint8_t> litSideMask(const Scene& scene, const GBuffer& g, std::size_t light) {
  const auto lights = makeGpuLights(scene.lights, g.origin);
  const sh::GpuLight& l = lights.at(light);
  std::vector<std::uint8_t> mask(g.pixelCount(), 0);
  for (std::size_t i = 0; i < mask.size(); ++i) {
    if (!g.hit(i)) continue;
    const glm::vec3 p(g.position[i]), n(g.normal[i]);
    const glm::vec3 L = std::uint32_t(l.position.w) == sh::kLightDirectional ? glm::vec3(l.position)
                                                                            : glm::normalize(glm::vec3(l.position) - p);
    mask[i] = glm::dot(n, L) > 0.0f ? 1 : 0;
  }
  return mask;
}

Image composeImage(const Scene& scene, const RenderedFrame& frame) {
  const GBuffer& g = frame.gbuffer;
  Image img(g.width, g.height);
  const auto lights = makeGpuLights(scene.lights, g.origin);
  std::vector<float> r(g.pixelCount()), gr(g.pixelCount()), b(g.pixelCount());
  for (std::size_t i = 0; i < g.pixelCount(); ++i) {
    // The lighting of compose.comp (gpu/shared/Compose.h), so the window shows what render writes.
    glm::vec3 c = sh::skyColor();
    if (g.hit(i)) {
      glm::vec3 e = sh::ambientLight();
      for (std::size_t l = 0; l < lights.size(); ++l)
        e += sh::lightIrradiance(lights[l], glm::vec3(g.position[i]), glm::vec3(g.normal[i]), frame.visibility[l][i]);
      c = sh::instanceAlbedo(int(g.normal[i].w)) * e;
    }
    r[i] = c.r;
    gr[i] = c.g;
    b[i] = c.b;
  }
  img.setChannel("R", std::move(r));
  img.setChannel("G", std::move(gr));
  img.setChannel("B", std::move(b));
  for (std::size_t l = 0; l < lights.size(); ++l) img.setChannel(lightChannelName(scene, l) + ".V", frame.visibility[l]);
  return img;
}

Image displayImage(const Image& linear) {
  Image out(linear.width(), linear.height());
  for (const char* c : {"R", "G", "B"}) {
    std::vector<float> v = linear.channel(c);
    for (float& x : v) x = 1.0f - std::exp(-std::max(x, 0.0f));
    out.setChannel(c, std::move(v));
  }
  return out;
}

ShadowImageError compareWithTruth(const Scene& scene, const RenderedFrame& test, const RenderedFrame& truth) {
  const GBuffer& a = test.gbuffer;
  const GBuffer& b = truth.gbuffer;
  if (a.width != b.width || a.height != b.height)
    throw Error(fmt::format("cannot compare a {}x{} frame with a {}x{} one", a.width, a.height, b.width, b.height));
  ShadowImageError e;
  std::vector<float> va, vb, pa, pb, ua, ub;
  for (std::size_t l = 0; l < scene.lights.size(); ++l) {
    const std::vector<std::uint8_t> lit = litSideMask(scene, b, l);
    for (std::size_t i = 0; i < b.pixelCount(); ++i) {
      if (!lit[i] || !a.hit(i) || a.normal[i].w != b.normal[i].w) continue;
      va.push_back(test.visibility[l][i]);
      vb.push_back(truth.visibility[l][i]);
      if (truth.visibility[l][i] > 0.02f && truth.visibility[l][i] < 0.98f) {
        pa.push_back(test.visibility[l][i]);
        pb.push_back(truth.visibility[l][i]);
      } else if (truth.visibility[l][i] < 0.02f) {
        ua.push_back(test.visibility[l][i]);
        ub.push_back(truth.visibility[l][i]);
      }
    }
  }
  if (va.empty()) throw Error("no pixel to compare: the frames see no lit surface in common");
  e.pixels = va.size();
  e.visibilityRmse = rmse(va, vb);
  e.visibilityMeanAbs = meanAbsDifference(va, vb);
  e.penumbraPixels = pa.size();
  e.penumbraRmse = pa.empty() ? 0.0 : rmse(pa, pb);
  e.umbraPixels = ua.size();
  e.umbraMeanAbs = ua.empty() ? 0.0 : meanAbsDifference(ua, ub);
  const Image ia = displayImage(composeImage(scene, test)), ib = displayImage(composeImage(scene, truth));
  auto srgb = [](const Image& img) {
    std::vector<glm::vec3> out(img.pixelCount());
    const auto &r = img.channel("R"), &g = img.channel("G"), &bl = img.channel("B");
    for (std::size_t i = 0; i < out.size(); ++i) out[i] = {linearToSrgb(r[i]), linearToSrgb(g[i]), linearToSrgb(bl[i])};
    return out;
  };
  e.flip = flip(srgb(ib), srgb(ia), a.width, a.height).mean;
  return e;
}

} // namespace rtsdf
