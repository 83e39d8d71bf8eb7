#version 450
#extension GL_GOOGLE_include_directive : require
// TaaPass: temporal accumulation of the per-light visibility (taaResolve in render/taa/TaaParams.h): the
// history is clamped into the current frame's 3x3 neighbourhood (no ghosting where shadows move) and
// blended with the current frame.
#include "render/taa/TaaParams.h"

layout(local_size_x = 8, local_size_y = 8) in;
layout(push_constant) uniform Push { TaaParams params; };
layout(std430, binding = kTaaBindingCurrent) readonly buffer Current { float current[]; };
layout(std430, binding = kTaaBindingHistory) buffer History { float history[]; }; // in: last output, out: this frame's

void main() {
  ivec2 px = ivec2(gl_GlobalInvocationID.xy);
  int w = params.image.x, h = params.image.y;
  if (px.x >= w || px.y >= h) return;
  uint pixels = uint(w * h);
  for (int l = 0; l < params.image.z; ++l) {
    uint base = uint(l) * pixels;
    float nmin = 1.0e30, nmax = -1.0e30;
    for (int dy = -1; dy <= 1; ++dy)
      for (int dx = -1; dx <= 1; ++dx) {
        ivec2 q = clamp(px + ivec2(dx, dy), ivec2(0), ivec2(w - 1, h - 1));
        float c = current[base + uint(q.y * w + q.x)];
        nmin = min(nmin, c);
        nmax = max(nmax, c);
      }
    uint i = base + uint(px.y * w + px.x);
    history[i] = taaResolve(params, history[i], current[i], nmin, nmax);
  }
}
