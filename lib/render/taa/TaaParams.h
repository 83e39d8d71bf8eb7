// Shared by C++ and GLSL: the bindings and push constants of taa.comp (TaaPass) and the blend that it and its CPU
// copy (taaCpu) both evaluate.
#ifndef RTSDF_RENDER_TAA_TAAPARAMS_H
#define RTSDF_RENDER_TAA_TAAPARAMS_H
#include "gpu/shared/Common.h"

RTSDF_SHARED_BEGIN

/// taa.comp.
const uint kTaaBindingCurrent = 0u;
const uint kTaaBindingHistory = 1u; // in: the last output; out: this frame's
const uint kTaaBindingCount = 2u;

/// Push constants of taa.comp.
struct TaaParams {
  ivec4 image;      // x: width, y: height, z: number of lights, w: frame number (1: no history yet)
  float blend;      // weight of the new frame once the history is established
  uint clampHistory; // 1: clamp the history into the current frame's 3x3 neighbourhood range
  uint pad0, pad1;
};

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
