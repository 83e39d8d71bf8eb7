// Closed pieces that pass through each other are a union (sdf/scenebvh/PieceUnionParams.h): insideAnotherPiece
// tells whether a point lies inside any closed piece of this frame's overlap list other than a given one, by the
// parity of one ray's crossings with that piece's triangles (its instance's bottom level, triangles of other pieces
// skipped), the majority of three rays. Include after bvh_traverse.glsl, with RTSDF_PIECE_OF and RTSDF_UNION_PIECES
// defined as the bindings of GpuSceneBvh's pieceOf() and unionPieces() buffers.
#include "sdf/scenebvh/PieceUnionParams.h"

// Per leaf-ordered triangle: its closed piece in its mesh, or kOpenPiece.
layout(std430, binding = RTSDF_PIECE_OF) readonly buffer PieceOf { uint pieceOf[]; };
// x: how many closed pieces overlap another this frame (0: the union changes nothing, no ray is cast), then those.
layout(std430, binding = RTSDF_UNION_PIECES) readonly buffer UnionPieces {
  uvec4 unionHeader;
  UnionPiece unionPieces[];
};

// Whether the ray po + t d (object space of inst, t > 0) crosses piece 'piece' of inst's mesh an odd number of times.
bool oddCrossings(BvhInstance inst, vec3 po, vec3 d, uint piece) {
  vec3 invD = 1.0 / d;
  bool odd = false;
  uint stack[RTSDF_BVH_STACK];
  int sp = 0;
  stack[sp++] = inst.blasRoot;
  while (sp > 0 && RTSDF_LOOP_STEP) {
    BvhNode n = blasNodes[stack[--sp]];
    if (isinf(rayBox(po, invD, n.lo.xyz, n.hi.xyz, 0.0, 1.0 / 0.0))) continue;
    uint cnt = nodeCount(n);
    if (cnt == 0u) {
      stack[sp++] = nodeFirst(n) + 1u;
      stack[sp++] = nodeFirst(n);
      continue;
    }
    for (uint k = 0u; k < cnt && RTSDF_LOOP_STEP; ++k) {
      uint tri = nodeFirst(n) + k;
      if (pieceOf[tri] == piece &&
          rayCrossesTriangle(po, d, corners[3u * tri].xyz, corners[3u * tri + 1u].xyz, corners[3u * tri + 2u].xyz))
        odd = !odd;
    }
  }
  return odd;
}

// Whether world point p (the BVH's frame) lies inside a closed piece of the overlap list other than piece 'skipPiece'
// of the instance in slot 'skipSlot' (the nearest surface's, whose own rule said outside; kOpenPiece skips none).
bool insideAnotherPiece(vec3 p, uint skipSlot, uint skipPiece) {
  uint count = unionHeader.x;
  for (uint k = 0u; k < count && RTSDF_LOOP_STEP; ++k) {
    UnionPiece u = unionPieces[k];
    uint slot = floatBitsToUint(u.lo.w), piece = floatBitsToUint(u.hi.w);
    if (slot == skipSlot && piece == skipPiece) continue;
    BvhInstance inst = instances[slot];
    vec3 po = xformPoint(inst.worldToObject, p);
    if (any(lessThan(po, u.lo.xyz)) || any(greaterThan(po, u.hi.xyz))) continue;
    bool first = oddCrossings(inst, po, unionRayDirection(0u), piece);
    bool second = oddCrossings(inst, po, unionRayDirection(1u), piece);
    if (first == second ? first : oddCrossings(inst, po, unionRayDirection(2u), piece)) return true;
  }
  return false;
}
