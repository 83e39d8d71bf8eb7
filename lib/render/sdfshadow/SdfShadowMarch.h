// Shared by C++ and GLSL: the SDF soft-shadow march that SdfShadowPass's shaders and their CPU copy (sdfShadowsCpu)
// both run. The includer defines how the field is fetched first (RTSDF_SDF_TEXTURE, RTSDF_SDF_FETCH and/or
// RTSDF_SDF_LEVEL_SAMPLE, see sampleSdf).
#ifndef RTSDF_RENDER_SDFSHADOW_SDFSHADOWMARCH_H
#define RTSDF_RENDER_SDFSHADOW_SDFSHADOWMARCH_H
#include "render/sdfshadow/SdfShadowParams.h"

#if !defined(RTSDF_SDF_TEXTURE) && !defined(RTSDF_SDF_FETCH) && !defined(RTSDF_SDF_LEVEL_SAMPLE)
#error "define RTSDF_SDF_TEXTURE, RTSDF_SDF_FETCH or RTSDF_SDF_LEVEL_SAMPLE before including SdfShadowMarch.h"
#endif
#include "render/sdfshadow/DenseGridSampler.h"

RTSDF_SHARED_BEGIN

/// Trilinear sample of a cell-centred dense field at world point p (clamped to the grid). The includer
/// defines one of: RTSDF_SDF_TEXTURE(uvw), a hardware-filtered 3D texture lookup at normalized coordinates
/// (texel centres at (i + 0.5) / dims, clamp to edge: the same field, to the filter's sub-texel precision);
/// RTSDF_SDF_FETCH(linear index), a dense buffer filtered here (the CPU copy's path); and/or
/// RTSDF_SDF_LEVEL_SAMPLE(level, originH, dims, p) with RTSDF_CASCADE_LEVEL(level) (a CascadeFieldLevel): cascade
/// levels, each a dense buffer filtered by RTSDF_DEFINE_DENSE_SAMPLER's function, sampled where s.cascadeLevels > 0.
#if defined(RTSDF_SDF_TEXTURE)
RTSDF_FN float sampleSdf(SdfShadowParams s, vec3 p) {
  vec3 extent = vec3(s.gridDims.x, s.gridDims.y, s.gridDims.z) * s.gridOriginH.w;
  return RTSDF_SDF_TEXTURE((p - vec3(s.gridOriginH)) / extent);
}
#else
#if defined(RTSDF_SDF_FETCH)
#define RTSDF_ONE_BOX_FETCH(level, i) RTSDF_SDF_FETCH((i) + 0 * (level)) // one buffer: the level is -1
RTSDF_DEFINE_DENSE_SAMPLER(sampleDenseGrid, RTSDF_ONE_BOX_FETCH)
#endif

#if defined(RTSDF_SDF_LEVEL_SAMPLE)

/// The cascade levels' field at p (CascadeSamplerCpu's rule): the finest level whose box holds p more than one of
/// its fine voxels inside its faces (the whole stencil lies in it); within its blend band of that margin, mixed
/// linearly with the next coarser level (weight 0 on the margin itself); the outermost level, clamped, beyond.
/// @a scale: the fine voxel of the level sampled (the finer one in a blend band) over s.gridOriginH.w.
RTSDF_FN float sampleCascade(SdfShadowParams s, vec3 p, RTSDF_OUT(float) scale) {
  int n = int(s.cascadeLevels);
  for (int i = 0; i < n; ++i) {
    CascadeFieldLevel lv = RTSDF_CASCADE_LEVEL(i);
    float inside = insideLevel(lv, p);
    if (inside <= 0.0f) continue;
    scale = lv.originH.w / s.gridOriginH.w;
    float here = RTSDF_SDF_LEVEL_SAMPLE(i, lv.originH, lv.dims, p);
    if (i + 1 == n || inside >= lv.blend.x) return here;
    CascadeFieldLevel next = RTSDF_CASCADE_LEVEL(i + 1);
    float w = inside / lv.blend.x;
    return w * here + (1.0f - w) * RTSDF_SDF_LEVEL_SAMPLE(i + 1, next.originH, next.dims, p);
  }
  CascadeFieldLevel last = RTSDF_CASCADE_LEVEL(n - 1);
  scale = last.originH.w / s.gridOriginH.w;
  return RTSDF_SDF_LEVEL_SAMPLE(n - 1, last.originH, last.dims, p);
}
#endif

