#include "render/RayTracedShadows.h"

#include "render/AnalyticPenumbra.h"
#include "util/Bounds.h"
#include "util/Error.h"

#include <embree3/rtcore.h>
#include <fmt/format.h>
#include <glm/gtc/constants.hpp>
#include <tbb/blocked_range.h>
#include <tbb/parallel_for.h>

#include <cmath>
#include <cstring>
#include <limits>
#include <memory>

namespace rtsdf {
namespace {

using DevicePtr = std::unique_ptr<RTCDeviceTy, void (*)(RTCDevice)>;
using ScenePtr = std::unique_ptr<RTCSceneTy, void (*)(RTCScene)>;

/// Owns an Embree device and one scene of all world triangles: geomID = index in SceneGeometry::meshes.
class EmbreeScene {
public:
  explicit EmbreeScene(const SceneGeometry& geometry)
      : mDevice(rtcNewDevice(nullptr), rtcReleaseDevice), mScene(nullptr, rtcReleaseScene) {
    if (!mDevice)
      throw Error(fmt::format("Embree: cannot create a device (error {})", int(rtcGetDeviceError(nullptr))));
    mScene.reset(rtcNewScene(mDevice.get()));
    if (!mScene) fail("creating a scene");
    rtcSetSceneFlags(mScene.get(), RTC_SCENE_FLAG_ROBUST);
    rtcSetSceneBuildQuality(mScene.get(), RTC_BUILD_QUALITY_HIGH);
    for (std::size_t i = 0; i < geometry.meshes.size(); ++i) {
      const WorldMesh& wm = geometry.meshes[i];
      if (wm.triangles.empty() || wm.positions.empty()) continue;
      RTCGeometry g = rtcNewGeometry(mDevice.get(), RTC_GEOMETRY_TYPE_TRIANGLE);
      if (!g) fail("creating a triangle geometry");
      // Embree-owned buffers are padded as Embree needs; copy the world positions into them.
      auto* v = static_cast<float*>(rtcSetNewGeometryBuffer(g, RTC_BUFFER_TYPE_VERTEX, 0, RTC_FORMAT_FLOAT3,
                                                            3 * sizeof(float), wm.positions.size()));
      auto* t = static_cast<unsigned*>(rtcSetNewGeometryBuffer(g, RTC_BUFFER_TYPE_INDEX, 0, RTC_FORMAT_UINT3,
                                                               3 * sizeof(unsigned), wm.triangles.size()));
      if (!v || !t) {
        rtcReleaseGeometry(g);
        fail("allocating geometry buffers");
      }
      std::memcpy(v, wm.positions.data(), wm.positions.size() * sizeof(glm::vec3));
      std::memcpy(t, wm.triangles.data(), wm.triangles.size() * sizeof(glm::uvec3));
      rtcCommitGeometry(g);
      rtcAttachGeometryByID(mScene.get(), g, unsigned(i));
      rtcReleaseGeometry(g);
      if (rtcGetDeviceError(mDevice.get()) != RTC_ERROR_NONE) fail("attaching geometry");
    }
    rtcCommitScene(mScene.get());
    if (rtcGetDeviceError(mDevice.get()) != RTC_ERROR_NONE) fail("building the BVH");
  }

  RTCScene scene() const { return mScene.get(); }

private:
  [[noreturn]] void fail(const char* what) const {
    throw Error(fmt::format("Embree: {} failed (error {})", what, int(rtcGetDeviceError(mDevice.get()))));
  }

