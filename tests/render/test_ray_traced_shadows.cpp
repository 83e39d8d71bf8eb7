// The shadow ground truth: the closed-form penumbra of a sphere (checked against Monte Carlo integration and
// the planar limit) and the Embree ray tracer (checked against the closed form on data/scenes/analytic.json).
#include "TestUtil.h"
#include "render/AnalyticPenumbra.h"
#include "render/RayTracedShadows.h"
#include "scene/SceneGeometry.h"
#include "scene/SceneLoader.h"
#include "util/Error.h"

#include <glm/gtc/constants.hpp>
#include <gtest/gtest.h>
#include <tbb/task_arena.h>

#include <cmath>
#include <random>

using namespace rtsdf;

namespace {

constexpr double kPi = glm::pi<double>();

/// The published arccos form of the cap intersection (Tovchigrechko & Vakser 2001) for partial overlaps.
double capIntersectionArccos(double a, double b, double g) {
  const double c1 = (std::cos(g) - std::cos(a) * std::cos(b)) / (std::sin(a) * std::sin(b));
  const double c2 = (std::cos(b) - std::cos(g) * std::cos(a)) / (std::sin(g) * std::sin(a));
  const double c3 = (std::cos(a) - std::cos(g) * std::cos(b)) / (std::sin(g) * std::sin(b));
  return 2.0 * (kPi - std::acos(c1) - std::acos(c2) * std::cos(a) - std::acos(c3) * std::cos(b));
}

/// Area of the intersection of two discs (radii r1, r2, centres d apart) in the plane.
double planarLensArea(double r1, double r2, double d) {
  if (d >= r1 + r2) return 0.0;
  if (d <= std::abs(r1 - r2)) return kPi * std::min(r1, r2) * std::min(r1, r2);
  const double a1 = std::acos((d * d + r1 * r1 - r2 * r2) / (2.0 * d * r1));
  const double a2 = std::acos((d * d + r2 * r2 - r1 * r1) / (2.0 * d * r2));
  const double k = std::sqrt((-d + r1 + r2) * (d + r1 - r2) * (d - r1 + r2) * (d + r1 + r2));
  return r1 * r1 * a1 + r2 * r2 * a2 - 0.5 * k;
}

/// A configuration with cap radii (alpha: light, beta: sphere) and separation gamma: a unit sphere at the
/// origin seen from p, and the light's direction at angle gamma from the sphere's.
struct Config {
  double alpha, beta, gamma;
  glm::dvec3 p, toLight;
};

Config makeConfig(double alpha, double beta, double gamma) {
  const double d = 1.0 / std::sin(beta);
  const glm::dvec3 p(0.0, -d, 0.0);                                                           // sphere straight up
  const glm::dvec3 toLight(std::sin(gamma) * 0.6, std::cos(gamma), std::sin(gamma) * 0.8); // gamma from +y
  return {alpha, beta, gamma, p, toLight};
}

/// Monte Carlo estimate of the sun's visible fraction: uniform directions in the light's cone, each tested
/// against the sphere by ray-sphere intersection (independent of the closed form's cap geometry).
double monteCarloVisibility(const Config& c, int samples, std::uint64_t seed) {
  std::mt19937_64 rng(seed);
  std::uniform_real_distribution<double> uni(0.0, 1.0);
  const glm::dvec3 w = glm::normalize(c.toLight);
  const glm::dvec3 t = glm::normalize(glm::cross(std::abs(w.x) < 0.9 ? glm::dvec3(1, 0, 0) : glm::dvec3(0, 1, 0), w));
  const glm::dvec3 b = glm::cross(w, t);
  const glm::dvec3 center(0.0), oc = c.p - center;
  int visible = 0;
  for (int i = 0; i < samples; ++i) {
    const double cosTheta = 1.0 - uni(rng) * (1.0 - std::cos(c.alpha));
    const double sinTheta = std::sqrt(std::max(0.0, 1.0 - cosTheta * cosTheta));
    const double phi = 2.0 * kPi * uni(rng);
    const glm::dvec3 dir = sinTheta * std::cos(phi) * t + sinTheta * std::sin(phi) * b + cosTheta * w;
    // |oc + s dir|^2 = 1 with s > 0?
    const double bb = glm::dot(oc, dir), cc = glm::dot(oc, oc) - 1.0, disc = bb * bb - cc;
    const bool hit = disc >= 0.0 && -bb + std::sqrt(disc) > 0.0;
    visible += hit ? 0 : 1;
  }
  return double(visible) / samples;
}

} // namespace

