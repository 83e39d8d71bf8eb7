// Shared by C++ and GLSL: the renderer's camera, lights and per-pass parameters, and the functions both
// the shaders and their CPU references evaluate (camera rays, the SDF soft-shadow march).
#ifndef RTSDF_GPU_SHARED_RENDER_H
#define RTSDF_GPU_SHARED_RENDER_H
#include "gpu/shared/RenderBindings.h"

RTSDF_SHARED_BEGIN

/// A pinhole camera, precomputed on the host: the ray through pixel (px, py) (pixel centres at +0.5, row 0
/// at the top of the image) has direction normalize(forward + sx * right + sy * up) with sx, sy in [-1, 1].
struct CameraParams {
  vec4 position; // xyz: eye
  vec4 forward;  // xyz: unit view direction
  vec4 right;    // xyz: unit right * tan(fov / 2) * aspect
  vec4 up;       // xyz: unit up * tan(fov / 2)
  ivec4 size;    // xy: image width, height in pixels
};

/// Light types.
const uint kLightDirectional = 0u;
const uint kLightSphere = 1u;

/// One light as the GPU sees it.
struct GpuLight {
  vec4 position; // xyz: unit direction towards the light (directional) or the sphere's centre; w: type
  vec4 color;    // rgb: colour * intensity
  vec4 size;     // x: tan(angular radius) (directional) or radius (sphere)
};

/// The ray direction through pixel coordinates (px, py) (not rounded: + 0.5 is the pixel centre).
RTSDF_FN vec3 cameraDirection(CameraParams c, float px, float py) {
  float sx = 2.0f * px / float(c.size.x) - 1.0f;
  float sy = 1.0f - 2.0f * py / float(c.size.y);
  return normalize(vec3(c.forward) + sx * vec3(c.right) + sy * vec3(c.up));
}

/// How the SDF soft shadow turns the march into a visibility.
const uint kPenumbraClassic = 0u;  // min over samples of h / (w t): the classic estimate (outer penumbra)
const uint kPenumbraImproved = 1u; // triangulated between consecutive samples (fewer banding artifacts)
const uint kPenumbraCentered = 2u; // marches on inside occluders (signed h), penumbra centred on the
                                   // geometric shadow boundary like a real area light's
const uint kPenumbraUmbra = 3u;    // lightSamples centred marches towards jittered points of the light's
                                   // disc, each over its share of the cone, averaged (the SDF-simulated umbra)

/// Push constants of sdf_shadow.comp (and its CPU reference).
struct SdfShadowParams {
  vec4 gridOriginH; // xyz: world corner of fine voxel (0,0,0), w: voxel size
  ivec4 gridDims;   // xyz: fine voxels per axis, w: number of lights
  ivec4 image;      // x: width, y: height, z: frame number (jitter), w: seed
  float epsilon;    // a sample closer than this is a hit; also where the march starts (scene units, >= one voxel)
  float bias;       // subtracted from every SDF sample: thin surfaces cannot leak light (scene units)
  float maxStep;    // longest step (against banding where h is large)
  float normalOffset; // the march starts this far off the surface along its normal
  uint maxSteps;
  uint penumbra;    // kPenumbra*
  float jitter;     // 0: start at epsilon; 1: start spread over [0.25, 1.25] epsilon per pixel and frame, probes
                    // and umbra samples turned per pixel and frame
  float minStep;    // shortest step: the march samples h at least this densely near occluders
  uint lateralProbes; // centred and umbra: SDF samples around the cone where the ray came closest to an
                      // occluder (tells a plate crossing the whole cone from an edge; 0: off)
  uint lightSamples;  // umbra: marches per pixel, light and frame (>= 1)
  float contactReach; // > 0: mark the pixels where something other than the receiver's own plane lies within
                      // this distance (sdfShadowMarch's contact) for ContactShadowPass; 0: the pass does not run
};

/// SdfShadowPass adds this to the visibility of the pixels (and lights) whose contact rays ContactShadowPass is to
/// trace; that pass takes it off again (the visibility itself is in [0, 1]).
const float kContactPending = 2.0f;

/// Push constants of contact_shadow.comp (ContactShadowPass) and its CPU reference (contactShadowsCpu).
struct ContactShadowParams {
  ivec4 image;        // x: width, y: height, z: frame number (the rays' turn), w: seed
  uint lights;        // number of lights
  uint rays;          // short rays per pixel and light (>= 1: the pass does not run with none)
  float distance;     // how far the rays reach from the surface (scene units): the SDF's first voxels
  float normalOffset; // the rays start this far off the surface along its normal (scene units)
  float jitter;       // 0: the same rays every frame; 1: the pattern turned per pixel and frame (TAA averages)
  float pad0, pad1, pad2;
};

