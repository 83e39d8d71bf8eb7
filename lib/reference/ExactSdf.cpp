#include "reference/ExactSdf.h"

#include "grid/VdbIO.h"
#include "reference/TriangleDistance.h"
#include "reference/VertexTriangles.h"
#include "reference/PieceUnion.h"
#include "reference/WindingNumber.h"
#include "reference/WindingRegions.h"
#include "util/Error.h"
#include "util/Progress.h"

#include <embree3/rtcore.h>
#include <fmt/format.h>
#include <spdlog/spdlog.h>
#include <tbb/enumerable_thread_specific.h>
#include <tbb/parallel_for.h>

#include <algorithm>
#include <atomic>
#include <chrono>
#include <cmath>
#include <cstring>
#include <numeric>

namespace rtsdf {

namespace {

/// Per-mesh data for distance and sign: corners, and the pseudo-normals of every feature.
struct MeshData {
  const WorldMesh* mesh = nullptr;
  std::vector<glm::vec3> faceNormal;   // per triangle
  std::vector<glm::vec3> edgeNormal;   // per triangle, 3 (AB, BC, CA): sum of the adjacent face normals
  std::vector<glm::vec3> vertexNormal; // per vertex: angle-weighted sum of face normals
  std::unique_ptr<WindingNumberTree> winding;
  bool useWinding = false;
  /// Open meshes under SignMethod::Auto: where the winding number is needed (the rest is signed by the
  /// pseudo-normal); null: everywhere.
  std::unique_ptr<WindingRegions> regions;
};

/// Face, edge (the sum of the faces on the edge) and vertex (angle-weighted) pseudo-normals. Per triangle and per
/// vertex in parallel, edges found through the triangles around their first vertex (no hash map).
void computePseudoNormals(MeshData& md, const VertexTriangles& around) {
  const WorldMesh& m = *md.mesh;
  const std::size_t nt = m.triangles.size();
  std::vector<glm::dvec3> face(nt);
  md.faceNormal.resize(nt);
  tbb::parallel_for(std::size_t(0), nt, [&](std::size_t t) {
    const glm::uvec3 tri = m.triangles[t];
    const glm::dvec3 a(m.positions[tri.x]), b(m.positions[tri.y]), c(m.positions[tri.z]);
    const glm::dvec3 n = glm::cross(b - a, c - a);
    const double len = glm::length(n);
    face[t] = len > 0.0 ? n / len : glm::dvec3(0.0);
    md.faceNormal[t] = glm::vec3(face[t]);
  });
  md.edgeNormal.resize(3 * nt);
  tbb::parallel_for(std::size_t(0), nt, [&](std::size_t t) {
    const glm::uvec3 tri = m.triangles[t];
    for (int k = 0; k < 3; ++k) {
      const unsigned a = tri[k], b = tri[(k + 1) % 3];
      glm::dvec3 sum(0.0);
      around.forEachAround(a, [&](unsigned u) {
        if (runs(m.triangles[u], a, b) != 0) sum += face[u];
      });
      md.edgeNormal[3 * t + k] = glm::vec3(sum);
    }
  });
  md.vertexNormal.resize(m.positions.size());
  tbb::parallel_for(std::size_t(0), m.positions.size(), [&](std::size_t v) {
    glm::dvec3 sum(0.0);
    around.forEachAround(unsigned(v), [&](unsigned u) {
      const glm::uvec3 tri = m.triangles[u];
      const int k = tri.x == v ? 0 : (tri.y == v ? 1 : 2);
      const glm::dvec3 p(m.positions[v]);
      const glm::dvec3 e1 = glm::dvec3(m.positions[tri[(k + 1) % 3]]) - p;
      const glm::dvec3 e2 = glm::dvec3(m.positions[tri[(k + 2) % 3]]) - p;
      const double l1 = glm::length(e1), l2 = glm::length(e2);
      if (l1 > 0.0 && l2 > 0.0) sum += std::acos(glm::clamp(glm::dot(e1, e2) / (l1 * l2), -1.0, 1.0)) * face[u];
    });
    md.vertexNormal[v] = glm::vec3(sum);
  });
}

[[noreturn]] void embreeFail(RTCDevice device, const char* what) {
  throw Error(fmt::format("Embree: {} failed (error {})", what, int(rtcGetDeviceError(device))));
}

} // namespace

struct ExactDistanceField::Impl {
  RTCDevice device = nullptr;
  RTCScene scene = nullptr;
  std::vector<MeshData> meshes;
  std::unique_ptr<PieceUnion> pieces; // closed pieces passing through each other
  SignMethod sign;

