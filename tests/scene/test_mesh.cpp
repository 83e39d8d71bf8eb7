#include "TestUtil.h"
#include "scene/Mesh.h"
#include "scene/MeshIO.h"
#include "scene/MeshRepair.h"
#include "util/Error.h"

#include <gtest/gtest.h>

#include <limits>

using namespace rtsdf;
using rtsdf::test::TempDir;
using rtsdf::test::writeText;

namespace {

std::string errorOf(const std::function<void()>& f) {
  try {
    f();
  } catch (const Error& e) {
    return e.what();
  }
  return "";
}

} // namespace

TEST(Mesh, BoxIsClosedAndOutwardFacing) {
  Mesh box = makeBoxMesh({1.0f, 2.0f, 3.0f});
  const MeshReport r = validateMesh(box);
  EXPECT_EQ(r.triangles, 12u);
  EXPECT_TRUE(r.watertight());
  EXPECT_NEAR(test::signedVolume(box.positions, box.triangles), 6.0, 1e-9);
}

TEST(Mesh, BoxRejectsBadSize) {
  EXPECT_THROW(makeBoxMesh({1.0f, 0.0f, 1.0f}), Error);
  EXPECT_THROW(makeBoxMesh({1.0f, std::numeric_limits<float>::quiet_NaN(), 1.0f}), Error);
}

TEST(Mesh, NonFiniteCoordinateIsAnErrorNamingFileAndObject) {
  Mesh m = makeBoxMesh({1, 1, 1}, "crate");
  m.source = "crate.obj";
  m.positions[3].y = std::numeric_limits<float>::infinity();
  const std::string msg = errorOf([&] { validateMesh(m); });
  EXPECT_NE(msg.find("crate.obj"), std::string::npos) << msg;
  EXPECT_NE(msg.find("crate"), std::string::npos) << msg;
  EXPECT_NE(msg.find("non-finite"), std::string::npos) << msg;
}

TEST(Mesh, OutOfRangeIndexIsAnError) {
  Mesh m = makeBoxMesh({1, 1, 1});
  m.triangles[5].z = 8;
  const std::string msg = errorOf([&] { validateMesh(m); });
  EXPECT_NE(msg.find("vertex index 8"), std::string::npos) << msg;
}

TEST(Mesh, ZeroAreaTrianglesAreDroppedAndCounted) {
  Mesh m = makeBoxMesh({1, 1, 1});
  m.triangles.emplace_back(0, 0, 1);                 // repeated index
  m.positions.push_back({0.5f, 0.5f, 0.5f});
  m.positions.push_back({1.0f, 1.0f, 1.0f});
  m.positions.push_back({2.0f, 2.0f, 2.0f});
  m.triangles.emplace_back(8, 9, 10);                // collinear
  const MeshReport r = validateMesh(m);
  EXPECT_EQ(r.inputTriangles, 14u);
  EXPECT_EQ(r.degenerateDropped, 2u);
  EXPECT_EQ(r.triangles, 12u);
  EXPECT_EQ(m.positions.size(), 8u); // the unused collinear points are gone
  EXPECT_TRUE(r.watertight());
}

TEST(Mesh, EmptyAndAllDegenerateMeshesAreErrors) {
  Mesh empty;
  empty.source = "nothing.obj";
  EXPECT_NE(errorOf([&] { validateMesh(empty); }).find("empty mesh"), std::string::npos);
  Mesh flat;
  flat.source = "flat.obj";
  flat.positions = {{0, 0, 0}, {1, 0, 0}, {2, 0, 0}};
  flat.triangles = {{0, 1, 2}};
  const std::string msg = errorOf([&] { validateMesh(flat); });
  EXPECT_NE(msg.find("flat.obj"), std::string::npos) << msg;
  EXPECT_NE(msg.find("zero area"), std::string::npos) << msg;
}

