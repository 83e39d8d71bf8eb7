#version 450
#extension GL_GOOGLE_include_directive : require
// MaskRegionPass: one invocation. The coarse voxels this run of MaskCompactPass visits (MaskRegion): every voxel, or
// in a run over what changed (kMaskRegionOnly) the box holding the voxels whose decision can differ from the last
// run's: those whose coarse value changed (the coarse SDF's ChangedBox, where it was rebuilt this frame: a voxel keeps
// its band and so its freshness elsewhere), those a moving box comes within the band's reach of (the host's box: no
// other is near a moved instance, movedWithinReach), and the band voxels the last run left settling (the box it
// grew); elsewhere a band voxel is settled, not near a moved instance and not new, so it keeps its values, its bricks
// and its state. Then the indirect dispatch over the box, and this run's settling box reset (the last run's is the
// other parity's). A run over listed blocks (kMaskBlockList, after a scroll) has no box: its dispatch is the list's.
#include "sdf/mask/MaskParams.h"

layout(local_size_x = 1) in;
layout(push_constant) uniform Push { MaskRegionParams params; };
layout(std430, binding = kMaskRegionBindingChangedBox) readonly buffer Changed { uvec4 changedLo; uvec4 changedHi; };
layout(std430, binding = kMaskRegionBindingRegion) buffer Region { MaskRegion region; };

uvec4 lo = uvec4(0xFFFFFFFFu), hi = uvec4(0u);

void add(uvec4 addLo, uvec4 addHi) {
  if (addLo.x > addHi.x || addLo.y > addHi.y || addLo.z > addHi.z) return;
  lo = min(lo, addLo);
  hi = max(hi, addHi);
}

uint groupsFor(uint n) { return (n + uint(RTSDF_MASK_GROUP) - 1u) / uint(RTSDF_MASK_GROUP); }

void main() {
  uvec3 dims = uvec3(params.dims.xyz);
  uint last = (params.frame + 1u) & 1u, self = params.frame & 1u;
  if ((params.dims.w & kMaskBlockList) != 0) {
    // The run visits a list's blocks (mask_compact.comp): no box, and its dispatch is the list's.
  } else if ((params.dims.w & kMaskRegionOnly) == 0) {
    add(uvec4(0u), uvec4(dims - uvec3(1u), 0u));
  } else {
    if ((params.dims.w & kMaskCoarseRebuilt) != 0) add(changedLo, changedHi);
    if (all(lessThanEqual(params.nearLo.xyz, params.nearHi.xyz))) add(uvec4(params.nearLo), uvec4(params.nearHi));
    add(region.settlingLo[last], region.settlingHi[last]);
  }
  hi = min(hi, uvec4(dims - uvec3(1u), 0u));
  region.lo = lo;
  region.hi = hi;
  bool empty = lo.x > hi.x || lo.y > hi.y || lo.z > hi.z;
  uvec3 n = empty ? uvec3(0u) : hi.xyz - lo.xyz + uvec3(1u);
  region.groups = empty ? uvec4(0u, 1u, 1u, 0u) : uvec4(groupsFor(n.x), groupsFor(n.y), groupsFor(n.z), 0u);
  region.settlingLo[self] = uvec4(0xFFFFFFFFu);
  region.settlingHi[self] = uvec4(0u);
}