RTSDF_FN float sampleSdf(SdfShadowParams s, vec3 p) {
#if defined(RTSDF_SDF_LEVEL_SAMPLE)
  float scale;
  if (s.cascadeLevels > 0u) return sampleCascade(s, p, scale);
#endif
#if defined(RTSDF_SDF_FETCH)
  return sampleDenseGrid(-1, s.gridOriginH, s.gridDims, p);
#else
  return RTSDF_SDF_LEVEL_SAMPLE(0, s.gridOriginH, s.gridDims, p);
#endif
}
#endif

/// The field at p, and in @a scale how much coarser than s.gridOriginH.w the field there is: the fine voxel of the
/// cascade level sampled over it (1 for one box), by which the march scales its lengths at that sample.
RTSDF_FN float sampleSdfScaled(SdfShadowParams s, vec3 p, RTSDF_OUT(float) scale) {
#if defined(RTSDF_SDF_LEVEL_SAMPLE)
  if (s.cascadeLevels > 0u) return sampleCascade(s, p, scale);
#endif
  scale = 1.0f;
  return sampleSdf(s, p);
}

/// The march's parameters for a receiver at p: with cascade levels, its lengths (epsilon, bias, steps, the normal
/// offset, the contact reach and the voxel the gradient and thresholds use) are in level 0's voxels; scaled here to
/// the voxels of the finest level holding p (the field the march starts in is no finer, and a start under its voxel
/// would hit the receiver's own plane). One box: unchanged.
RTSDF_FN SdfShadowParams marchParamsAt(SdfShadowParams s, vec3 p) {
#if defined(RTSDF_SDF_LEVEL_SAMPLE)
  int n = int(s.cascadeLevels);
  for (int i = 0; i < n; ++i) {
    CascadeFieldLevel lv = RTSDF_CASCADE_LEVEL(i);
    float h = lv.originH.w;
    if (insideLevel(lv, p) > 0.0f || i + 1 == n) {
      float k = h / s.gridOriginH.w;
      s.epsilon *= k;
      s.bias *= k;
      s.maxStep *= k;
      s.minStep *= k;
      s.normalOffset *= k;
      s.contactReach *= k;
      s.gridOriginH.w = h;
      return s;
    }
  }
#endif
  return s;
}

/// The box the march runs in (a directional light's ray ends where it leaves it): the one grid's, or the outermost
/// cascade level's.
RTSDF_FN void marchBox(SdfShadowParams s, RTSDF_OUT(vec3) lo, RTSDF_OUT(vec3) hi) {
  vec4 originH = s.gridOriginH;
  ivec4 dims = s.gridDims;
#if defined(RTSDF_SDF_LEVEL_SAMPLE)
  if (s.cascadeLevels > 0u) {
    CascadeFieldLevel last = RTSDF_CASCADE_LEVEL(int(s.cascadeLevels) - 1);
    originH = last.originH;
    dims = last.dims;
  }
#endif
  lo = vec3(originH);
  hi = lo + vec3(dims.x, dims.y, dims.z) * originH.w;
}