  DevicePtr mDevice; // declared first: released last
  ScenePtr mScene;
};

/// PCG hash (Jarzynski & Olano 2020): a well-mixed 32-bit hash of a 32-bit input.
std::uint32_t pcgHash(std::uint32_t v) {
  const std::uint32_t state = v * 747796405u + 2891336453u;
  const std::uint32_t word = ((state >> ((state >> 28u) + 4u)) ^ state) * 277803737u;
  return (word >> 22u) ^ word;
}

/// A uniform number in [0, 1) from the top 24 bits of @a h.
double unit(std::uint32_t h) { return double(h >> 8) * (1.0 / 16777216.0); }

/// An orthonormal frame around unit @a w (Duff et al. 2017).
void frame(const glm::dvec3& w, glm::dvec3& t, glm::dvec3& b) {
  const double sign = std::copysign(1.0, w.z);
  const double a = -1.0 / (sign + w.z);
  const double c = w.x * w.y * a;
  t = glm::dvec3(1.0 + sign * w.x * w.x * a, sign * c, -sign * w.x);
  b = glm::dvec3(c, sign + w.y * w.y * a, -w.y);
}

/// The direction at polar offset (1 - cos theta = @a omc) and azimuth @a phi around the frame (t, b, w).
glm::dvec3 coneDirection(const glm::dvec3& t, const glm::dvec3& b, const glm::dvec3& w, double omc, double phi) {
  const double cosTheta = 1.0 - omc;
  const double sinTheta = std::sqrt(std::max(0.0, omc * (2.0 - omc)));
  return sinTheta * std::cos(phi) * t + sinTheta * std::sin(phi) * b + cosTheta * w;
}

bool occluded(RTCScene scene, const glm::vec3& origin, const glm::vec3& direction, float tfar) {
  RTCIntersectContext context;
  rtcInitIntersectContext(&context);
  RTCRay ray{};
  ray.org_x = origin.x; ray.org_y = origin.y; ray.org_z = origin.z;
  ray.dir_x = direction.x; ray.dir_y = direction.y; ray.dir_z = direction.z;
  ray.tnear = 0.0f;
  ray.tfar = tfar;
  ray.mask = ~0u;
  ray.flags = 0;
  rtcOccluded1(scene, &context, &ray);
  return ray.tfar < 0.0f; // Embree sets tfar to -inf on a hit
}

void validateLight(const Light& l, std::size_t index) {
  const std::string name = fmt::format("light {} ('{}')", index, l.name);
  if (l.type == Light::Type::Directional) {
    if (!isFinite(l.direction) || !(glm::length(l.direction) > 0.0))
      throw Error(fmt::format("ray-traced shadows: {}: the direction must be finite and non-zero", name));
    if (!(l.angularRadius >= 0.0 && l.angularRadius < glm::half_pi<double>()))
      throw Error(fmt::format("ray-traced shadows: {}: angular radius {} rad is outside [0, pi/2)", name,
                              l.angularRadius));
  } else {
    if (!isFinite(l.position) || !std::isfinite(l.radius) || l.radius < 0.0)
      throw Error(fmt::format("ray-traced shadows: {}: the position must be finite and the radius (got {}) "
                              "finite and not negative", name, l.radius));
  }
}

} // namespace

GBuffer traceGBuffer(const SceneGeometry& geometry, const gpu::shared::CameraParams& camera) {
  requireWorldFrame(geometry, "ray-traced G-buffer");
  const int width = camera.size.x, height = camera.size.y;
  if (width < 1 || height < 1)
    throw Error(fmt::format("G-buffer: image size {}x{} must be positive", width, height));
  const EmbreeScene embree(geometry);
  GBuffer g;
  g.width = width;
  g.height = height;
  g.position.assign(g.pixelCount(), glm::vec4(0.0f, 0.0f, 0.0f, -1.0f));
  g.normal.assign(g.pixelCount(), glm::vec4(0.0f, 0.0f, 0.0f, -1.0f));
  const glm::vec3 origin(camera.position);

  tbb::parallel_for(tbb::blocked_range<int>(0, height), [&](const tbb::blocked_range<int>& rows) {
    RTCIntersectContext context;
    rtcInitIntersectContext(&context);
    context.flags = RTC_INTERSECT_CONTEXT_FLAG_COHERENT;
    for (int y = rows.begin(); y != rows.end(); ++y)
      for (int x = 0; x < width; ++x) {
        const glm::vec3 dir = gpu::shared::cameraDirection(camera, float(x) + 0.5f, float(y) + 0.5f);
        RTCRayHit rh{};
        rh.ray.org_x = origin.x; rh.ray.org_y = origin.y; rh.ray.org_z = origin.z;
        rh.ray.dir_x = dir.x; rh.ray.dir_y = dir.y; rh.ray.dir_z = dir.z;
        rh.ray.tnear = 0.0f;
        rh.ray.tfar = std::numeric_limits<float>::infinity();
        rh.ray.mask = ~0u;
        rh.hit.geomID = RTC_INVALID_GEOMETRY_ID;
        rh.hit.instID[0] = RTC_INVALID_GEOMETRY_ID;
        rtcIntersect1(embree.scene(), &context, &rh);
        if (rh.hit.geomID == RTC_INVALID_GEOMETRY_ID) continue;
        const std::size_t i = std::size_t(y) * std::size_t(width) + std::size_t(x);
        const float t = rh.ray.tfar;
        g.position[i] = glm::vec4(origin + t * dir, t);
        const WorldMesh& m = geometry.meshes[rh.hit.geomID];
        const glm::uvec3 tri = m.triangles[rh.hit.primID];
        const glm::dvec3 a(m.positions[tri.x]), b(m.positions[tri.y]), c(m.positions[tri.z]);
        glm::dvec3 n = glm::cross(b - a, c - a);
        const double len = glm::length(n);
        n = len > 0.0 ? n / len : -glm::dvec3(dir);
        if (glm::dot(n, glm::dvec3(dir)) > 0.0) n = -n;
        g.normal[i] = glm::vec4(glm::vec3(n), float(rh.hit.geomID));
      }
  });
  return g;
}

namespace {

/// A light's cone as seen from a point: axis w with frame (t, b), 1 - cos(half-angle) = omc; for sphere lights
/// also the sphere to clip rays at.
struct Cone {
  glm::dvec3 w, t, b;
  double omc = 0.0;
};

void checkTraceInputs(const std::vector<Light>& lights, const GBuffer& gbuffer, const RayTracedShadowSettings& s) {
  if (s.samples < 1) throw Error(fmt::format("ray-traced shadows: samples must be at least 1 (got {})", s.samples));
  if (!std::isfinite(s.normalOffset)) throw Error("ray-traced shadows: the normal offset must be finite");
  if (gbuffer.width < 0 || gbuffer.height < 0 || gbuffer.position.size() != gbuffer.pixelCount() ||
      gbuffer.normal.size() != gbuffer.pixelCount())
    throw Error(fmt::format("ray-traced shadows: the G-buffer is {}x{} but holds {} positions and {} normals",
                            gbuffer.width, gbuffer.height, gbuffer.position.size(), gbuffer.normal.size()));
  for (std::size_t l = 0; l < lights.size(); ++l) validateLight(lights[l], l);
}

/// The visibility of light @a l at pixel @a i from @a origin (offset off the surface point @a p); -1 when the
/// point is inside a sphere light (the visibility stays 1).
float pixelVisibility(RTCScene scene, const Light& light, const Cone& sun, std::size_t l, std::size_t i,
                      const glm::vec3& p, const glm::vec3& origin, const RayTracedShadowSettings& settings) {
  const float inf = std::numeric_limits<float>::infinity();
  Cone cone;
  glm::dvec3 toCenter(0.0);
  double radius = 0.0;
  if (light.type == Light::Type::Directional) {
    cone = sun;
  } else {
    toCenter = light.position - glm::dvec3(origin);
    const double d = glm::length(toCenter);
    if (glm::length(light.position - glm::dvec3(p)) <= light.radius || !(d > light.radius)) return -1.0f; // inside
    radius = light.radius;
    cone.w = toCenter / d;
    frame(cone.w, cone.t, cone.b);
    const double sinBeta = radius / d;
    cone.omc = sinBeta * sinBeta / (1.0 + std::sqrt(std::max(0.0, 1.0 - sinBeta * sinBeta)));
  }
  // The distance along unit @a dir to the light (infinite for the sun, the sphere's near side otherwise).
  auto lightDistance = [&](const glm::dvec3& dir) {
    if (light.type == Light::Type::Directional) return inf;
    const double b = glm::dot(dir, toCenter);
    const glm::dvec3 perp = toCenter - b * dir;
    return float(b - std::sqrt(std::max(0.0, radius * radius - glm::dot(perp, perp))));
  };
  if (cone.omc == 0.0) // a point of light: one exact ray
    return occluded(scene, origin, glm::vec3(cone.w), lightDistance(cone.w)) ? 0.0f : 1.0f;
  // Per-pixel stream: a randomised sunflower over the cone (equal-area rings, golden-ratio azimuths).
  const int n = settings.samples;
  const double goldenFraction = 0.5 * (std::sqrt(5.0) - 1.0);
  const std::uint32_t key = pcgHash(pcgHash(pcgHash(settings.seed) ^ std::uint32_t(l)) ^ std::uint32_t(i));
  const double rotation = unit(pcgHash(key ^ 0x68E31DA4u));
  int visible = 0;
  for (int s = 0; s < n; ++s) {
    const double u = (double(s) + unit(pcgHash(key + pcgHash(std::uint32_t(s))))) / double(n);
    double v = rotation + double(s) * goldenFraction;
    v -= std::floor(v);
    const glm::dvec3 dir = coneDirection(cone.t, cone.b, cone.w, u * cone.omc, glm::two_pi<double>() * v);
    if (!occluded(scene, origin, glm::vec3(dir), lightDistance(dir))) ++visible;
  }
  return float(double(visible) / double(n));
}

} // namespace

LightVisibility rayTracedVisibility(const SceneGeometry& geometry, const std::vector<Light>& lights,
                                    const GBuffer& gbuffer, const RayTracedShadowSettings& settings,
                                    const JobControl* control) {
  requireWorldFrame(geometry, "ray-traced shadows");
  checkTraceInputs(lights, gbuffer, settings);
  LightVisibility vis(lights.size(), std::vector<float>(gbuffer.pixelCount(), 1.0f));
  if (lights.empty() || gbuffer.pixelCount() == 0) return vis;

  const EmbreeScene embree(geometry);
  const float offset =
      float(settings.normalOffset >= 0.0 ? settings.normalOffset : 1e-4 * geometry.bounds.maxExtent());
  // Per light: the direction towards it and its cone (directional lights; sphere lights vary per pixel).
  std::vector<Cone> suns(lights.size());
  for (std::size_t l = 0; l < lights.size(); ++l)
    if (lights[l].type == Light::Type::Directional) {
      Cone& c = suns[l];
      c.w = -glm::normalize(lights[l].direction);
      frame(c.w, c.t, c.b);
      c.omc = oneMinusCos(lights[l].angularRadius);
    }
  JobPoll poll(control, "ray tracing", std::uint64_t(gbuffer.height));
  tbb::parallel_for(tbb::blocked_range<int>(0, gbuffer.height), [&](const tbb::blocked_range<int>& rows) {
    if (poll.stopping()) return;
    for (int y = rows.begin(); y != rows.end(); ++y, poll.done())
      for (int x = 0; x < gbuffer.width; ++x) {
        const std::size_t i = std::size_t(y) * std::size_t(gbuffer.width) + std::size_t(x);
        if (!gbuffer.hit(i)) continue;
        const glm::vec3 p(gbuffer.position[i]);
        const glm::vec3 origin = p + offset * glm::vec3(gbuffer.normal[i]);
        for (std::size_t l = 0; l < lights.size(); ++l) {
          const float v = pixelVisibility(embree.scene(), lights[l], suns[l], l, i, p, origin, settings);
          if (v >= 0.0f) vis[l][i] = v;
        }
      }
  });
  if (poll.stopping()) throw Interrupted();
  return vis;
}

} // namespace rtsdf
