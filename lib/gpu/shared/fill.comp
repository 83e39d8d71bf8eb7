#version 450
#extension GL_GOOGLE_include_directive : require
// The smallest real pass: writes an affine ramp into a buffer. It proves the build path
// (glslc -> embedded SPIR-V -> compute pipeline) and the shared-header convention.
#include "gpu/shared/FillParams.h"

layout(local_size_x = 64) in;
layout(push_constant) uniform Push { FillParams params; };
layout(std430, binding = 0) writeonly buffer Out { uint values[]; };

void main() {
  uint i = gl_GlobalInvocationID.x;
  if (i < params.count) values[i] = i * params.scale + params.offset;
}
