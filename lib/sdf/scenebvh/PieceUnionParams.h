// Shared by C++ and GLSL: the union of closed pieces that pass through each other (piece_union.glsl and its CPU
// copy, ClosedPieces.h). A point inside any closed piece is inside, whichever surface is nearest: the refinement
// asks where its own rule (the nearest triangle's side, or the rays' votes) says outside.
#ifndef RTSDF_SDF_SCENEBVH_PIECEUNIONPARAMS_H
#define RTSDF_SDF_SCENEBVH_PIECEUNIONPARAMS_H
#include "gpu/shared/Common.h"

RTSDF_SHARED_BEGIN

/// The piece of a leaf-ordered triangle that lies on no closed piece (its piece is open: it keeps the nearest rule).
const uint kOpenPiece = 0xFFFFFFFFu;

/// A closed piece of one instance whose world box overlaps another closed piece's (of any instance) this frame.
struct UnionPiece {
  vec4 lo; // xyz: the piece's box in its mesh's (object) space, w: uintBitsToFloat(instance slot)
  vec4 hi; // xyz: box max, w: uintBitsToFloat(piece index in its mesh, meshPieces)
};

/// The fixed directions (object space) of the parity rays: none has a zero component (no infinite slab in the box
/// tests), no two are near each other, and no simple ratio ties them to a grid or a tessellation's axes.
RTSDF_FN vec3 unionRayDirection(uint k) {
  if (k == 0u) return vec3(0.5773503f, 0.7071068f, 0.4082483f);
  if (k == 1u) return vec3(-0.6180340f, 0.3183099f, 0.7182818f);
  return vec3(0.2679492f, -0.8090170f, -0.5235988f);
}

/// Whether the ray o + t d, t > 0, crosses triangle abc (Moller-Trumbore, the edges included: a ray through an edge
/// or a vertex may count one crossing twice or not at all, which the majority of three rays outvotes).
RTSDF_FN bool rayCrossesTriangle(vec3 o, vec3 d, vec3 a, vec3 b, vec3 c) {
  RTSDF_PRECISE vec3 e1 = b - a, e2 = c - a;
  RTSDF_PRECISE vec3 pv = cross(d, e2);
  RTSDF_PRECISE float det = dot(e1, pv);
  if (det == 0.0f) return false;
  RTSDF_PRECISE float inv = 1.0f / det;
  RTSDF_PRECISE vec3 tv = o - a;
  RTSDF_PRECISE float u = dot(tv, pv) * inv;
  if (u < 0.0f || u > 1.0f) return false;
  RTSDF_PRECISE vec3 qv = cross(tv, e1);
  RTSDF_PRECISE float v = dot(d, qv) * inv;
  if (v < 0.0f || u + v > 1.0f) return false;
  return dot(e2, qv) * inv > 0.0f;
}

RTSDF_SHARED_END

#endif
