// Shared by C++ and GLSL: the bindings and push constants of contact_shadow.comp (ContactShadowPass) and its CPU
// copy (contactShadowsCpu). The pixels it traces are those SdfShadowPass marked (kContactPending).
#ifndef RTSDF_RENDER_CONTACTSHADOW_CONTACTSHADOWPARAMS_H
#define RTSDF_RENDER_CONTACTSHADOW_CONTACTSHADOWPARAMS_H
#include "bvh/GpuBvhLayout.h"
#include "render/sdfshadow/SdfShadowParams.h"

RTSDF_SHARED_BEGIN

/// contact_shadow.comp: the scene BVH (GpuBvhLayout.h's kBvhBinding*), then the G-buffer, the lights and the
/// visibility it lowers in place (light-major, as SdfShadowPass wrote it).
const uint kContactShadowBindingPositions = kBvhBindingCount + 0u;
const uint kContactShadowBindingNormals = kBvhBindingCount + 1u;
const uint kContactShadowBindingLights = kBvhBindingCount + 2u;
const uint kContactShadowBindingVisibility = kBvhBindingCount + 3u;
const uint kContactShadowBindingCount = kBvhBindingCount + 4u;

/// Push constants of contact_shadow.comp (ContactShadowPass) and its CPU copy (contactShadowsCpu).
struct ContactShadowParams {
  ivec4 image;        // x: width, y: height, z: frame number (the rays' turn), w: seed
  uint lights;        // number of lights
  uint rays;          // short rays per pixel and light (>= 1: the pass does not run with none)
  float distance;     // how far the rays reach from the surface (scene units): the SDF's first voxels (times the
                      // mark's reach scale, contactReachScale: a receiver in cascade level i reaches 2^i as far)
  float normalOffset; // the rays start this far off the surface along its normal (scene units)
  float jitter;       // 0: the same rays every frame; 1: the pattern turned per pixel and frame (TAA averages)
  float pad0, pad1, pad2;
};

/// The turn of pixel @a pixel's contact-ray pattern (lightDiscDirection) in this frame: 0 without jitter, else a
/// number of its own per pixel and frame (the seed salted apart from the march's jitter).
RTSDF_FN float contactRayTurn(ContactShadowParams c, uint pixel) {
  return c.jitter * pixelJitter(pixel, uint(c.image.z), uint(c.image.w) ^ 0x5bd1e995u);
}

RTSDF_SHARED_END

#endif