// ---------------------------------------------------------------------------------------------------------
// Closed-form penumbra
// ---------------------------------------------------------------------------------------------------------

TEST(AnalyticPenumbra, MatchesMonteCarlo) {
  struct Case { double alpha, beta, gamma; const char* what; };
  const Case cases[] = {
      {0.10, 0.30, 0.45, "disjoint"},
      {0.10, 0.30, 0.40, "touching"},
      {0.10, 0.30, 0.36, "partial, light mostly visible"},
      {0.10, 0.30, 0.30, "partial, half"},
      {0.10, 0.30, 0.22, "partial, light mostly hidden"},
      {0.10, 0.30, 0.15, "light inside the sphere's cap"},
      {0.30, 0.10, 0.10, "sphere's cap inside the light"},
      {0.30, 0.10, 0.25, "partial, small occluder on the light's rim"},
      {0.30, 0.10, 0.35, "partial, small occluder outside the rim"},
      {0.50, 0.45, 0.20, "partial, similar caps"},
      {0.07, 0.52, 0.50, "partial, sun behind a near sphere (the analytic scene's penumbra)"},
      {1.20, 1.00, 1.50, "partial, large caps"},
      {0.70, 1.30, 0.90, "partial, very large occluder"},
  };
  const int n = 2'000'000;
  for (const Case& k : cases) {
    SCOPED_TRACE(k.what);
    const Config c = makeConfig(k.alpha, k.beta, k.gamma);
    const double exact = sunVisibilityPastSphere(c.p, c.toLight, c.alpha, glm::dvec3(0.0), 1.0);
    const double mc = monteCarloVisibility(c, n, 12345);
    const double sigma = std::sqrt(exact * (1.0 - exact) / n);
    EXPECT_NEAR(mc, exact, 5.0 * sigma + 1e-9) << "exact " << exact << " sigma " << sigma;
  }
  // The cases with a known answer.
  EXPECT_EQ(sunVisibilityPastSphere(makeConfig(0.1, 0.3, 0.45).p, makeConfig(0.1, 0.3, 0.45).toLight, 0.1,
                                    glm::dvec3(0.0), 1.0), 1.0);
  EXPECT_EQ(sunVisibilityPastSphere(makeConfig(0.1, 0.3, 0.15).p, makeConfig(0.1, 0.3, 0.15).toLight, 0.1,
                                    glm::dvec3(0.0), 1.0), 0.0);
  const Config inside = makeConfig(0.3, 0.1, 0.1);
  EXPECT_NEAR(sunVisibilityPastSphere(inside.p, inside.toLight, 0.3, glm::dvec3(0.0), 1.0),
              1.0 - (1.0 - std::cos(0.1)) / (1.0 - std::cos(0.3)), 1e-12);
}

TEST(AnalyticPenumbra, StableFormEqualsPublishedForm) {
  for (double a : {0.05, 0.2, 0.7, 1.4})
    for (double b : {0.03, 0.3, 0.9, 1.5})
      for (int k = 1; k < 20; ++k) {
        const double lo = std::abs(a - b), hi = a + b, g = lo + (hi - lo) * k / 20.0;
        EXPECT_NEAR(capIntersectionSolidAngle(a, b, g), capIntersectionArccos(a, b, g), 1e-10)
            << a << " " << b << " " << g;
      }
}

