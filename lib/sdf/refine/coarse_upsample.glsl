// The coarse SDF trilinearly upsampled at a fine voxel's centre: upsampleCoarse() (sdf/refine/RefineCpu.cpp), the
// same weights and order of lerps, bit for bit (nothing fused on either side). The includer declares the buffer
// coarse[] and a RefineParams named params (or RTSDF_UPSAMPLE_PARAMS) first.
#ifndef RTSDF_UPSAMPLE_PARAMS
#define RTSDF_UPSAMPLE_PARAMS params
#endif

// Coarse values of plane z at the cell's x and y corners: (x0 y0, x1 y0, x0 y1, x1 y1).
vec4 coarsePlane(ivec2 x01, ivec2 y01, int z) {
  ivec3 d = RTSDF_UPSAMPLE_PARAMS.coarseDims.xyz;
  int r0 = (z * d.y + y01.x) * d.x, r1 = (z * d.y + y01.y) * d.x;
  return vec4(coarse[r0 + x01.x], coarse[r0 + x01.y], coarse[r1 + x01.x], coarse[r1 + x01.y]);
}

// The cell of fine voxel v: its lower and upper coarse corners (clamped at the borders) and the weights.
void upsampleCell(ivec3 v, out ivec3 i0, out ivec3 i1, out vec3 t) {
  ivec3 cd = RTSDF_UPSAMPLE_PARAMS.coarseDims.xyz;
  precise vec3 p = RTSDF_UPSAMPLE_PARAMS.fineOriginH.xyz + (vec3(v) + 0.5) * RTSDF_UPSAMPLE_PARAMS.fineOriginH.w;
  precise vec3 g = (p - RTSDF_UPSAMPLE_PARAMS.coarseOriginInvH.xyz) * RTSDF_UPSAMPLE_PARAMS.coarseOriginInvH.w - 0.5;
  i0 = clamp(ivec3(floor(g)), ivec3(0), cd - 1);
  i1 = min(i0 + 1, cd - 1);
  t = clamp(g - vec3(i0), 0.0, 1.0);
}

// glm::mix's formula, x (1 - a) + y a, with nothing fused (precise): the host's resolve of the bricks and the CPU
// references get the same bits on any device. mix() and unqualified arithmetic leave a driver free to fuse
// multiply-adds, and NVIDIA's does: the last bit then differs from the host's in about a tenth of the voxels.
float lerpUnfused(float x, float y, float a) {
  precise float r = x * (1.0 - a) + y * a;
  return r;
}

// Trilinear interpolation between plane c0 (the cell's lower z) and c1 (its upper z).
float trilinear(vec4 c0, vec4 c1, vec3 t) {
  float c00 = lerpUnfused(c0.x, c0.y, t.x);
  float c10 = lerpUnfused(c0.z, c0.w, t.x);
  float c01 = lerpUnfused(c1.x, c1.y, t.x);
  float c11 = lerpUnfused(c1.z, c1.w, t.x);
  return lerpUnfused(lerpUnfused(c00, c10, t.y), lerpUnfused(c01, c11, t.y), t.z);
}

// The upsampled coarse SDF at fine voxel v (eight coarse loads).
float upsampleCoarseAt(ivec3 v) {
  ivec3 i0, i1;
  vec3 t;
  upsampleCell(v, i0, i1, t);
  ivec2 x01 = ivec2(i0.x, i1.x), y01 = ivec2(i0.y, i1.y);
  return trilinear(coarsePlane(x01, y01, i0.z), coarsePlane(x01, y01, i1.z), t);
}