/// The signed distance (in light-disc radii, negative: covered) from the cone's axis to the edge of the occluder
/// the centred march came closest to, from lateralProbes SDF samples around the cone there. The centre's own
/// signed distance cannot tell a plate from a rod: a plate the ray crosses is never deeper than half its
/// thickness, so it passes for a narrow edge and lets light through its umbra. Each probe sits on a ray
/// parallel to L at the cone's radius r = w t, moved along L onto the plane through the closest point parallel
/// to the surface the ray approached (normal: the SDF gradient at the last sample half a voxel clear of every
/// surface). For a straight edge at signed distance e r from the axis, the probe facing away from the occluder
/// is r (1 - e) outside it, so e = 1 - hMax / r: the same as the centre's h / r for thick occluders, but -1 or
/// less for a plate that covers the whole rim. Returns 1 (no opinion) where the approach grazes the surface
/// (the receiver's own plane) or moves away from it.
RTSDF_FN float lateralEdgeDistance(SdfShadowParams s, vec3 o, vec3 L, float tApproach, float tClose, float w,
                                   float rotation01) {
  RTSDF_PRECISE vec3 a = o + L * tApproach;
  float e = 0.25f * s.gridOriginH.w;
  RTSDF_PRECISE vec3 g = vec3(1.0f, -1.0f, -1.0f) * sampleSdf(s, a + e * vec3(1.0f, -1.0f, -1.0f)) +
                         vec3(-1.0f, -1.0f, 1.0f) * sampleSdf(s, a + e * vec3(-1.0f, -1.0f, 1.0f)) +
                         vec3(-1.0f, 1.0f, -1.0f) * sampleSdf(s, a + e * vec3(-1.0f, 1.0f, -1.0f)) +
                         vec3(1.0f, 1.0f, 1.0f) * sampleSdf(s, a + e * vec3(1.0f, 1.0f, 1.0f));
  float gl = length(g);
  if (!(gl > 0.0f)) return 1.0f;
  vec3 n = g / gl;
  float ln = dot(n, L);
  if (ln > -0.25f) return 1.0f; // grazing (the receiver's own plane) or moving away: no crossing to probe
  vec3 u, v;
  perpendicularBasis(L, u, v);
  RTSDF_PRECISE vec3 q = o + L * tClose;
  float r = w * tClose;
  float hMax = -3.0e38f;
  for (uint k = 0u; k < s.lateralProbes; ++k) {
    float phi = 6.28318531f * (float(k) + rotation01) / float(s.lateralProbes);
    vec3 d = cos(phi) * u + sin(phi) * v;
    RTSDF_PRECISE vec3 p = q + r * d - (r * dot(d, n) / ln) * L;
    hMax = max(hMax, sampleSdf(s, p) - s.bias);
  }
  return hMax / r - 1.0f;
}