TEST(AnalyticPenumbra, ContinuousAndMonotonic) {
  for (const auto& [a, b] : {std::pair{0.07, 0.52}, std::pair{0.3, 0.1}, std::pair{0.2, 0.2}, std::pair{1.0, 1.3}}) {
    SCOPED_TRACE(testing::Message() << a << " " << b);
    // Across the case boundaries (containment, tangency) the value does not jump.
    for (double g0 : {std::abs(a - b), a + b}) {
      if (g0 <= 0.0) continue;
      const double below = capIntersectionSolidAngle(a, b, g0 - 1e-9), above = capIntersectionSolidAngle(a, b, g0 + 1e-9);
      EXPECT_NEAR(below, above, 1e-7);
    }
    // A fine sweep: the overlap shrinks as the caps separate, by no more than the largest possible slope allows
    // (the lens' boundary chord is at most 2 min(a, b) long, so |dOmega/dgamma| <= 2 sin(min)).
    const double h = 1e-4;
    double prev = capIntersectionSolidAngle(a, b, 0.0);
    for (double g = h; g < a + b + 0.05 && g <= kPi; g += h) {
      const double cur = capIntersectionSolidAngle(a, b, g);
      EXPECT_LE(cur, prev + 1e-13) << g;
      EXPECT_LE(prev - cur, 2.0 * std::sin(std::min(a, b)) * h * 1.0001 + 1e-13) << g;
      prev = cur;
    }
    EXPECT_EQ(prev, 0.0);
  }
}

TEST(AnalyticPenumbra, SmallAngleLimitIsThePlanarLens) {
  for (double scale : {1e-2, 1e-3, 1e-4, 1e-6}) {
    const double a = 2.0 * scale, b = 3.0 * scale;
    for (double g : {1.2 * scale, 2.5 * scale, 4.0 * scale, 4.9 * scale}) {
      const double planar = planarLensArea(a, b, g);
      const double spherical = capIntersectionSolidAngle(a, b, g);
      // The spherical correction is O(angle^2) relative; the evaluation stays accurate at tiny angles.
      EXPECT_NEAR(spherical / planar, 1.0, 30.0 * scale * scale + 1e-9) << scale << " " << g;
    }
  }
}

TEST(AnalyticPenumbra, SpecialCasesAndErrors) {
  const glm::dvec3 up(0, 1, 0), c(0, 1, 0);
  EXPECT_EQ(sunVisibilityPastSphere({0, 0, 0}, up, 0.1, c, 0.0), 1.0);      // no occluder
  EXPECT_EQ(sunVisibilityPastSphere({0, 0.9, 0}, up, 0.1, c, 0.5), 0.0);    // inside the sphere
  EXPECT_EQ(sunVisibilityPastSphere({0, 0, 0}, up, 0.0, c, 0.5), 0.0);      // hard, blocked
  EXPECT_EQ(sunVisibilityPastSphere({2, 0, 0}, up, 0.0, c, 0.5), 1.0);      // hard, clear
  EXPECT_EQ(sunVisibilityPastSphere({0, 0, 0}, -up, 0.3, c, 0.5), 1.0);     // light behind the point
  EXPECT_THROW(sunVisibilityPastSphere({0, 0, 0}, {0, 0, 0}, 0.1, c, 0.5), Error);
  EXPECT_THROW(sunVisibilityPastSphere({0, 0, 0}, up, -0.1, c, 0.5), Error);
  EXPECT_THROW(sunVisibilityPastSphere({0, 0, 0}, up, 2.0, c, 0.5), Error);
  EXPECT_THROW(sunVisibilityPastSphere({0, 0, 0}, up, 0.1, c, -1.0), Error);
  EXPECT_THROW(sunVisibilityPastSphere({NAN, 0, 0}, up, 0.1, c, 1.0), Error);
  EXPECT_THROW(capIntersectionSolidAngle(0.1, 0.1, -0.1), Error);
}

// ---------------------------------------------------------------------------------------------------------
// Ray tracer
// ---------------------------------------------------------------------------------------------------------

namespace {

struct AnalyticScene {
  Scene scene;
  SceneGeometry geometry;
  std::size_t floor = 0, ball = 0;  // instance indices
  glm::dvec3 center{0.0};           // the ball's centre
  double radius = 0.25;
};

AnalyticScene loadAnalytic() {
  AnalyticScene a;
  a.scene = loadScene(test::dataPath("scenes/analytic.json"));
  a.geometry = buildSceneGeometry(a.scene);
  for (std::size_t i = 0; i < a.scene.instances.size(); ++i) {
    if (a.scene.instances[i].name == "floor") a.floor = i;
    if (a.scene.instances[i].name == "ball") a.ball = i;
  }
  a.center = a.scene.instances[a.ball].transform.translation;
  return a;
}

std::string floorOnlyScene() {
  return R"({"meshes": {"floor": {"box": [1, 0.02, 1]}},
             "instances": [{"name": "floor", "mesh": "floor", "translate": [0, -0.01, 0]}],
             "lights": [{"type": "directional", "direction": [0.3, -1, 0.2], "angular_radius_deg": 10},
                        {"type": "sphere", "position": [0.2, 1, 0], "radius": 0.3},
                        {"type": "directional", "direction": [0, -1, 0]}],
             "camera": {"position": [0, 2, 0], "look_at": [0, 0, 0], "up": [0, 0, -1], "fov_deg": 50}})";
}

} // namespace