TEST(Mesh, SplitVerticesAreWeldedSoTopologyIsSeen) {
  // A box whose triangles each own their three vertices (as OBJ files with per-face normals often are).
  const Mesh box = makeBoxMesh({1, 1, 1});
  Mesh split;
  for (const auto& t : box.triangles) {
    const unsigned b = unsigned(split.positions.size());
    for (int c = 0; c < 3; ++c) split.positions.push_back(box.positions[t[c]]);
    split.triangles.emplace_back(b, b + 1, b + 2);
  }
  const MeshReport r = validateMesh(split);
  EXPECT_EQ(r.weldedVertices, 36u - 8u);
  EXPECT_TRUE(r.watertight());
}

TEST(Mesh, TopologyFindsBoundaryAndMisorientedEdges) {
  Mesh m = makeBoxMesh({1, 1, 1});
  m.triangles.pop_back(); // open one face
  MeshReport r;
  analyzeTopology(m, r);
  EXPECT_EQ(r.boundaryEdges, 3u);
  EXPECT_FALSE(r.watertight());
  Mesh flipped = makeBoxMesh({1, 1, 1});
  std::swap(flipped.triangles[0].y, flipped.triangles[0].z);
  MeshReport f;
  analyzeTopology(flipped, f);
  EXPECT_EQ(f.boundaryEdges, 0u);
  EXPECT_GT(f.misorientedEdges, 0u);
  EXPECT_FALSE(f.watertight());
}

TEST(MeshIO, BundledBunnyIsClosedAndTeapotIsOpen) {
  Mesh bunny = loadMeshFile(test::dataPath("meshes/bunny.obj"));
  const MeshReport b = validateMesh(bunny);
  EXPECT_EQ(b.triangles, 3674u);
  EXPECT_EQ(bunny.positions.size(), 1839u);
  EXPECT_EQ(b.boundaryEdges, 0u);
  EXPECT_TRUE(b.watertight());
  EXPECT_GT(test::signedVolume(bunny.positions, bunny.triangles), 0.0);

  Mesh teapot = loadMeshFile(test::dataPath("meshes/teapot.obj"));
  const MeshReport t = validateMesh(teapot);
  EXPECT_EQ(t.inputTriangles, 992u);
  EXPECT_EQ(t.triangles, 992u);
  // As published the patch seams are split (528 boundary edges over 792 vertices); welding coincident
  // vertices closes the seams (529 vertices) but the teapot stays open: 64 boundary edges remain.
  EXPECT_EQ(teapot.positions.size(), 529u);
  EXPECT_EQ(t.boundaryEdges, 64u);
  EXPECT_EQ(t.nonManifoldEdges, 0u);
  EXPECT_FALSE(t.watertight());
}