/// The SDF soft-shadow march from surface point p (unit normal n) towards the light along unit L, up to
/// tMax, for a light whose half-angle has tangent w (0: a point or parallel light, hard shadows).
/// jitter01 in [0, 1) offsets the start. penumbra: kPenumbraClassic, Improved or Centered (the caller's
/// choice rather than s.penumbra, so that the umbra estimate needs no modified copy of the parameters).
/// Returns the light's visibility in [0, 1]. @a contact is set when a sample within s.contactReach of the start
/// finds the field short of the distance to the receiver's own plane by an eighth of a voxel: something else lies
/// that near (a crease, a contact, a gap under a wall), below what the field resolves, so ContactShadowPass is to
/// trace it. On a flat open receiver the filtered field is that distance exactly, so the test is quiet there; on a
/// convex one it is larger.
RTSDF_FN float sdfShadowMarch(SdfShadowParams s, uint penumbra, vec3 p, vec3 n, vec3 L, float tMax, float w,
                              float jitter01, RTSDF_INOUT(bool) contact) {
  RTSDF_PRECISE vec3 o = p + n * s.normalOffset;
  RTSDF_PRECISE float t = s.epsilon * (1.0f + s.jitter * (jitter01 - 0.75f));
  float ln = dot(L, n);
  float res = 1.0f;
  float ph = 1.0e30f;
  bool centered = penumbra == kPenumbraCentered;
  // Centred: the closest approach (smallest h / (w t)) and the last sample before it at least half a voxel off
  // every surface (0: none), where the gradient is the normal of the surface approached.
  float tClose = 0.0f, tApproach = 0.0f, tOutside = 0.0f;
  for (uint i = 0u; i < s.maxSteps; ++i) {
    if (t >= tMax) break;
    // k: the bias, hit threshold and steps follow the voxel of the field sampled here (cascade levels; 1: one box).
    float k;
    RTSDF_PRECISE float h = sampleSdfScaled(s, o + L * t, k) - s.bias * k;
    if (t <= s.contactReach && h + s.bias * k < s.normalOffset + t * ln - 0.125f * s.gridOriginH.w) contact = true;
    if (!centered && h < s.epsilon * k) return 0.0f; // the march hit a surface: umbra
    if (w > 0.0f) {
      if (penumbra == kPenumbraImproved) {
        // Aaltonen's triangulation: the nearest point to the occluder between this sample and the last.
        RTSDF_PRECISE float y = (h * h) / (2.0f * ph);
        RTSDF_PRECISE float dd = sqrt(max(h * h - y * y, 0.0f));
        res = min(res, dd / (w * max(t - y, 1.0e-6f)));
      } else {
        RTSDF_PRECISE float edge = h / (w * t);
        if (edge < res) { tClose = t; tApproach = tOutside; }
        if (h >= 0.5f * s.gridOriginH.w) tOutside = t;
        res = min(res, edge);
      }
    } else if (h < 0.0f) {
      res = -1.0f; // centred and a point-like light: inside an occluder means fully shadowed
    }
    if (centered && res <= -1.0f) break;
    ph = h;
    // Steps never shorter than minStep (progress inside occluders, centred mode; samples near the closest
    // approach to an occluder's edge), never longer than maxStep.
    t += clamp(abs(h), s.minStep * k, s.maxStep * k);
  }
  if (centered) {
    if (s.lateralProbes > 0u && res > -1.0f && res < 1.0f && tApproach > 0.0f)
      res = min(res, lateralEdgeDistance(s, o, L, tApproach, tClose, w, s.jitter * jitter01));
    RTSDF_PRECISE float r = clamp(res, -1.0f, 1.0f);
    // Visible fraction of a disc behind a straight occluder edge at signed distance r (in disc radii),
    // the cubic approximation of the circular segment area.
    return 0.25f * (1.0f + r) * (1.0f + r) * (2.0f - r);
  }
  RTSDF_PRECISE float r = clamp(res, 0.0f, 1.0f);
  return r * r * (3.0f - 2.0f * r);
}

/// The SDF-simulated umbra (kPenumbraUmbra): the mean of s.lightSamples centred marches (lateral probes
/// included) from p towards points of the light's disc (tangent of its half-angle w around unit L), each over a
/// cone of 1 / lightSamples of the disc's area. The points follow a sunflower (Vogel) spiral, one per
/// equal-area ring, turned by a second number from the pixel's jitter (TAA integrates the turns). Narrower
/// cones make each estimate's straight-edge assumption hold over a smaller patch of the disc, and a plate
/// that one cone crosses shadows its share whatever the others see.
/// @note Its own shader variants (RTSDF_SHADOW_UMBRA): a second march loop in the one shader slowed the single
///       march by a quarter on lavapipe even where it never ran.
RTSDF_FN float sdfShadowUmbra(SdfShadowParams s, vec3 p, vec3 n, vec3 L, float tMax, float w, float jitter01,
                              RTSDF_INOUT(bool) contact) {
  if (!(w > 0.0f)) return sdfShadowMarch(s, kPenumbraCentered, p, n, L, tMax, w, jitter01, contact);
  uint count = max(s.lightSamples, 1u);
  float wk = w / sqrt(float(count));
  // The spiral's turn: a second number from the pixel's jitter (24 bits, exact in a float and a uint).
  float turn = s.jitter * unitFloat(pcgHash(uint(jitter01 * 16777216.0f)));
  float sum = 0.0f;
  for (uint k = 0u; k < count; ++k)
    sum += sdfShadowMarch(s, kPenumbraCentered, p, n, lightDiscDirection(L, w, k, count, turn), tMax, wk, jitter01,
                          contact);
  return sum / float(count);
}

RTSDF_SHARED_END

#endif