TEST(RayTracedShadows, NothingAboveMeansFullyLit) {
  const Scene s = parseScene(floorOnlyScene(), "floor.json");
  const SceneGeometry g = buildSceneGeometry(s);
  const GBuffer gb = traceGBuffer(g, makeCameraParams(s.camera, 48, 36));
  std::size_t hits = 0, misses = 0;
  for (std::size_t i = 0; i < gb.pixelCount(); ++i) {
    if (gb.hit(i)) {
      ++hits;
      EXPECT_NEAR(gb.position[i].y, 0.0f, 1e-5f);
      EXPECT_EQ(gb.normal[i], glm::vec4(0, 1, 0, 0));
    } else {
      ++misses;
      EXPECT_EQ(gb.position[i].w, -1.0f);
      EXPECT_EQ(gb.normal[i].w, -1.0f);
    }
  }
  EXPECT_GT(hits, gb.pixelCount() / 6);
  EXPECT_GT(misses, gb.pixelCount() / 10); // the floor fills only the middle of the view
  RayTracedShadowSettings settings;
  settings.samples = 64;
  const LightVisibility v = rayTracedVisibility(g, s.lights, gb, settings);
  ASSERT_EQ(v.size(), 3u);
  for (const auto& light : v) {
    ASSERT_EQ(light.size(), gb.pixelCount());
    for (float x : light) EXPECT_EQ(x, 1.0f);
  }
}

TEST(RayTracedShadows, GBufferOfTheAnalyticScene) {
  const AnalyticScene a = loadAnalytic();
  // The scene's camera sees only the floor (the penumbra); a wider one from further back sees the ball too.
  Camera wide = a.scene.camera;
  wide.position = glm::dvec3(1.0, 1.5, 0.95);
  wide.target = glm::dvec3(0.1, 0.0, 0.05);
  wide.verticalFov = glm::radians(25.0);
  std::size_t onFloor = 0, onBall = 0;
  for (const Camera& camera : {a.scene.camera, wide}) {
    const gpu::shared::CameraParams cam = makeCameraParams(camera, 96, 72);
    const GBuffer gb = traceGBuffer(a.geometry, cam);
    ASSERT_EQ(gb.width, 96);
    ASSERT_EQ(gb.height, 72);
    ASSERT_EQ(gb.position.size(), gb.pixelCount());
    ASSERT_EQ(gb.normal.size(), gb.pixelCount());
    const glm::vec3 eye(cam.position);
    // The icosphere's triangles lie between 0.99993 r (face centres, 6 subdivisions) and r (vertices).
    const double inner = a.radius * (1.0 - 7.2e-5) - 2e-6, outer = a.radius + 2e-6;
    for (int y = 0; y < gb.height; ++y)
      for (int x = 0; x < gb.width; ++x) {
        const std::size_t i = std::size_t(y) * gb.width + x;
        ASSERT_TRUE(gb.hit(i)); // the floor fills both views
        const glm::vec3 p(gb.position[i]), n(gb.normal[i]);
        const glm::vec3 dir = gpu::shared::cameraDirection(cam, x + 0.5f, y + 0.5f);
        EXPECT_NEAR(glm::length(p - (eye + gb.position[i].w * dir)), 0.0f, 1e-5f);
        EXPECT_NEAR(glm::length(n), 1.0f, 1e-5f);
        EXPECT_LT(glm::dot(n, dir), 0.0f); // faces the camera
        const int id = int(gb.normal[i].w);
        ASSERT_EQ(float(id), gb.normal[i].w);
        if (std::size_t(id) == a.floor) {
          ++onFloor;
          EXPECT_NEAR(p.y, 0.0f, 2e-6f);
          EXPECT_NEAR(n.y, 1.0f, 1e-6f);
        } else {
          ASSERT_EQ(std::size_t(id), a.ball);
          ++onBall;
          const double r = glm::length(glm::dvec3(p) - a.center);
          EXPECT_GE(r, inner);
          EXPECT_LE(r, outer);
          EXPECT_GT(glm::dot(glm::dvec3(n), (glm::dvec3(p) - a.center) / r), 0.999); // outward, near the radial
        }
      }
  }
  EXPECT_GT(onBall, 500u);
  EXPECT_GT(onFloor, 96u * 72u);

  // Rays that leave the scene are misses: a camera looking up from above the floor sees nothing.
  Camera sky;
  sky.position = glm::dvec3(0.0, 1.0, 0.0);
  sky.target = glm::dvec3(0.3, 2.0, 0.1);
  const GBuffer none = traceGBuffer(a.geometry, makeCameraParams(sky, 16, 12));
  for (std::size_t i = 0; i < none.pixelCount(); ++i) {
    EXPECT_EQ(none.position[i].w, -1.0f);
    EXPECT_EQ(none.normal[i].w, -1.0f);
  }
  const LightVisibility v = rayTracedVisibility(a.geometry, a.scene.lights, none);
  for (float x : v[0]) EXPECT_EQ(x, 1.0f);
}