TEST(MeshIO, ReadsObjPlyStlAndGltf) {
  TempDir dir;
  writeText(dir / "t.obj", "v 0 0 0\nv 1 0 0\nv 0 1 0\nv 0 0 1\nf 1 3 2\nf 1 2 4\nf 1 4 3\nf 2 3 4\n");
  writeText(dir / "t.ply", "ply\nformat ascii 1.0\nelement vertex 4\nproperty float x\nproperty float y\n"
                           "property float z\nelement face 4\nproperty list uchar int vertex_indices\nend_header\n"
                           "0 0 0\n1 0 0\n0 1 0\n0 0 1\n3 0 2 1\n3 0 1 3\n3 0 3 2\n3 1 2 3\n");
  std::string stl = "solid t\n";
  const float p[4][3] = {{0, 0, 0}, {1, 0, 0}, {0, 1, 0}, {0, 0, 1}};
  const int f[4][3] = {{0, 2, 1}, {0, 1, 3}, {0, 3, 2}, {1, 2, 3}};
  for (const auto& t : f) {
    stl += "facet normal 0 0 0\nouter loop\n";
    for (int c = 0; c < 3; ++c) stl += "vertex " + std::to_string(p[t[c]][0]) + " " + std::to_string(p[t[c]][1]) + " " +
                                       std::to_string(p[t[c]][2]) + "\n";
    stl += "endloop\nendfacet\n";
  }
  writeText(dir / "t.stl", stl + "endsolid t\n");
  // glTF 2.0 with the buffer inline as a base64 data URI: 4 float3 positions then 12 uint16 indices.
  std::string bytes;
  for (const auto& v : p) bytes.append(reinterpret_cast<const char*>(v), 12);
  for (const auto& t : f)
    for (int c = 0; c < 3; ++c) {
      const std::uint16_t i = std::uint16_t(t[c]);
      bytes.append(reinterpret_cast<const char*>(&i), 2);
    }
  static const char* b64 = "ABCDEFGHIJKLMNOPQRSTUVWXYZabcdefghijklmnopqrstuvwxyz0123456789+/";
  std::string enc;
  for (std::size_t i = 0; i < bytes.size(); i += 3) {
    std::uint32_t n = std::uint8_t(bytes[i]) << 16;
    if (i + 1 < bytes.size()) n |= std::uint8_t(bytes[i + 1]) << 8;
    if (i + 2 < bytes.size()) n |= std::uint8_t(bytes[i + 2]);
    enc += b64[(n >> 18) & 63];
    enc += b64[(n >> 12) & 63];
    enc += i + 1 < bytes.size() ? b64[(n >> 6) & 63] : '=';
    enc += i + 2 < bytes.size() ? b64[n & 63] : '=';
  }
  writeText(dir / "t.gltf",
            R"({"asset":{"version":"2.0"},"scene":0,"scenes":[{"nodes":[0]}],"nodes":[{"mesh":0}],)"
            R"("meshes":[{"primitives":[{"attributes":{"POSITION":0},"indices":1}]}],)"
            R"("buffers":[{"byteLength":72,"uri":"data:application/octet-stream;base64,)" + enc + R"("}],)"
            R"("bufferViews":[{"buffer":0,"byteOffset":0,"byteLength":48},{"buffer":0,"byteOffset":48,"byteLength":24}],)"
            R"("accessors":[{"bufferView":0,"componentType":5126,"count":4,"type":"VEC3","min":[0,0,0],"max":[1,1,1]},)"
            R"({"bufferView":1,"componentType":5123,"count":12,"type":"SCALAR"}]})");
  for (const char* name : {"t.obj", "t.ply", "t.stl", "t.gltf"}) {
    SCOPED_TRACE(name);
    Mesh m = loadMeshFile(dir / name);
    const MeshReport r = validateMesh(m);
    EXPECT_EQ(r.triangles, 4u);
    EXPECT_TRUE(r.watertight());
    EXPECT_NEAR(test::signedVolume(m.positions, m.triangles), 1.0 / 6.0, 1e-6);
  }
}

TEST(MeshIO, MissingAndMalformedFilesNameTheFile) {
  TempDir dir;
  EXPECT_NE(errorOf([&] { loadMeshFile(dir / "absent.obj"); }).find("absent.obj"), std::string::npos);
  writeText(dir / "junk.ply", "this is not a ply file\n");
  const std::string msg = errorOf([&] { loadMeshFile(dir / "junk.ply"); });
  EXPECT_NE(msg.find("junk.ply"), std::string::npos) << msg;
  writeText(dir / "lines.obj", "v 0 0 0\nv 1 0 0\nl 1 2\n");
  EXPECT_NE(errorOf([&] { loadMeshFile(dir / "lines.obj"); }).find("lines.obj"), std::string::npos);
}

// assimp's OBJ importer writes past its vertex array after one-vertex polylines: they are refused first, counted
// as its tokenizer counts them (statements end at \f and \0 too, a backslash continues one).
TEST(MeshIO, ObjOneVertexPolylinesAreRefusedBeforeAssimpReadsThem) {
  const std::string tri = "v 0 0 0\nv 1 0 0\nv 0 1 0\nf 1 2 3\n";
  const auto error = [](const std::string& text) {
    return errorOf([&] { loadMeshFromMemory(text, ".obj", "t.obj"); });
  };
  const char withNul[] = "v 0 0 0\nv 1 0 0\nv 0 1 0\n#\0l 3\nf 1 2 3\n";
  for (const std::string bad : {tri + "l 1\nl 1\nl 1 2 3\n", tri + "l 2\n", tri + "# note\fl 1\n",
                                std::string(withNul, sizeof(withNul) - 1), tri + "l 1/1\n", tri + "lx -1\n",
                                tri + "l 1 \\\n\n"}) {
    const std::string msg = error(bad);
    EXPECT_NE(msg.find("t.obj: line "), std::string::npos) << bad << ": " << msg;
    EXPECT_NE(msg.find("needs at least 2 vertices"), std::string::npos) << bad << ": " << msg;
  }
  EXPECT_NE(error(tri + "l 1\nl 1\nl 1 2 3\n").find("line 5"), std::string::npos);
  // Two vertices as assimp reads them (a backslash continues a statement; "+1" reads as 1, then 1 again), or
  // none (an empty 'l' is dropped), load.
  for (const std::string good :
       {tri + "l 1 2\n", tri + "l 1 \\\n 2\n", tri + "l +1\n", tri + "l\n", tri + "l 1 2 3\r\n"})
    EXPECT_EQ(error(good), "") << good;
}