/// Push constants of shadow_map.comp (build) and shadow_lookup.comp.
struct ShadowMapParams {
  vec4 center;      // xyz: scene centre, w: half extent covered by a directional light's map
  vec4 lightAxis;   // xyz: unit direction towards the light (directional), w: distance of the map plane
  vec4 right;       // xyz: unit, directional maps' u axis
  vec4 up;          // xyz: unit, directional maps' v axis
  ivec4 info;       // x: map resolution N, y: light index, z: light type, w: number of lights
  ivec4 image;      // x: width, y: height, z: PCF radius in texels
  float depthBias;  // in texels (scaled by the texel's world size)
  float pad0, pad1, pad2;
};

/// Push constants of taa.comp.
struct TaaParams {
  ivec4 image;      // x: width, y: height, z: number of lights, w: frame number (1: no history yet)
  float blend;      // weight of the new frame once the history is established
  uint clampHistory; // 1: clamp the history into the current frame's 3x3 neighbourhood range
  uint pad0, pad1;
};

/// Trilinear sample of a cell-centred dense field at world point p (clamped to the grid). The includer
/// defines one of: RTSDF_SDF_TEXTURE(uvw), a hardware-filtered 3D texture lookup at normalized coordinates
/// (texel centres at (i + 0.5) / dims, clamp to edge: the same field, to the filter's sub-texel precision);
/// or RTSDF_SDF_FETCH(linear index), a dense buffer filtered here (the CPU reference's path).
#if defined(RTSDF_SDF_TEXTURE)
RTSDF_FN float sampleSdf(SdfShadowParams s, vec3 p) {
  vec3 extent = vec3(s.gridDims.x, s.gridDims.y, s.gridDims.z) * s.gridOriginH.w;
  return RTSDF_SDF_TEXTURE((p - vec3(s.gridOriginH)) / extent);
}
#elif defined(RTSDF_SDF_FETCH)
RTSDF_FN float sampleSdf(SdfShadowParams s, vec3 p) {
  RTSDF_PRECISE vec3 g = (p - vec3(s.gridOriginH)) / s.gridOriginH.w - vec3(0.5f);
  vec3 hiC = vec3(s.gridDims.x - 1, s.gridDims.y - 1, s.gridDims.z - 1);
  g = clamp(g, vec3(0.0f), hiC);
  ivec3 i0 = ivec3(floor(g));
  ivec3 i1 = min(i0 + ivec3(1), ivec3(s.gridDims.x - 1, s.gridDims.y - 1, s.gridDims.z - 1));
  RTSDF_PRECISE vec3 f = g - vec3(i0);
  int sx = 1, sy = s.gridDims.x, sz = s.gridDims.x * s.gridDims.y;
  float c000 = RTSDF_SDF_FETCH(i0.x * sx + i0.y * sy + i0.z * sz), c100 = RTSDF_SDF_FETCH(i1.x * sx + i0.y * sy + i0.z * sz);
  float c010 = RTSDF_SDF_FETCH(i0.x * sx + i1.y * sy + i0.z * sz), c110 = RTSDF_SDF_FETCH(i1.x * sx + i1.y * sy + i0.z * sz);
  float c001 = RTSDF_SDF_FETCH(i0.x * sx + i0.y * sy + i1.z * sz), c101 = RTSDF_SDF_FETCH(i1.x * sx + i0.y * sy + i1.z * sz);
  float c011 = RTSDF_SDF_FETCH(i0.x * sx + i1.y * sy + i1.z * sz), c111 = RTSDF_SDF_FETCH(i1.x * sx + i1.y * sy + i1.z * sz);
  RTSDF_PRECISE float x00 = c000 + (c100 - c000) * f.x, x10 = c010 + (c110 - c010) * f.x;
  RTSDF_PRECISE float x01 = c001 + (c101 - c001) * f.x, x11 = c011 + (c111 - c011) * f.x;
  RTSDF_PRECISE float y0 = x00 + (x10 - x00) * f.y, y1 = x01 + (x11 - x01) * f.y;
  RTSDF_PRECISE float r = y0 + (y1 - y0) * f.z;
  return r;
}
#endif

/// Distance along o + t d (d unit) at which the ray leaves the box [lo, hi] (0 when it starts outside and
/// never enters: nothing to march through).
RTSDF_FN float exitDistance(vec3 o, vec3 d, vec3 lo, vec3 hi) {
  float tExit = 3.0e38f;
  float tEnter = 0.0f;
  for (int a = 0; a < 3; ++a) {
    if (d[a] != 0.0f) {
      RTSDF_PRECISE float t0 = (lo[a] - o[a]) / d[a];
      RTSDF_PRECISE float t1 = (hi[a] - o[a]) / d[a];
      tEnter = max(tEnter, min(t0, t1));
      tExit = min(tExit, max(t0, t1));
    } else if (o[a] < lo[a] || o[a] > hi[a]) {
      return 0.0f;
    }
  }
  return tExit > tEnter ? tExit : 0.0f;
}

