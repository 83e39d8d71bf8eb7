#version 450
#extension GL_GOOGLE_include_directive : require
// BrickAllocPass: the brick pool's slots follow the ray mask, on the GPU. MaskCompactPass counts per brick the band
// voxels in view over it (needed: the count is not zero); then three dispatches of this shader (params.phase):
//   FREE   one invocation per brick: a slotted brick no longer needed pushes its slot on the free stack;
//   TAKE   one invocation per brick: a needed brick without a slot pops one (its history starts fresh: every
//          band voxel in it is new to the band, since a voxel in the band last frame kept its brick), or, with
//          the stack empty, counts an overflow and stays without;
//   SETTLE one invocation: the stack's top lowered by the slots taken.
// A slot is pushed and popped in different dispatches, so the stack needs no lock.
#include "sdf/mask/MaskParams.h"

layout(local_size_x = RTSDF_BRICK_GROUP) in;
layout(push_constant) uniform Push { BrickParams params; };
layout(std430, binding = kBrickBindingCounts) buffer Counts { uint counts[]; };
layout(std430, binding = kBrickBindingNeeded) readonly buffer Needed { uint needed[]; };
layout(std430, binding = kBrickBindingSlots) buffer Slots { uint slots[]; };
layout(std430, binding = kBrickBindingFree) buffer FreeStack { uint freeStack[]; };

void main() {
  if (params.phase == RTSDF_BRICK_SETTLE) { // one work group: its first invocation alone
    if (gl_GlobalInvocationID.x == 0u)
      counts[kBrickCountFreeTop] -= min(counts[kBrickCountAllocated], counts[kBrickCountFreeTop]);
    return;
  }
  uint b = gl_GlobalInvocationID.x;
  if (b >= params.bricks) return;
  bool isNeeded = needed[b] != 0u;
  uint slot = slots[b];
  if (params.phase == RTSDF_BRICK_FREE) {
    if (isNeeded) atomicAdd(counts[kBrickCountActive], 1u);
    if (slot != kNoBrick && !isNeeded) {
      freeStack[atomicAdd(counts[kBrickCountFreeTop], 1u)] = slot;
      slots[b] = kNoBrick;
    }
    return;
  }
  if (!isNeeded || slot != kNoBrick) return;
  uint top = counts[kBrickCountFreeTop]; // unchanged during this dispatch
  uint k = atomicAdd(counts[kBrickCountAllocated], 1u);
  if (k < top) slots[b] = freeStack[top - 1u - k];
  else atomicAdd(counts[kBrickCountOverflow], 1u);
}