namespace {

/// Compares ray-traced visibility of the floor pixels with the closed form for a light that sees the ball as
/// a cone of angular radius @a lightRadius(p) around @a toLight(p).
template <class ToLight, class LightRadius>
void compareWithClosedForm(const AnalyticScene& a, const GBuffer& gb, const std::vector<float>& vis, int samples,
                           double offset, ToLight toLight, LightRadius lightRadius, double minPenumbraFraction) {
  std::size_t penumbra = 0, lit = 0, dark = 0, floorPixels = 0;
  double sumAbs = 0.0, sumSigned = 0.0, sumVar = 0.0, sumTess = 0.0, worst = 0.0;
  for (std::size_t i = 0; i < gb.pixelCount(); ++i) {
    if (!gb.hit(i) || std::size_t(gb.normal[i].w) != a.floor) continue;
    ++floorPixels;
    const glm::dvec3 o = glm::dvec3(glm::vec3(gb.position[i]) + float(offset) * glm::vec3(gb.normal[i]));
    const glm::dvec3 l = toLight(o);
    const double lr = lightRadius(o);
    // The tessellated ball lies between the true sphere and one 0.0072 % smaller (6 subdivisions): its
    // visibility lies between theirs.
    const double vTrue = sunVisibilityPastSphere(o, l, lr, a.center, a.radius);
    const double vInner = sunVisibilityPastSphere(o, l, lr, a.center, a.radius * (1.0 - 7.2e-5));
    const double rt = vis[i];
    if (vTrue == 1.0) {
      ++lit;
      ASSERT_EQ(rt, 1.0f) << "pixel " << i;
    } else if (vInner == 0.0) {
      ++dark;
      ASSERT_EQ(rt, 0.0f) << "pixel " << i;
    } else {
      ++penumbra;
      const double exact = 0.5 * (vTrue + vInner), tess = 0.5 * (vInner - vTrue);
      const double sigma = std::sqrt(std::max(exact * (1.0 - exact), 1.0 / samples) / samples);
      const double diff = rt - exact, excess = std::max(0.0, std::abs(diff) - tess);
      // Binomial sigma bounds the noise of the stratified estimator from above.
      EXPECT_LE(excess, 4.5 * sigma) << "pixel " << i << " exact " << exact << " ray traced " << rt;
      worst = std::max(worst, excess / sigma);
      sumAbs += std::abs(diff);
      sumSigned += diff;
      sumVar += sigma * sigma;
      sumTess += tess;
    }
  }
  const double n = double(penumbra);
  std::printf("  floor pixels %zu: lit %zu, umbra %zu, penumbra %zu; penumbra mean |diff| %.5f, mean diff %.6f "
              "(3 sigma of the mean %.6f), worst %.2f binomial sigma\n",
              floorPixels, lit, dark, penumbra, sumAbs / n, sumSigned / n, 3.0 * std::sqrt(sumVar) / n, worst);
  EXPECT_GT(lit, 0u);
  EXPECT_GT(dark, 0u);
  EXPECT_GE(n, minPenumbraFraction * gb.pixelCount());
  EXPECT_LT(sumAbs / n, 0.01);                                     // mean |diff| over the penumbra
  EXPECT_LT(std::abs(sumSigned / n), 3.0 * std::sqrt(sumVar) / n + sumTess / n); // no bias
}

} // namespace