/// Two unit vectors u, v with (u, v, L) orthonormal: the plane across the light's cone around unit L.
RTSDF_FN void perpendicularBasis(vec3 L, RTSDF_OUT(vec3) u, RTSDF_OUT(vec3) v) {
  u = normalize(cross(L, abs(L.x) < 0.9f ? vec3(1.0f, 0.0f, 0.0f) : vec3(0.0f, 1.0f, 0.0f)));
  v = cross(L, u);
}

/// Direction towards light l from point p, the distance to march (tMax) and the tangent of its half-angle.
/// Returns false when p is inside a sphere light (fully lit).
RTSDF_FN bool lightGeometry(GpuLight l, vec3 p, vec3 gridLo, vec3 gridHi, RTSDF_OUT(vec3) L, RTSDF_OUT(float) tMax,
                            RTSDF_OUT(float) w) {
  if (uint(l.position.w) == kLightDirectional) {
    L = vec3(l.position);
    tMax = exitDistance(p, L, gridLo, gridHi);
    w = l.size.x;
    return true;
  }
  vec3 toC = vec3(l.position) - p;
  float dist = length(toC);
  float radius = l.size.x;
  L = dist > 0.0f ? toC / dist : vec3(0.0f, 1.0f, 0.0f);
  if (dist <= radius) { tMax = 0.0f; w = 0.0f; return false; }
  tMax = min(dist - radius, exitDistance(p, L, gridLo, gridHi));
  w = radius / sqrt(max(dist * dist - radius * radius, 1.0e-20f));
  return true;
}

/// Direction k of @a count towards the disc of a light seen along unit L with a half-angle of tangent w: the
/// k-th of count equal-area rings at its mid radius, azimuths on a golden-ratio (sunflower) spiral turned by
/// turn01. The umbra estimate's marches and the contact rays spread over the light this way.
RTSDF_FN vec3 lightDiscDirection(vec3 L, float w, uint k, uint count, float turn01) {
  if (!(w > 0.0f)) return L;
  vec3 u, v;
  perpendicularBasis(L, u, v);
  float radius = w * sqrt((float(k) + 0.5f) / float(count));
  float phi = 6.28318531f * (float(k) * 0.618033989f + turn01);
  return normalize(L + radius * (cos(phi) * u + sin(phi) * v));
}

#if defined(RTSDF_SDF_TEXTURE) || defined(RTSDF_SDF_FETCH)

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
    RTSDF_PRECISE float h = sampleSdf(s, o + L * t) - s.bias;
    if (t <= s.contactReach && h + s.bias < s.normalOffset + t * ln - 0.125f * s.gridOriginH.w) contact = true;
    if (!centered && h < s.epsilon) return 0.0f; // the march hit a surface: umbra
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
    t += clamp(abs(h), s.minStep, s.maxStep);
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

#endif // RTSDF_SDF_TEXTURE || RTSDF_SDF_FETCH

/// The pixel's jitter in [0, 1) for frame @a frame: the shared PCG hash's top 24 bits (exact in a float, so the
/// same on both sides).
RTSDF_FN float pixelJitter(uint pixel, uint frame, uint seed) {
  return unitFloat(pcgHash(pixel * 1664525u + frame * 22695477u + seed * 2654435769u));
}

/// The turn of pixel @a pixel's contact-ray pattern (lightDiscDirection) in this frame: 0 without jitter, else a
/// number of its own per pixel and frame (the seed salted apart from the march's jitter).
RTSDF_FN float contactRayTurn(ContactShadowParams c, uint pixel) {
  return c.jitter * pixelJitter(pixel, uint(c.image.z), uint(c.image.w) ^ 0x5bd1e995u);
}

/// Cube-map face f (0..5: +x, -x, +y, -y, +z, -z) of direction d and its face coordinates in [-1, 1]:
/// axis a = f / 2 holds the sign, axes (a + 1) % 3 and (a + 2) % 3 the coordinates s and t.
RTSDF_FN uint cubeFace(vec3 d, RTSDF_OUT(float) s, RTSDF_OUT(float) t) {
  vec3 ad = abs(d);
  uint a = (ad.x >= ad.y && ad.x >= ad.z) ? 0u : (ad.y >= ad.z ? 1u : 2u);
  float m = ad[a];
  s = d[(a + 1u) % 3u] / m;
  t = d[(a + 2u) % 3u] / m;
  return 2u * a + (d[a] < 0.0f ? 1u : 0u);
}
RTSDF_FN vec3 cubeDirection(uint face, float s, float t) {
  uint a = face / 2u;
  vec3 d = vec3(0.0f);
  d[a] = (face & 1u) != 0u ? -1.0f : 1.0f;
  d[(a + 1u) % 3u] = s;
  d[(a + 2u) % 3u] = t;
  return normalize(d);
}

