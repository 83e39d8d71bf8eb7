// Shared by C++ and GLSL: the trilinear filter of a cell-centred dense grid, as a function template by macro, so
// that the one box's field, each cascade level's buffer on the GPU (one function per binding: GLSL cannot pass a
// buffer) and the CPU copy's levels all run the same float operations. Include after the shared Common.h.
#ifndef RTSDF_RENDER_SDFSHADOW_DENSEGRIDSAMPLER_H
#define RTSDF_RENDER_SDFSHADOW_DENSEGRIDSAMPLER_H

/// Defines RTSDF_FN float NAME(int level, vec4 originH, ivec4 dims, vec3 p): the trilinear sample at world point p
/// of the grid with corner originH.xyz, voxel originH.w and dims.xyz voxels (x fastest; clamped to the grid), its
/// values fetched by FETCH(level, linear index).
#define RTSDF_DEFINE_DENSE_SAMPLER(NAME, FETCH)                                                                     \
  RTSDF_FN float NAME(int level, vec4 originH, ivec4 dims, vec3 p) {                                               \
    RTSDF_PRECISE vec3 g = (p - vec3(originH)) / originH.w - vec3(0.5f);                                          \
    vec3 hiC = vec3(dims.x - 1, dims.y - 1, dims.z - 1);                                                           \
    g = clamp(g, vec3(0.0f), hiC);                                                                                 \
    ivec3 i0 = ivec3(floor(g));                                                                                    \
    ivec3 i1 = min(i0 + ivec3(1), ivec3(dims.x - 1, dims.y - 1, dims.z - 1));                                      \
    RTSDF_PRECISE vec3 f = g - vec3(i0);                                                                           \
    int sx = 1, sy = dims.x, sz = dims.x * dims.y;                                                                 \
    float c000 = FETCH(level, i0.x * sx + i0.y * sy + i0.z * sz);                                                  \
    float c100 = FETCH(level, i1.x * sx + i0.y * sy + i0.z * sz);                                                  \
    float c010 = FETCH(level, i0.x * sx + i1.y * sy + i0.z * sz);                                                  \
    float c110 = FETCH(level, i1.x * sx + i1.y * sy + i0.z * sz);                                                  \
    float c001 = FETCH(level, i0.x * sx + i0.y * sy + i1.z * sz);                                                  \
    float c101 = FETCH(level, i1.x * sx + i0.y * sy + i1.z * sz);                                                  \
    float c011 = FETCH(level, i0.x * sx + i1.y * sy + i1.z * sz);                                                  \
    float c111 = FETCH(level, i1.x * sx + i1.y * sy + i1.z * sz);                                                  \
    RTSDF_PRECISE float x00 = c000 + (c100 - c000) * f.x, x10 = c010 + (c110 - c010) * f.x;                        \
    RTSDF_PRECISE float x01 = c001 + (c101 - c001) * f.x, x11 = c011 + (c111 - c011) * f.x;                        \
    RTSDF_PRECISE float y0 = x00 + (x10 - x00) * f.y, y1 = x01 + (x11 - x01) * f.y;                                \
    RTSDF_PRECISE float r = y0 + (y1 - y0) * f.z;                                                                  \
    return r;                                                                                                      \
  }

#endif