TEST(RayTracedShadows, SunPenumbraMatchesClosedForm) {
  const AnalyticScene a = loadAnalytic();
  ASSERT_EQ(a.scene.lights.size(), 1u);
  const Light& sun = a.scene.lights[0];
  const GBuffer gb = traceGBuffer(a.geometry, makeCameraParams(a.scene.camera, 96, 72));
  RayTracedShadowSettings settings;
  settings.samples = 1024;
  settings.normalOffset = 1e-4;
  const LightVisibility v = rayTracedVisibility(a.geometry, a.scene.lights, gb, settings);
  ASSERT_EQ(v.size(), 1u);
  const glm::dvec3 toSun = -glm::normalize(sun.direction);
  compareWithClosedForm(
      a, gb, v[0], settings.samples, settings.normalOffset, [&](const glm::dvec3&) { return toSun; },
      [&](const glm::dvec3&) { return sun.angularRadius; }, 0.25);
}

TEST(RayTracedShadows, SphereLightPenumbraMatchesClosedForm) {
  // A sphere light beyond the ball, roughly where the sun is: from any point it is a cone of half-angle
  // asin(R / d) around the direction to its centre, so the same closed form applies point by point.
  const AnalyticScene a = loadAnalytic();
  Light bulb;
  bulb.type = Light::Type::Sphere;
  bulb.position = a.center - 3.0 * glm::normalize(a.scene.lights[0].direction);
  bulb.radius = 0.2;
  const GBuffer gb = traceGBuffer(a.geometry, makeCameraParams(a.scene.camera, 96, 72));
  RayTracedShadowSettings settings;
  settings.samples = 1024;
  settings.normalOffset = 1e-4;
  const LightVisibility v = rayTracedVisibility(a.geometry, {bulb}, gb, settings);
  compareWithClosedForm(
      a, gb, v[0], settings.samples, settings.normalOffset, [&](const glm::dvec3& o) { return bulb.position - o; },
      [&](const glm::dvec3& o) { return std::asin(bulb.radius / glm::length(bulb.position - o)); }, 0.05);
}

TEST(RayTracedShadows, DeterministicForASeedAndAnyThreadCount) {
  const AnalyticScene a = loadAnalytic();
  const GBuffer gb = traceGBuffer(a.geometry, makeCameraParams(a.scene.camera, 64, 48));
  RayTracedShadowSettings settings;
  settings.samples = 32;
  settings.seed = 7;
  LightVisibility one, many, again;
  tbb::task_arena(1).execute([&] { one = rayTracedVisibility(a.geometry, a.scene.lights, gb, settings); });
  tbb::task_arena(4).execute([&] { many = rayTracedVisibility(a.geometry, a.scene.lights, gb, settings); });
  again = rayTracedVisibility(a.geometry, a.scene.lights, gb, settings);
  EXPECT_EQ(one, many);
  EXPECT_EQ(one, again);
  GBuffer gbOne;
  tbb::task_arena(1).execute([&] { gbOne = traceGBuffer(a.geometry, makeCameraParams(a.scene.camera, 64, 48)); });
  EXPECT_EQ(gbOne.position, gb.position);
  EXPECT_EQ(gbOne.normal, gb.normal);

  settings.seed = 8;
  const LightVisibility other = rayTracedVisibility(a.geometry, a.scene.lights, gb, settings);
  std::size_t differ = 0;
  for (std::size_t i = 0; i < gb.pixelCount(); ++i) differ += other[0][i] != one[0][i];
  EXPECT_GT(differ, 50u); // penumbra pixels see other samples
}