TEST(MeshIO, ObjWithOutOfRangeIndexOrNanIsRejected) {
  TempDir dir;
  writeText(dir / "range.obj", "v 0 0 0\nv 1 0 0\nv 0 1 0\nf 1 2 9\n");
  const std::string a = errorOf([&] {
    Mesh m = loadMeshFile(dir / "range.obj");
    validateMesh(m);
  });
  EXPECT_NE(a.find("range.obj"), std::string::npos) << a;
  writeText(dir / "nan.obj", "v 0 0 0\nv nan 0 0\nv 0 1 0\nf 1 2 3\n");
  const std::string b = errorOf([&] {
    Mesh m = loadMeshFile(dir / "nan.obj");
    validateMesh(m);
  });
  EXPECT_NE(b.find("nan.obj"), std::string::npos) << b;
}

TEST(Mesh, SubdivisionKeepsTheSurfaceAndCuttingHolesOpensIt) {
  Mesh bunny = loadMeshFile(test::dataPath("meshes/bunny.obj"));
  validateMesh(bunny);
  Mesh fine = subdivideMesh(bunny, 2);
  const MeshReport f = validateMesh(fine);
  EXPECT_EQ(f.triangles, 16u * 3674u);
  EXPECT_EQ(f.weldedVertices, 0u); // one new vertex per edge, shared by both of its faces
  EXPECT_TRUE(f.watertight());
  EXPECT_NEAR(test::signedVolume(fine.positions, fine.triangles), test::signedVolume(bunny.positions, bunny.triangles),
              1e-4 * test::signedVolume(bunny.positions, bunny.triangles));
  EXPECT_THROW(subdivideMesh(bunny, 7), Error);

  Mesh holes = cutHoles(fine, 5, 0.3f);
  EXPECT_EQ(cutHoles(fine, 5, 0.3f).triangles, holes.triangles); // reproducible
  const MeshReport h = validateMesh(holes);
  EXPECT_LT(h.triangles, f.triangles);
  EXPECT_GT(h.triangles, f.triangles * 9 / 10); // small holes
  EXPECT_GT(h.boundaryEdges, 5u * 6u);         // five rims
  EXPECT_EQ(h.nonManifoldEdges, 0u);
  EXPECT_EQ(h.misorientedEdges, 0u);
}

namespace {

void reverseAll(Mesh& m) {
  for (glm::uvec3& t : m.triangles) std::swap(t.y, t.z);
}

/// Reverse every @a every-th triangle (a reproducible share of flipped faces).
void reverseEvery(Mesh& m, int every) {
  for (std::size_t t = 0; t < m.triangles.size(); t += std::size_t(every)) std::swap(m.triangles[t].y, m.triangles[t].z);
}

/// Whether @a a and @a b hold the same triangles with the same corner order (up to rotation), by position
/// (validation renumbers the vertices).
bool sameOrientation(const Mesh& a, const Mesh& b) {
  if (a.triangles.size() != b.triangles.size()) return false;
  for (std::size_t t = 0; t < a.triangles.size(); ++t) {
    const glm::vec3 x[3] = {a.positions[a.triangles[t].x], a.positions[a.triangles[t].y],
                            a.positions[a.triangles[t].z]};
    const glm::vec3 y[3] = {b.positions[b.triangles[t].x], b.positions[b.triangles[t].y],
                            b.positions[b.triangles[t].z]};
    bool rotated = false;
    for (int k = 0; k < 3; ++k) rotated = rotated || (x[0] == y[k] && x[1] == y[(k + 1) % 3] && x[2] == y[(k + 2) % 3]);
    if (!rotated) return false;
  }
  return true;
}

} // namespace