  ~Impl() {
    if (scene) rtcReleaseScene(scene);
    if (device) rtcReleaseDevice(device);
  }
};

namespace {

struct ClosestQuery {
  const ExactDistanceField::Impl* impl;
  ExactDistanceField::Hit* hit;
  bool found;
};

bool closestCallback(RTCPointQueryFunctionArguments* args) {
  auto* q = static_cast<ClosestQuery*>(args->userPtr);
  const WorldMesh& m = *q->impl->meshes[args->geomID].mesh;
  const glm::uvec3 tri = m.triangles[args->primID];
  const glm::vec3 p(args->query->x, args->query->y, args->query->z);
  TriangleFeature f;
  const glm::vec3 c = closestPointOnTriangle(p, m.positions[tri.x], m.positions[tri.y], m.positions[tri.z], f);
  const float d = glm::length(p - c);
  if (d < args->query->radius) {
    args->query->radius = d;
    *q->hit = {d, c, args->geomID, args->primID, int(f)};
    q->found = true;
    return true; // the query radius shrank
  }
  return false;
}

struct CollectQuery {
  const ExactDistanceField::Impl* impl;
  std::vector<std::uint64_t>* out;
};

bool collectCallback(RTCPointQueryFunctionArguments* args) {
  auto* q = static_cast<CollectQuery*>(args->userPtr);
  const WorldMesh& m = *q->impl->meshes[args->geomID].mesh;
  const glm::uvec3 tri = m.triangles[args->primID];
  const glm::vec3 p(args->query->x, args->query->y, args->query->z);
  const float d2 = distanceSquaredToTriangle(p, m.positions[tri.x], m.positions[tri.y], m.positions[tri.z]);
  if (d2 <= args->query->radius * args->query->radius)
    q->out->push_back((std::uint64_t(args->geomID) << 32) | args->primID);
  return false;
}

} // namespace

ExactDistanceField::ExactDistanceField(const SceneGeometry& geometry, SignMethod sign) : mImpl(new Impl) {
  Impl& im = *mImpl;
  im.sign = sign;
  if (geometry.triangleCount() == 0) throw Error("exact SDF: the scene has no triangles");
  im.device = rtcNewDevice(nullptr);
  if (!im.device) throw Error(fmt::format("Embree: cannot create a device (error {})", int(rtcGetDeviceError(nullptr))));
  im.scene = rtcNewScene(im.device);
  // Medium (Embree's default): a band fill asks a few queries per triangle, so a high-quality build (spatial splits)
  // cost more than it saved (0.16 s of 1.4 s on a 235k-triangle scan at 256).
  rtcSetSceneBuildQuality(im.scene, RTC_BUILD_QUALITY_MEDIUM);
  im.meshes.resize(geometry.meshes.size());
  std::vector<MeshPieces> pieces(geometry.meshes.size());
  for (std::size_t i = 0; i < geometry.meshes.size(); ++i) {
    const WorldMesh& wm = geometry.meshes[i];
    MeshData& md = im.meshes[i];
    md.mesh = &wm;
    const VertexTriangles around(wm.positions.size(), wm.triangles);
    computePseudoNormals(md, around);
    md.useWinding = sign == SignMethod::WindingNumber || (sign == SignMethod::Auto && !wm.watertight);
    pieces[i] = connectedPieces(wm, around);
    if (sign == SignMethod::Auto && !wm.watertight)
      md.regions = std::make_unique<WindingRegions>(wm, around, pieces[i]);
    if (md.useWinding) md.winding = std::make_unique<WindingNumberTree>(wm.positions, wm.triangles);

    RTCGeometry g = rtcNewGeometry(im.device, RTC_GEOMETRY_TYPE_TRIANGLE);
    // Embree-owned buffers are padded as Embree needs; copy the world positions into them.
    auto* v = static_cast<float*>(rtcSetNewGeometryBuffer(g, RTC_BUFFER_TYPE_VERTEX, 0, RTC_FORMAT_FLOAT3,
                                                          3 * sizeof(float), wm.positions.size()));
    auto* t = static_cast<unsigned*>(rtcSetNewGeometryBuffer(g, RTC_BUFFER_TYPE_INDEX, 0, RTC_FORMAT_UINT3,
                                                             3 * sizeof(unsigned), wm.triangles.size()));
    if (!v || !t) embreeFail(im.device, "allocating geometry buffers");
    std::memcpy(v, wm.positions.data(), wm.positions.size() * sizeof(glm::vec3));
    std::memcpy(t, wm.triangles.data(), wm.triangles.size() * sizeof(glm::uvec3));
    rtcCommitGeometry(g);
    rtcAttachGeometryByID(im.scene, g, unsigned(i));
    rtcReleaseGeometry(g);
    if (rtcGetDeviceError(im.device) != RTC_ERROR_NONE) embreeFail(im.device, "attaching geometry");
  }
  rtcCommitScene(im.scene);
  if (rtcGetDeviceError(im.device) != RTC_ERROR_NONE) embreeFail(im.device, "building the BVH");
  im.pieces = std::make_unique<PieceUnion>(geometry, std::move(pieces));
}

ExactDistanceField::~ExactDistanceField() = default;

bool ExactDistanceField::closest(const glm::vec3& p, float maxDistance, Hit& hit) const {
  RTCPointQuery query;
  query.x = p.x; query.y = p.y; query.z = p.z;
  query.radius = std::isfinite(maxDistance) ? maxDistance : std::numeric_limits<float>::max();
  query.time = 0.0f;
  RTCPointQueryContext context;
  rtcInitPointQueryContext(&context);
  ClosestQuery q{mImpl.get(), &hit, false};
  rtcPointQuery(mImpl->scene, &query, &context, closestCallback, &q);
  return q.found;
}

bool ExactDistanceField::intersect(const glm::vec3& origin, const glm::vec3& direction, float tmax, float& t,
                                   bool& front) const {
  RTCIntersectContext context;
  rtcInitIntersectContext(&context);
  RTCRayHit rh{};
  rh.ray.org_x = origin.x; rh.ray.org_y = origin.y; rh.ray.org_z = origin.z;
  rh.ray.dir_x = direction.x; rh.ray.dir_y = direction.y; rh.ray.dir_z = direction.z;
  rh.ray.tnear = 0.0f;
  rh.ray.tfar = tmax;
  rh.ray.mask = ~0u;
  rh.hit.geomID = RTC_INVALID_GEOMETRY_ID;
  rtcIntersect1(mImpl->scene, &context, &rh);
  if (rh.hit.geomID == RTC_INVALID_GEOMETRY_ID) return false;
  t = rh.ray.tfar;
  const WorldMesh& m = *mImpl->meshes[rh.hit.geomID].mesh;
  const glm::uvec3 tri = m.triangles[rh.hit.primID];
  const glm::vec3 n = glm::cross(m.positions[tri.y] - m.positions[tri.x], m.positions[tri.z] - m.positions[tri.x]);
  front = glm::dot(direction, n) < 0.0f;
  return true;
}

void ExactDistanceField::collect(const glm::vec3& p, float radius, std::vector<std::uint64_t>& out) const {
  RTCPointQuery query;
  query.x = p.x; query.y = p.y; query.z = p.z;
  query.radius = radius;
  query.time = 0.0f;
  RTCPointQueryContext context;
  rtcInitPointQueryContext(&context);
  CollectQuery q{mImpl.get(), &out};
  rtcPointQuery(mImpl->scene, &query, &context, collectCallback, &q);
}

bool ExactDistanceField::usesWinding(const glm::vec3& p, const Hit& hit) const {
  const MeshData& md = mImpl->meshes[hit.mesh];
  // A point alone: a mesh of several pieces would need the checks of a bake's cells and sub-blocks.
  return usesWindingInBand(p, hit) || (md.regions && md.regions->pieceCount() > 1);
}

bool ExactDistanceField::usesWindingInBand(const glm::vec3& p, const Hit& hit) const {
  const MeshData& md = mImpl->meshes[hit.mesh];
  return md.useWinding &&
         (!md.regions || md.regions->needed(p, hit.distance, hit.triangle, TriangleFeature(hit.feature)));
}

bool ExactDistanceField::inside(const glm::vec3& p, const Hit& hit) const {
  return inside(p, hit, usesWinding(p, hit));
}

bool ExactDistanceField::inside(const glm::vec3& p, const Hit& hit, bool winding) const {
  if (insideNearestPiece(p, hit, winding)) return true;
  // Parts that pass through each other are a union: outside the part it is nearest to, a point may still lie
  // inside another closed part whose surface is farther.
  return mImpl->pieces->insideAnotherPiece(p, hit.mesh, hit.triangle);
}

bool ExactDistanceField::insideNearestPiece(const glm::vec3& p, const Hit& hit) const {
  return insideNearestPiece(p, hit, usesWinding(p, hit));
}

bool ExactDistanceField::insideNearestPiece(const glm::vec3& p, const Hit& hit, bool winding) const {
  const MeshData& md = mImpl->meshes[hit.mesh];
  if (winding && md.winding) return md.winding->inside(glm::dvec3(p));
  const glm::uvec3 tri = md.mesh->triangles[hit.triangle];
  glm::vec3 n;
  switch (TriangleFeature(hit.feature)) {
  case TriangleFeature::Face: n = md.faceNormal[hit.triangle]; break;
  case TriangleFeature::VertexA: n = md.vertexNormal[tri.x]; break;
  case TriangleFeature::VertexB: n = md.vertexNormal[tri.y]; break;
  case TriangleFeature::VertexC: n = md.vertexNormal[tri.z]; break;
  case TriangleFeature::EdgeAB: n = md.edgeNormal[3 * hit.triangle + 0]; break;
  case TriangleFeature::EdgeBC: n = md.edgeNormal[3 * hit.triangle + 1]; break;
  case TriangleFeature::EdgeCA: n = md.edgeNormal[3 * hit.triangle + 2]; break;
  default: n = md.faceNormal[hit.triangle]; break;
  }
  return glm::dot(p - hit.point, n) < 0.0f;
}

bool ExactDistanceField::hasSeveralPieces(unsigned mesh) const {
  const MeshData& md = mImpl->meshes[mesh];
  return md.regions && md.regions->pieceCount() > 1;
}

bool ExactDistanceField::pseudoNormalHoldsNear(const glm::vec3& c, const Hit& hit) const {
  const MeshData& md = mImpl->meshes[hit.mesh];
  if (!md.winding) return true;
  const double side = insideNearestPiece(c, hit, false) ? 1.0 : 0.0;
  return std::fabs(md.winding->evaluate(glm::dvec3(c)) - side) < kPseudoNormalMargin;
}

bool ExactDistanceField::touchesRim(unsigned mesh, unsigned triangle) const {
  const MeshData& md = mImpl->meshes[mesh];
  return md.regions && md.regions->touchesRim(triangle);
}

bool ExactDistanceField::samePiece(const Hit& a, const Hit& b) const {
  if (a.mesh != b.mesh) return false;
  const MeshData& md = mImpl->meshes[a.mesh];
  return !md.regions || md.regions->pieceOf(a.triangle) == md.regions->pieceOf(b.triangle);
}

float ExactDistanceField::signedDistance(const glm::vec3& p) const {
  Hit hit;
  if (!closest(p, INFINITY, hit)) return INFINITY;
  return inside(p, hit) ? -hit.distance : hit.distance;
}

namespace {

struct Candidate {
  glm::vec3 a, b, c;
  unsigned mesh, triangle;
  glm::vec3 centre; ///< of the corners' bounding sphere: |p - centre| - radius bounds the distance from below
  float radius;
};

Candidate makeCandidate(const glm::vec3& a, const glm::vec3& b, const glm::vec3& c, unsigned mesh, unsigned tri) {
  const glm::vec3 centre = (a + b + c) / 3.0f;
  const float radius = std::sqrt(std::max({glm::dot(a - centre, a - centre), glm::dot(b - centre, b - centre),
                                           glm::dot(c - centre, c - centre)}));
  return {a, b, c, mesh, tri, centre, radius};
}

struct BlockScratch {
  std::vector<std::uint64_t> ids;
  std::vector<Candidate> cand;
  std::vector<float> dist, lower; // per candidate: distance and its lower bound from the last region's centre
  std::vector<int> all;  // every candidate's index
  std::vector<int> near; // candidates whose lower bound is within reach of the last region
  std::vector<int> sub;  // candidates of the current 4^3 sub-block
  std::vector<int> cell; // candidates of the current 2^3 cell
  /// The current sub-block's centre, its nearest candidate there, and whether the pseudo-normal holds near it
  /// (pseudoNormalHoldsNear: asked once, by the first voxel that would use it).
  glm::vec3 subCentre{0.0f};
  int subNearest = -1;
  enum class Region { Unknown, Holds, Fails } region = Region::Unknown;
  ExactDistanceField::Hit subHit;
  /// The current 2^3 cell has a rim within three of its radii (a triangle that touches one, of an open mesh of
  /// several pieces): the winding number may turn by a half within the cell.
  bool cellNearRim = false;
};

constexpr float kSlack = 1.0f + 1e-5f; // float rounding in the distance bounds

/// What filling any block of the band needs: the field, the voxels, the band and the culling radii.
struct BandFill {
  const ExactDistanceField& field;
  const GridSpec& spec;
  float band, h;
  float r8; ///< block centre to its farthest voxel centre
  float r4; ///< sub-block centre to its farthest voxel centre
  float r2; ///< 2^3 cell centre to its farthest voxel centre
};

/// Voxels of one block, added to the shared totals once per block rather than once per voxel.
struct BlockCounts {
  std::uint64_t active = 0, evaluated = 0, winding = 0;
};

/// Gathers into s.cand the triangles that can be nearest to a voxel of the 8^3 block centred at @a bc.
/// @return false when there are none: no voxel of the block is within the band.
bool gatherCandidates(const BandFill& f, const glm::vec3& bc, BlockScratch& s) {
  const ExactDistanceField::Impl& im = f.field.impl();
  ExactDistanceField::Hit hit;
  if (!f.field.closest(bc, f.band + f.r8, hit)) return false; // no voxel of this block is within the band
  // Any voxel's nearest triangle lies within D + 2 r8 of the block centre; only band + r8 matters.
  const float gather = std::min(hit.distance + 2.0f * f.r8, f.band + f.r8) * kSlack + 1e-6f * f.h;
  s.ids.clear();
  f.field.collect(bc, gather, s.ids);
  s.cand.clear();
  for (std::uint64_t id : s.ids) {
    const unsigned mi = unsigned(id >> 32), ti = unsigned(id & 0xffffffffu);
    const WorldMesh& m = *im.meshes[mi].mesh;
    const glm::uvec3 t = m.triangles[ti];
    s.cand.push_back(makeCandidate(m.positions[t.x], m.positions[t.y], m.positions[t.z], mi, ti));
  }
  return !s.cand.empty();
}

/// Whether the pseudo-normal holds at the current sub-block's centre (pseudoNormalHoldsNear). Away from the rims
/// (fillCell's nearRim) the winding number varies slowly: its offset from the pseudo-normal's side stays within the
/// margin across the sub-block.
bool pseudoNormalHoldsInSubBlock(const BandFill& f, BlockScratch& s) {
  const Candidate& c = s.cand[std::size_t(s.subNearest)];
  TriangleFeature feature;
  const glm::vec3 q = closestPointOnTriangle(s.subCentre, c.a, c.b, c.c, feature);
  s.subHit = {glm::length(s.subCentre - q), q, c.mesh, c.triangle, int(feature)};
  return f.field.pseudoNormalHoldsNear(s.subCentre, s.subHit);
}

/// Whether voxel @a p, nearest to @a hit, is signed by the winding number: usesWindingInBand says so, or its mesh is
/// open and of several pieces, and a rim is near its cell, or the pseudo-normal does not hold in its sub-block or
/// holds there on another piece.
bool needsWinding(const BandFill& f, BlockScratch& s, const glm::vec3& p, const ExactDistanceField::Hit& hit) {
  if (f.field.usesWindingInBand(p, hit)) return true;
  if (!f.field.hasSeveralPieces(hit.mesh)) return false;
  if (s.cellNearRim) return true;
  if (s.region == BlockScratch::Region::Unknown)
    s.region = pseudoNormalHoldsInSubBlock(f, s) ? BlockScratch::Region::Holds : BlockScratch::Region::Fails;
  return s.region == BlockScratch::Region::Fails || !f.field.samePiece(s.subHit, hit);
}

/// Voxel @a v of the block at @a o: its distance to the nearest of the cell's candidates s.cell and, within the band,
/// its sign.
void fillVoxel(const BandFill& f, const glm::ivec3& o, const glm::ivec3& v, BlockScratch& s, float* values, bool* act,
               BlockCounts& n) {
  const glm::vec3 p(f.spec.indexToWorld(glm::dvec3(v)));
  float best = INFINITY;
  int bi = -1;
  for (int i : s.cell) {
    // A triangle whose bounding sphere is farther than the best so far cannot be nearer (the margin covers the
    // rounding of both sides, so the nearest found is the same as without the test).
    const float lower = glm::length(p - s.cand[i].centre) - s.cand[i].radius;
    if (lower > 0.0f && lower * lower * 0.9999f > best) continue;
    const float d2 = distanceSquaredToTriangle(p, s.cand[i].a, s.cand[i].b, s.cand[i].c);
    if (d2 < best) { best = d2; bi = i; }
  }
  ++n.evaluated;
  const float d = std::sqrt(best);
  if (!(d <= f.band)) return; // inactive; its sign comes from signed flood fill
  const Candidate& c = s.cand[bi];
  TriangleFeature feature;
  const glm::vec3 q = closestPointOnTriangle(p, c.a, c.b, c.c, feature);
  const ExactDistanceField::Hit h2{d, q, c.mesh, c.triangle, int(feature)};
  const bool winding = needsWinding(f, s, p, h2);
  n.winding += winding;
  const bool in = f.field.inside(p, h2, winding);
  const int li = ((v.x - o.x) * 8 + (v.y - o.y)) * 8 + (v.z - o.z);
  values[li] = in ? -d : d;
  act[li] = true;
  ++n.active;
}

/// Into @a out, the candidates of @a from that can be nearest to a voxel within @a r of @a c: those within
/// min(D + 2r, band + r) of @a c, D being the distance from @a c to the nearest (which this returns). A voxel's
/// nearest triangle is within D + r of the voxel, so within D + 2r of c; only voxels in the band matter. The
/// candidates' bounding spheres cull first: exact distances only for those whose lower bound is within reach.
float keepNearest(const BandFill& f, const glm::vec3& c, float r, const std::vector<int>& from, BlockScratch& s,
                  std::vector<int>& out) {
  float upper = INFINITY;
  for (int i : from) {
    s.lower[i] = glm::length(c - s.cand[i].centre) - s.cand[i].radius;
    upper = std::min(upper, s.lower[i] + 2.0f * s.cand[i].radius);
  }
  const float reach = std::min(upper + 2.0f * r, f.band + r) * kSlack + 1e-6f * f.h;
  float d = INFINITY;
  s.near.clear();
  for (int i : from) {
    if (s.lower[i] > reach) continue;
    s.dist[i] = std::sqrt(distanceSquaredToTriangle(c, s.cand[i].a, s.cand[i].b, s.cand[i].c));
    d = std::min(d, s.dist[i]);
    s.near.push_back(i);
  }
  const float keep = std::min(d + 2.0f * r, f.band + r) * kSlack + 1e-6f * f.h;
  out.clear();
  for (int i : s.near)
    if (s.dist[i] <= keep) out.push_back(i);
  return d;
}

/// The 2^3 cell at @a co of the block at @a o: its voxels are filled from the sub-block's candidates that can be
/// nearest to one of them (with many small triangles, a 4^3 sub-block still holds hundreds: a finer cut pays).
void fillCell(const BandFill& f, const glm::ivec3& o, const glm::ivec3& co, BlockScratch& s, float* values, bool* act,
              BlockCounts& n) {
  if (co.x >= f.spec.dims.x || co.y >= f.spec.dims.y || co.z >= f.spec.dims.z) return;
  const glm::vec3 cc(f.spec.indexToWorld(glm::dvec3(co) + 0.5));
  if (keepNearest(f, cc, f.r2, s.sub, s, s.cell) > f.band + f.r2) return; // the whole cell is outside the band
  s.cellNearRim = std::any_of(s.cell.begin(), s.cell.end(), [&](int i) {
    return s.dist[i] < 3.0f * f.r2 && f.field.touchesRim(s.cand[std::size_t(i)].mesh, s.cand[std::size_t(i)].triangle);
  });
  const glm::ivec3 hi = glm::min(co + 2, f.spec.dims);
  for (int x = co.x; x < hi.x; ++x)
    for (int y = co.y; y < hi.y; ++y)
      for (int z = co.z; z < hi.z; ++z) fillVoxel(f, o, glm::ivec3(x, y, z), s, values, act, n);
}

/// Sub-block @a sb (4^3; bits 0, 1, 2 of @a sb step x, y, z) of the block at @a o: skipped when wholly outside the
/// band, else its voxels are filled from the block's candidates that can be nearest to one of them.
void fillSubBlock(const BandFill& f, const glm::ivec3& o, int sb, BlockScratch& s, float* values, bool* act,
                  BlockCounts& n) {
  const glm::ivec3 so = o + 4 * glm::ivec3(sb & 1, (sb >> 1) & 1, (sb >> 2) & 1);
  if (so.x >= f.spec.dims.x || so.y >= f.spec.dims.y || so.z >= f.spec.dims.z) return;
  const glm::vec3 sc(f.spec.indexToWorld(glm::dvec3(so) + 1.5));
  if (keepNearest(f, sc, f.r4, s.all, s, s.sub) > f.band + f.r4) return; // the whole sub-block is outside the band
  s.subCentre = sc;
  s.subNearest = *std::min_element(s.sub.begin(), s.sub.end(), [&](int a, int b) { return s.dist[a] < s.dist[b]; });
  s.region = BlockScratch::Region::Unknown;
  for (int c = 0; c < 8; ++c) fillCell(f, o, so + 2 * glm::ivec3(c & 1, (c >> 1) & 1, (c >> 2) & 1), s, values, act, n);
}

} // namespace

openvdb::FloatGrid::Ptr exactSignedDistance(const SceneGeometry& geometry, const GridSpec& spec,
                                            const ExactSdfOptions& options, ExactSdfStats* stats) {
  const auto start = std::chrono::steady_clock::now();
  requireWorldFrame(geometry, "exact SDF");
  if (std::isnan(options.band) || options.band <= 0.0)
    throw Error(fmt::format("exact SDF: band {} must be positive (or inf for the full domain)", options.band));
  ExactDistanceField field(geometry, options.sign);

  // Full domain: a band no voxel can lie outside of.
  const double domain = glm::length(spec.bounds().extent()) + glm::length(geometry.bounds.extent()) +
                        glm::length(spec.bounds().center() - geometry.bounds.center());
  const bool full = !(options.band < domain);
  const float band = float(full ? domain : options.band);
  const float h = float(spec.voxelSize);
  const float r8 = 3.5f * std::sqrt(3.0f) * h; // block centre to its farthest voxel centre
  const float r4 = 1.5f * std::sqrt(3.0f) * h; // sub-block centre to its farthest voxel centre
  const float r2 = 0.5f * std::sqrt(3.0f) * h; // cell centre to its farthest voxel centre
  const BandFill bandFill{field, spec, band, h, r8, r4, r2};

  tbb::enumerable_thread_specific<BlockScratch> scratch;
  std::atomic<std::uint64_t> active{0}, evaluated{0}, winding{0};
  const glm::ivec3 blocks = (spec.dims + 7) / 8;
  const std::uint64_t blockCount = std::uint64_t(blocks.x) * blocks.y * blocks.z;
  Progress progress("exact SDF", options.progress ? blockCount : 0);
  JobPoll poll(options.control, "exact SDF", blockCount);

  auto fill = [&](const glm::ivec3& o, float* values, bool* act) -> bool {
    if (poll.stopping()) return false;
    BlockScratch& s = scratch.local();
    progress.add();
    poll.done();
    if (!options.window.empty() && !options.window.isInside(openvdb::Coord(o.x, o.y, o.z))) return false;
    const glm::vec3 bc(spec.indexToWorld(glm::dvec3(o) + 3.5));
    if (!gatherCandidates(bandFill, bc, s)) return false;
    s.dist.resize(s.cand.size());
    s.lower.resize(s.cand.size());
    s.all.resize(s.cand.size());
    std::iota(s.all.begin(), s.all.end(), 0);
    BlockCounts n;
    for (int sb = 0; sb < 8; ++sb) fillSubBlock(bandFill, o, sb, s, values, act, n);
    active += n.active;
    evaluated += n.evaluated;
    winding += n.winding;
    return n.active > 0;
  };

  openvdb::FloatGrid::Ptr grid = buildLevelSet(spec, band, fill);
  progress.finish();
  if (poll.stopping()) throw Interrupted();
  if (stats) {
    stats->activeVoxels = active;
    stats->evaluatedVoxels = evaluated;
    stats->windingQueries = winding;
    stats->seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
  }
  return grid;
}

} // namespace rtsdf