TEST(RayTracedShadows, HardLightsGiveZeroOrOne) {
  AnalyticScene a = loadAnalytic();
  std::vector<Light> lights = a.scene.lights;
  lights[0].angularRadius = 0.0;
  Light point;
  point.type = Light::Type::Sphere;
  point.position = a.center - 3.0 * glm::normalize(lights[0].direction); // its shadow falls where the sun's does
  lights.push_back(point);
  const GBuffer gb = traceGBuffer(a.geometry, makeCameraParams(a.scene.camera, 64, 48));
  RayTracedShadowSettings settings;
  settings.samples = 16;
  settings.normalOffset = 1e-4;
  const LightVisibility v = rayTracedVisibility(a.geometry, lights, gb, settings);
  const glm::dvec3 toSun = -glm::normalize(lights[0].direction);
  for (std::size_t l = 0; l < 2; ++l) {
    std::size_t zeros = 0, ones = 0;
    for (float x : v[l]) {
      EXPECT_TRUE(x == 0.0f || x == 1.0f) << x;
      zeros += x == 0.0f;
      ones += x == 1.0f;
    }
    EXPECT_GT(zeros, 100u);
    EXPECT_GT(ones, 100u);
  }
  // The hard sun agrees with the exact sphere except within the tessellation gap of the shadow's edge.
  std::size_t mismatches = 0, floorPixels = 0;
  for (std::size_t i = 0; i < gb.pixelCount(); ++i) {
    if (std::size_t(gb.normal[i].w) != a.floor) continue;
    ++floorPixels;
    const glm::dvec3 o(glm::vec3(gb.position[i]) + 1e-4f * glm::vec3(gb.normal[i]));
    mismatches += sunVisibilityPastSphere(o, toSun, 0.0, a.center, a.radius) != v[0][i];
  }
  EXPECT_LE(mismatches, 2u) << "of " << floorPixels;
}

TEST(RayTracedShadows, PointInsideASphereLightIsLit) {
  const AnalyticScene a = loadAnalytic();
  const GBuffer gb = traceGBuffer(a.geometry, makeCameraParams(a.scene.camera, 64, 48));
  // A sphere light resting half in the floor where the camera looks (in the sun's umbra): floor points inside
  // it are lit; points just outside see its lower half blocked by the floor and the ball may hide some more.
  Light bulb;
  bulb.type = Light::Type::Sphere;
  bulb.position = a.scene.camera.target;
  bulb.radius = 0.05;
  RayTracedShadowSettings settings;
  settings.samples = 64;
  const LightVisibility v = rayTracedVisibility(a.geometry, {bulb}, gb, settings);
  std::size_t inside = 0, outside = 0;
  for (std::size_t i = 0; i < gb.pixelCount(); ++i) {
    const double d = glm::length(glm::dvec3(glm::vec3(gb.position[i])) - bulb.position);
    if (d < bulb.radius) {
      ++inside;
      EXPECT_EQ(v[0][i], 1.0f) << d;
    } else if (d > 1.01 * bulb.radius && d < 2.0 * bulb.radius) {
      ++outside;
      EXPECT_LT(v[0][i], 0.75f) << d;
    }
  }
  EXPECT_GT(inside, 20u);
  EXPECT_GT(outside, 20u);
}

TEST(RayTracedShadows, BadInputThrows) {
  const Scene s = parseScene(floorOnlyScene(), "floor.json");
  const SceneGeometry g = buildSceneGeometry(s);
  const GBuffer gb = traceGBuffer(g, makeCameraParams(s.camera, 8, 6));
  RayTracedShadowSettings settings;
  settings.samples = 0;
  EXPECT_THROW(rayTracedVisibility(g, s.lights, gb, settings), Error);
  settings.samples = -3;
  EXPECT_THROW(rayTracedVisibility(g, s.lights, gb, settings), Error);
  settings.samples = 4;
  GBuffer wrong = gb;
  wrong.width = 9;
  EXPECT_THROW(rayTracedVisibility(g, s.lights, wrong, settings), Error);
  wrong = gb;
  wrong.normal.pop_back();
  EXPECT_THROW(rayTracedVisibility(g, s.lights, wrong, settings), Error);
  std::vector<Light> bad = s.lights;
  bad[0].angularRadius = 2.0;
  EXPECT_THROW(rayTracedVisibility(g, bad, gb, settings), Error);
  bad = s.lights;
  bad[1].radius = -1.0;
  EXPECT_THROW(rayTracedVisibility(g, bad, gb, settings), Error);
  EXPECT_NO_THROW(rayTracedVisibility(g, s.lights, gb, settings));
  EXPECT_TRUE(rayTracedVisibility(g, {}, gb, settings).empty());
}
