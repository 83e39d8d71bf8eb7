// Shared by C++ and GLSL: the sign of points whose nearest surface lies on an open mesh (open_winding.glsl and its CPU
// copy, OpenPieces.h). The exact field (reference/ExactSdf.h, WindingRegions.h) signs such a point by the mesh's
// generalized winding number w >= 1/2 where the nearest triangle's side may be wrong: where the nearest feature is on
// the rim (boundary, non-manifold or mis-oriented edges, pinched vertices), and, a point alone, throughout a mesh of
// several pieces. The refinement asks the same, per leaf-ordered triangle, and sums the solid angles over the
// instance's bottom level, far clusters by their dipoles (Barill et al. 2018), as the exact field's tree does.
#ifndef RTSDF_SDF_SCENEBVH_OPENPIECEPARAMS_H
#define RTSDF_SDF_SCENEBVH_OPENPIECEPARAMS_H
#include "gpu/shared/Common.h"

RTSDF_SHARED_BEGIN
#ifdef __cplusplus
using glm::atan;
#endif

/// Flags per leaf-ordered triangle (GpuSceneBvh::openFlags()). 0: its mesh is closed (the side of the nearest
/// triangle signs).
const uint kOpenMesh = 1u;           // its mesh is open: the winding number signs where the flags below say
const uint kOpenSeveralPieces = 2u;  // its mesh has several pieces: the winding number signs wherever it is nearest
const uint kOpenRimEdgeAB = 4u;      // edge AB on the rim; BC: << 1, CA: << 2
const uint kOpenRimVertexA = 32u;    // corner A on the rim; B: << 1, C: << 2

/// A bottom-level BVH node's cluster as a dipole (GpuSceneBvh::windingNodes(), one per BvhNode, same index).
struct WindingNode {
  vec4 centreRadius; // xyz: area-weighted centroid of its triangles (object space), w: radius of a ball about it
                     // holding them
  vec4 areaNormal;   // xyz: the sum of its triangles' vector areas (cross(b - a, c - a) / 2), w: 0
};

/// A cluster farther than this many radii from the point counts by its dipole (the exact field's tree: 2). Its
/// error reaches about 0.05 (inside the open teapot's body beside its handle's end, w = 0.52-0.55 summed as
/// 0.48-0.50; the exact field's tree errs by up to about 0.03 the same way there).
const float kWindingFarRatio = 2.0f;
/// Where the first walk's number lies within this of 1/2, the dipoles' error may have put it on the wrong side: a
/// second walk with farther clusters decides (errors about a quarter: (radius / distance)^2), for a few voxels only.
const float kWindingRecheckBand = 0.1f;
const float kWindingRecheckFarRatio = 4.0f;
/// Still within this of 1/2 after the second walk, the exact sum over every triangle of the mesh decides
/// (WindingExactPass, one work group per voxel), where the exact field's tree sums again with finer dipoles
/// (WindingNumberTree::inside, errors of a few 1e-3; a GPU sums every triangle faster than it walks that finely): the
/// second walk left 12 voxels of the open teapot at size M on the other side of the exact sum (2 voxels off), and a
/// third, finer walk in the refinement runs out of a CPU device's loop budget there.
const float kWindingExactBand = 0.05f;

/// The feature of triangle abc nearest to p (0: the face, 1-3: corner A, B, C, 4-6: edge AB, BC, CA), by the regions
/// the exact field's closestPointOnTriangle tells apart (Ericson 5.1.5), the same comparisons in the same order.
RTSDF_FN uint nearestFeature(vec3 p, vec3 a, vec3 b, vec3 c) {
  vec3 ab = b - a, ac = c - a, ap = p - a;
  float d1 = dot(ab, ap), d2 = dot(ac, ap);
  if (d1 <= 0.0f && d2 <= 0.0f) return 1u;
  vec3 bp = p - b;
  float d3 = dot(ab, bp), d4 = dot(ac, bp);
  float vc = d1 * d4 - d3 * d2;
  if (d3 >= 0.0f && d4 <= d3) return 2u;
  if (vc <= 0.0f && d1 >= 0.0f && d3 <= 0.0f) return 4u;
  vec3 cp = p - c;
  float d5 = dot(ab, cp), d6 = dot(ac, cp);
  float vb = d5 * d2 - d1 * d6;
  if (d6 >= 0.0f && d5 <= d6) return 3u;
  if (vb <= 0.0f && d2 >= 0.0f && d6 <= 0.0f) return 6u;
  float va = d3 * d6 - d5 * d4;
  if (va <= 0.0f && (d4 - d3) >= 0.0f && (d5 - d6) >= 0.0f) return 5u;
  if (!(va + vb + vc > 0.0f)) return 4u; // a degenerate triangle: an edge
  return 0u;
}

/// Whether the winding number signs a point whose nearest feature is @a feature (nearestFeature) of a triangle with
/// @a flags: the exact field's rule for a point alone (ExactDistanceField::usesWinding).
RTSDF_FN bool windingSigns(uint flags, uint feature) {
  if ((flags & kOpenMesh) == 0u) return false;
  if ((flags & kOpenSeveralPieces) != 0u) return true;
  if (feature >= 4u) return (flags & (kOpenRimEdgeAB << (feature - 4u))) != 0u;
  if (feature >= 1u) return (flags & (kOpenRimVertexA << (feature - 1u))) != 0u;
  return false;
}

/// The signed solid angle of triangle abc seen from p (Van Oosterom and Strackee 1983): positive on the side its
/// counter-clockwise normal points away from.
RTSDF_FN float triangleSolidAngle(vec3 p, vec3 a, vec3 b, vec3 c) {
  vec3 x = a - p, y = b - p, z = c - p;
  float lx = length(x), ly = length(y), lz = length(z);
  float det = dot(x, cross(y, z));
  float den = lx * ly * lz + dot(x, y) * lz + dot(y, z) * lx + dot(z, x) * ly;
  return 2.0f * atan(det, den);
}

/// The solid angle a cluster far from p subtends, by its dipole.
RTSDF_FN float dipoleSolidAngle(vec3 p, WindingNode n) {
  vec3 r = vec3(n.centreRadius) - p;
  float l = length(r);
  return dot(r, vec3(n.areaNormal)) / (l * l * l);
}

/// Whether the cluster of @a n lies far enough from p, @a ratio of its radii, to count by its dipole.
RTSDF_FN bool windingFar(vec3 p, WindingNode n, float ratio) {
  return length(vec3(n.centreRadius) - p) > ratio * n.centreRadius.w;
}

RTSDF_SHARED_END

#endif