TEST(MeshRepair, InsideOutClosedMeshesAreTurnedOutward) {
  for (Mesh clean : {makeSphereMesh(1.0f, 3), test::makeTorus(1.0f, 0.3f, 32, 12), makeBoxMesh({1, 2, 3})}) {
    validateMesh(clean);
    Mesh m = clean;
    reverseAll(m);
    const MeshReport r = validateMesh(m);
    EXPECT_TRUE(r.watertight()) << clean.name;
    EXPECT_EQ(r.orientation.piecesTurnedOutward, 1u) << clean.name;
    EXPECT_EQ(r.orientation.reorientedTriangles, m.triangles.size()) << clean.name;
    EXPECT_EQ(r.orientation.closedPieces, 1u) << clean.name;
    EXPECT_TRUE(sameOrientation(m, clean)) << clean.name;
    EXPECT_GT(test::signedVolume(m.positions, m.triangles), 0.0) << clean.name;
  }
}

TEST(MeshRepair, RandomlyFlippedFacesFollowTheirPiece) {
  for (int every : {100, 5, 2}) { // 1%, 20% and 50% of the faces reversed
    Mesh clean = makeSphereMesh(1.0f, 3);
    validateMesh(clean);
    Mesh m = clean;
    reverseEvery(m, every);
    const MeshReport r = validateMesh(m);
    EXPECT_TRUE(r.watertight()) << every;
    EXPECT_EQ(r.misorientedEdges, 0u) << every;
    EXPECT_TRUE(sameOrientation(m, clean)) << every;
    EXPECT_EQ(r.orientation.reorientedTriangles, (clean.triangles.size() + every - 1) / every) << every;
  }
}

TEST(MeshRepair, OpenPiecesKeepTheOrientationMostOfTheirFacesHad) {
  Mesh clean = cutHoles(makeSphereMesh(1.0f, 3), 3, 0.4f);
  validateMesh(clean);
  for (bool insideOut : {false, true}) {
    Mesh m = clean;
    if (insideOut) reverseAll(m);
    const Mesh majority = m;
    reverseEvery(m, 7);
    const MeshReport r = validateMesh(m);
    EXPECT_GT(r.boundaryEdges, 0u);
    EXPECT_EQ(r.misorientedEdges, 0u);
    EXPECT_EQ(r.orientation.closedPieces, 0u);
    EXPECT_EQ(r.orientation.piecesTurnedOutward, 0u); // an open piece has no inside to face
    EXPECT_TRUE(sameOrientation(m, majority)) << insideOut;
  }
}

TEST(MeshRepair, PiecesArePartsJoinedByEdges) {
  // Two spheres passing through each other, one inside-out, and a loose open triangle: three pieces.
  Mesh a = makeSphereMesh(1.0f, 2), b = makeSphereMesh(1.0f, 2);
  reverseAll(b);
  Mesh m = a;
  const unsigned offset = unsigned(m.positions.size());
  for (glm::vec3 p : b.positions) m.positions.push_back(p + glm::vec3(1.2f, 0.0f, 0.0f));
  for (glm::uvec3 t : b.triangles) m.triangles.push_back(t + glm::uvec3(offset));
  m.positions.insert(m.positions.end(), {{5, 0, 0}, {6, 0, 0}, {5, 1, 0}});
  m.triangles.emplace_back(unsigned(m.positions.size() - 3), unsigned(m.positions.size() - 2),
                           unsigned(m.positions.size() - 1));
  const MeshReport r = validateMesh(m);
  EXPECT_EQ(r.orientation.pieces, 3u);
  EXPECT_EQ(r.orientation.closedPieces, 2u);
  EXPECT_EQ(r.orientation.piecesTurnedOutward, 1u);
  const MeshPieces pieces = meshPieces(m.triangles);
  ASSERT_EQ(pieces.count(), 3u);
  for (double v : pieceSignedVolumes6(m.positions, m.triangles, pieces)) EXPECT_GE(v, 0.0);
}