/// The shadow ray of texel (x, y) of face @a face of a light's map: origin and unit direction; depth along it.
RTSDF_FN void shadowMapRay(ShadowMapParams m, GpuLight l, uint x, uint y, uint face, RTSDF_OUT(vec3) o,
                           RTSDF_OUT(vec3) d) {
  float n = float(m.info.x);
  float s = (2.0f * (float(x) + 0.5f) / n - 1.0f);
  float t = (2.0f * (float(y) + 0.5f) / n - 1.0f);
  if (uint(l.position.w) == kLightDirectional) {
    o = vec3(m.center) + vec3(m.right) * (s * m.center.w) + vec3(m.up) * (t * m.center.w) +
        vec3(m.lightAxis) * m.lightAxis.w;
    d = -vec3(m.lightAxis);
  } else {
    o = vec3(l.position);
    d = cubeDirection(face, s, t);
  }
}

#ifdef RTSDF_DEPTH_FETCH
/// Percentage-closer filtered visibility of light l (map m, depths from RTSDF_DEPTH_FETCH(index within this
/// light's map)) at surface point p with unit normal n: the fraction of the (2r+1)^2 texels around p's texel
/// whose stored depth is not nearer to the light than p.
RTSDF_FN float shadowMapLookup(ShadowMapParams m, GpuLight l, vec3 p, vec3 n) {
  int res = m.info.x;
  int r = m.image.z;
  float depth;
  float texel;
  float cosTheta;
  uint face = 0u;
  float s, t;
  if (uint(l.position.w) == kLightDirectional) {
    texel = 2.0f * m.center.w / float(res);
    cosTheta = dot(n, vec3(m.lightAxis));
    vec3 q = p + n * texel;
    vec3 rel = q - vec3(m.center);
    s = dot(rel, vec3(m.right)) / m.center.w;
    t = dot(rel, vec3(m.up)) / m.center.w;
    depth = m.lightAxis.w - dot(rel, vec3(m.lightAxis));
  } else {
    vec3 toP = p - vec3(l.position);
    float dist = length(toP);
    if (dist <= l.size.x || dist == 0.0f) return 1.0f;
    texel = 2.0f * dist / float(res);
    cosTheta = dot(n, -toP / dist);
    vec3 q = p + n * texel;
    vec3 dq = q - vec3(l.position);
    depth = length(dq);
    face = cubeFace(dq, s, t);
  }
  if (abs(s) > 1.0f || abs(t) > 1.0f) return 1.0f; // outside the map: nothing there casts a shadow
  int cx = clamp(int(floor((s * 0.5f + 0.5f) * float(res))), 0, res - 1);
  int cy = clamp(int(floor((t * 0.5f + 0.5f) * float(res))), 0, res - 1);
  // Slope-scaled: a surface at a grazing angle to the light changes depth fast across one texel.
  float c = clamp(abs(cosTheta), 0.05f, 1.0f);
  float bias = m.depthBias * texel * (1.0f + min(sqrt(1.0f - c * c) / c, 8.0f));
  int lit = 0, total = 0;
  for (int dy = -r; dy <= r; ++dy)
    for (int dx = -r; dx <= r; ++dx) {
      int x = clamp(cx + dx, 0, res - 1), y = clamp(cy + dy, 0, res - 1);
      float stored = RTSDF_DEPTH_FETCH(int(face) * res * res + y * res + x);
      lit += stored >= depth - bias ? 1 : 0;
      ++total;
    }
  return float(lit) / float(total);
}
#endif // RTSDF_DEPTH_FETCH

/// One TAA step for one pixel: the history clamped into the current 3x3 neighbourhood's range [nmin, nmax],
/// then blended with the current value (the first frames average evenly until 1 / frame < blend).
RTSDF_FN float taaResolve(TaaParams p, float history, float current, float nmin, float nmax) {
  if (p.image.w <= 1) return current;
  float h = p.clampHistory != 0u ? clamp(history, nmin, nmax) : history;
  float a = max(p.blend, 1.0f / float(p.image.w));
  return h + (current - h) * a;
}

RTSDF_SHARED_END

#endif
