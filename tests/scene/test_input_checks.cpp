// Hostile mesh and scene files (docs/reliability.md): references that lead out of their folder, headers whose
// counts and lengths do not fit the file, indices past the vertices, names of a megabyte.
#include "TestUtil.h"
#include "scene/ConfinedFiles.h"
#include "scene/MeshIO.h"
#include "scene/SceneLoader.h"
#include "util/Error.h"

#include <gtest/gtest.h>

#include <cstring>

using namespace rtsdf;
using rtsdf::test::TempDir;
using rtsdf::test::writeText;
namespace fs = std::filesystem;

namespace {

template <class F> std::string errorOf(F&& f) {
  try {
    f();
  } catch (const Error& e) {
    return e.what();
  }
  return "";
}

const char* kTetraObj = "v 0 0 0\nv 1 0 0\nv 0 1 0\nv 0 0 1\nf 1 3 2\nf 1 2 4\nf 1 4 3\nf 2 3 4\n";

std::string u32(std::uint32_t v) { return std::string(reinterpret_cast<const char*>(&v), 4); }

/// Three float3 positions, then uint16 indices: the glTF buffer of one primitive.
std::string triangleBuffer(const std::vector<std::uint16_t>& indices) {
  const float p[3][3] = {{0, 0, 0}, {1, 0, 0}, {0, 1, 0}};
  std::string bytes(reinterpret_cast<const char*>(p), sizeof p);
  for (const std::uint16_t i : indices) bytes.append(reinterpret_cast<const char*>(&i), 2);
  while (bytes.size() % 4) bytes += '\0';
  return bytes;
}

/// A glTF's JSON for triangleBuffer(@a indices) named 'tri', the buffer at @a uri (none: the GLB's BIN chunk), its
/// primitive of glTF mode @a mode (4: triangles).
std::string triangleGltf(std::size_t indices, const std::string& uri, std::size_t bufferBytes, int mode = 4) {
  return R"({"asset":{"version":"2.0"},"scene":0,"scenes":[{"nodes":[0]}],"nodes":[{"mesh":0}],)"
         R"("meshes":[{"name":"tri","primitives":[{"attributes":{"POSITION":0},"indices":1,"mode":)" +
         std::to_string(mode) + R"(}]}],)"
         R"("buffers":[{"byteLength":)" + std::to_string(bufferBytes) +
         (uri.empty() ? "" : R"(,"uri":")" + uri + "\"") +
         R"(}],"bufferViews":[{"buffer":0,"byteOffset":0,"byteLength":36},{"buffer":0,"byteOffset":36,"byteLength":)" +
         std::to_string(2 * indices) + R"(}],"accessors":[{"bufferView":0,"componentType":5126,"count":3,)"
         R"("type":"VEC3","min":[0,0,0],"max":[1,1,0]},{"bufferView":1,"componentType":5123,"count":)" +
         std::to_string(indices) + R"(,"type":"SCALAR"}]})";
}

/// A GLB of @a json and @a bin, its JSON chunk's length written as @a jsonLength when given.
std::string glb(std::string json, const std::string& bin, std::uint32_t jsonLength = 0) {
  while (json.size() % 4) json += ' ';
  std::string body = u32(jsonLength ? jsonLength : std::uint32_t(json.size())) + "JSON" + json;
  if (!bin.empty()) body += u32(std::uint32_t(bin.size())) + std::string("BIN\0", 4) + bin;
  return "glTF" + u32(2) + u32(std::uint32_t(12 + body.size())) + body;
}

} // namespace

TEST(InputChecks, GltfBufferOutsideItsFolderIsRefused) {
  TempDir dir;
  fs::create_directories(dir / "m");
  writeText(dir / "m" / "t.gltf", triangleGltf(3, "../../../../../../etc/passwd", 42));
  std::string msg = errorOf([&] { loadMeshFile(dir / "m" / "t.gltf"); });
  EXPECT_NE(msg.find("t.gltf: the reference '../../../../../../etc/passwd' is refused"), std::string::npos) << msg;
  EXPECT_NE(msg.find("'..' leads out of it"), std::string::npos) << msg;
  EXPECT_EQ(msg.find('\n'), std::string::npos) << msg;
  // Without indices the check before assimp reads no buffer: the confined file system refuses it.
  std::string noIndices = triangleGltf(3, "../outside.bin", 44);
  noIndices.replace(noIndices.find(R"(,"indices":1)"), 12, "");
  writeText(dir / "outside.bin", triangleBuffer({0, 1, 2}));
  writeText(dir / "m" / "n.gltf", noIndices);
  msg = errorOf([&] { loadMeshFile(dir / "m" / "n.gltf"); });
  EXPECT_NE(msg.find("n.gltf: the reference '../outside.bin' is refused"), std::string::npos) << msg;
  MeshLoadOptions allow;
  allow.allowOutsideReferences = true;
  EXPECT_EQ(loadMeshFile(dir / "m" / "n.gltf", allow).triangles.size(), 1u);
}

TEST(InputChecks, GltfBufferInsideItsFolderLoads) {
  TempDir dir;
  writeText(dir / "t.bin", triangleBuffer({0, 1, 2}));
  writeText(dir / "t.gltf", triangleGltf(3, "t.bin", 44));
  EXPECT_EQ(loadMeshFile(dir / "t.gltf").triangles.size(), 1u);
}

TEST(InputChecks, MeshInMemoryReadsNoFile) {
  std::string noIndices = triangleGltf(3, "/etc/passwd", 44);
  noIndices.replace(noIndices.find(R"(,"indices":1)"), 12, "");
  const std::string msg = errorOf([&] { loadMeshFromMemory(noIndices, ".gltf", "mem.gltf"); });
  EXPECT_NE(msg.find("mem.gltf: the reference '/etc/passwd' is refused"), std::string::npos) << msg;
  EXPECT_NE(errorOf([&] { loadMeshFromMemory(std::string("mtllib /etc/passwd\n") + kTetraObj, ".obj", "m.obj"); })
                .find("m.obj: the reference '/etc/passwd' is refused"),
            std::string::npos);
}

TEST(InputChecks, ObjMaterialLibraryOutsideIsRefusedUnlessAllowed) {
  TempDir dir;
  fs::create_directories(dir / "m");
  writeText(dir / "outside.mtl", "newmtl a\nKd 1 0 0\n");
  writeText(dir / "m" / "up.obj", std::string("mtllib ../outside.mtl\n") + kTetraObj);
  std::string msg = errorOf([&] { loadMeshFile(dir / "m" / "up.obj"); });
  EXPECT_NE(msg.find("up.obj: the reference '../outside.mtl' is refused"), std::string::npos) << msg;
  // A symbolic link inside the folder that leads out of it.
  fs::create_symlink(dir / "outside.mtl", dir / "m" / "link.mtl");
  writeText(dir / "m" / "link.obj", std::string("mtllib link.mtl\n") + kTetraObj);
  msg = errorOf([&] { loadMeshFile(dir / "m" / "link.obj"); });
  EXPECT_NE(msg.find("link.obj: the reference 'link.mtl' is refused"), std::string::npos) << msg;
  EXPECT_NE(msg.find("symbolic link"), std::string::npos) << msg;
  MeshLoadOptions allow;
  allow.allowOutsideReferences = true;
  EXPECT_EQ(loadMeshFile(dir / "m" / "up.obj", allow).triangles.size(), 4u);
  EXPECT_EQ(loadMeshFile(dir / "m" / "link.obj", allow).triangles.size(), 4u);
}

TEST(InputChecks, EscapeFromFolderSaysWhy) {
  TempDir dir;
  fs::create_directories(dir / "a" / "b");
  EXPECT_EQ(escapeFromFolder(dir / "a", dir / "a" / "b" / ".." / "x.obj"), "");
  EXPECT_EQ(escapeFromFolder(dir / "a", dir / "a" / ".." / "x.obj"), "'..' leads out of it");
  EXPECT_EQ(escapeFromFolder(dir / "a", "/etc/passwd"), "an absolute path outside it");
  fs::create_directory_symlink(dir.path(), dir / "a" / "up");
  EXPECT_NE(escapeFromFolder(dir / "a", dir / "a" / "up" / "x.obj").find("symbolic link"), std::string::npos);
}

TEST(InputChecks, SceneMeshPathsStayInTheScenesFolderOrBeside) {
  TempDir dir;
  fs::create_directories(dir / "p" / "scenes");
  fs::create_directories(dir / "p" / "meshes");
  writeText(dir / "p" / "meshes" / "t.obj", kTetraObj);
  writeText(dir / "t.obj", kTetraObj);
  const auto scene = [](const std::string& path) {
    return R"({"meshes": {"m": {"path": ")" + path + R"("}}, "instances": [{"mesh": "m"}]})";
  };
  writeText(dir / "p" / "scenes" / "ok.json", scene("../meshes/t.obj"));
  EXPECT_EQ(loadScene(dir / "p" / "scenes" / "ok.json").meshes.size(), 1u);
  writeText(dir / "p" / "scenes" / "far.json", scene("../../t.obj"));
  const std::string msg = errorOf([&] { loadScene(dir / "p" / "scenes" / "far.json"); });
  EXPECT_NE(msg.find("far.json: the reference '../../t.obj' is refused"), std::string::npos) << msg;
  MeshLoadOptions allow;
  allow.allowOutsideReferences = true;
  EXPECT_EQ(loadScene(dir / "p" / "scenes" / "far.json", allow).meshes.size(), 1u);
}

TEST(InputChecks, BinaryStlCountMustMatchTheSize) {
  std::string stl(80, ' ');
  stl += u32(1000000) + std::string(600, '\x01');
  const std::string msg = errorOf([&] { loadMeshFromMemory(stl, ".stl", "bunny.stl"); });
  EXPECT_EQ(msg, "bunny.stl: binary STL says 1000000 triangles (50000084 bytes) but the file has 684 bytes");
  // Cut short: one triangle declared, half of it there.
  std::string cut(80, 'x');
  cut += u32(1) + std::string(25, '\0');
  EXPECT_NE(errorOf([&] { loadMeshFromMemory(cut, ".stl", "cut.stl"); }).find("says 1 triangles (134 bytes)"),
            std::string::npos);
  EXPECT_NE(errorOf([&] { loadMeshFromMemory(std::string(40, '\x02'), ".stl", "tiny.stl"); }).find("at least 84"),
            std::string::npos);
}

TEST(InputChecks, BinaryPlyCountsMustFitAfterTheHeader) {
  const std::string header = "ply\nformat binary_little_endian 1.0\nelement vertex 3\nproperty float x\n"
                             "property float y\nproperty float z\nelement face 1000\nproperty list uchar int "
                             "vertex_indices\nend_header\n";
  const std::string msg = errorOf([&] { loadMeshFromMemory(header + std::string(36 + 13, '\0'), ".ply", "f.ply"); });
  EXPECT_NE(msg.find("f.ply: the PLY header declares element 'face' with 1000 records of at least 1 bytes"),
            std::string::npos) << msg;
  EXPECT_NE(msg.find("the file has 49 bytes after its header"), std::string::npos) << msg;
  const std::string vertices =
      errorOf([&] { loadMeshFromMemory(header + std::string(20, '\0'), ".ply", "v.ply"); });
  EXPECT_NE(vertices.find("element 'vertex' with 3 records of at least 12 bytes"), std::string::npos) << vertices;
}

// assimp reads the count of an element whose name it does not know where the name starts: a name of digits was
// 3817748707 records, 91 GB allocated at once (fuzz/regressions/fuzz_mesh/ply-element-name-of-digits-read-as-count).
// Records of no properties still count a byte each.
TEST(InputChecks, PlyElementCountsAreTheCountsTheImporterReads) {
  const std::string digits = "ply\nformat ascii 1.0\nelement 555555555555555555555555555555555loat\nend_header\n"
                             "0 0 0\n";
  EXPECT_EQ(errorOf([&] { loadMeshFromMemory(digits, ".ply", "d.ply"); }),
            "d.ply: the PLY header declares element '555555555555555555555555555555555loat' with 3817748707 records "
            "of at least 1 bytes (in all at least 3817748707 bytes), but the file has 6 bytes after its header");
  // A name it does not know, followed by its count, is 0 records to the importer: the count is not held against it.
  const std::string tetra = "ply\nformat ascii 1.0\nelement vertex 4\nproperty float x\nproperty float y\n"
                            "property float z\nelement face 4\nproperty list uchar int vertex_indices\n"
                            "element color 1000000\nproperty uchar r\nend_header\n0 0 0\n1 0 0\n0 1 0\n0 0 1\n"
                            "3 0 2 1\n3 0 1 3\n3 0 3 2\n3 1 2 3\n";
  EXPECT_EQ(loadMeshFromMemory(tetra, ".ply", "t.ply").triangles.size(), 4u);
  // A header line that is no PLY keyword: assimp skips it, not always cleanly (28 GB allocated after
  // 'proper555...5ty float x': fuzz/regressions/fuzz_mesh/ply-unknown-header-line-of-digits-28gb).
  std::string unknown = tetra;
  unknown.replace(unknown.find("property float y"), 16, "proper555ty float y");
  EXPECT_EQ(errorOf([&] { loadMeshFromMemory(unknown, ".ply", "u.ply"); }),
            "u.ply: line 5 of the PLY header starts with 'proper555ty', not a PLY keyword (format, comment, obj_info, "
            "element, property, end_header)");
}

TEST(InputChecks, GlbLengthsMustFitTheFile) {
  const std::string json = triangleGltf(3, "", 44);
  const std::string good = glb(json, triangleBuffer({0, 1, 2}));
  EXPECT_EQ(loadMeshFromMemory(good, ".glb", "good.glb").triangles.size(), 1u);
  TempDir dir;
  writeText(dir / "good.glb", good);
  EXPECT_EQ(loadMeshFile(dir / "good.glb").triangles.size(), 1u);

  writeText(dir / "lying.glb", glb(json, triangleBuffer({0, 1, 2}), 0x80000000u));
  std::string msg = errorOf([&] { loadMeshFile(dir / "lying.glb"); });
  EXPECT_NE(msg.find("lying.glb: GLB chunk 0 (JSON) says 2147483648 bytes but"), std::string::npos) << msg;
  std::string longer = good;
  const std::uint32_t claimed = 1u << 30;
  std::memcpy(&longer[8], &claimed, 4);
  writeText(dir / "long.glb", longer);
  msg = errorOf([&] { loadMeshFile(dir / "long.glb"); });
  EXPECT_NE(msg.find("long.glb: the GLB header says 1073741824 bytes but the file has"), std::string::npos) << msg;
  // The importer reads the JSON chunk whatever the header's length says: a length of 0 let a JSON chunk stating
  // 4 GiB through (fuzz/regressions/fuzz_gltf/glb-header-length-0-json-chunk-4-gib).
  std::string none = glb(json, triangleBuffer({0, 1, 2}), 0xFFDD0000u);
  std::memset(&none[8], 0, 4);
  EXPECT_EQ(errorOf([&] { loadMeshFromMemory(none, ".glb", "none.glb"); }),
            "none.glb: the GLB header says 0 bytes: too few for its 12-byte header and its JSON chunk's");
  // The BIN chunk past a JSON chunk of more than 64 KiB is checked too.
  std::string big = glb(json + std::string(70000, ' '), triangleBuffer({0, 1, 2}));
  const std::uint32_t binClaim = 1u << 31;
  std::memcpy(&big[big.size() - 44 - 8], &binClaim, 4);
  writeText(dir / "bin.glb", big);
  msg = errorOf([&] { loadMeshFile(dir / "bin.glb"); });
  EXPECT_NE(msg.find("bin.glb: GLB chunk 1 (BIN) says 2147483648 bytes but 44 remain"), std::string::npos) << msg;
}

TEST(InputChecks, GltfIndexPastTheVerticesNamesMeshAndFace) {
  TempDir dir;
  writeText(dir / "t.bin", triangleBuffer({0, 1, 2, 0, 2, 99}));
  writeText(dir / "t.gltf", triangleGltf(6, "t.bin", 48));
  const std::string msg = errorOf([&] { loadMeshFile(dir / "t.gltf"); });
  EXPECT_EQ(msg, (dir / "t.gltf").string() +
                     ": mesh 'tri' primitive 0: face 1 uses vertex index 99 but the primitive has 3 vertices");
  const std::string inGlb = glb(triangleGltf(6, "", 48), triangleBuffer({0, 1, 2, 0, 2, 99}));
  EXPECT_NE(errorOf([&] { loadMeshFromMemory(inGlb, ".glb", "i.glb"); }).find("i.glb: mesh 'tri' primitive 0: face 1"),
            std::string::npos);
}

// Points, lines, loops, strips and fans are checked as triangles are: assimp read a line loop whose first line it
// had dropped (an index past the vertices) through a null pointer, and counted a line strip of no indices as 2^32
// lines (64 GiB asked for); both were fuzz_gltf's findings (fuzz/regressions/fuzz_gltf).
TEST(InputChecks, GltfPrimitivesOfEveryModeNeedEnoughIndicesWithinTheVertices) {
  const auto load = [](const std::vector<std::uint16_t>& indices, int mode) {
    const std::string bin = triangleBuffer(indices);
    const std::string file = glb(triangleGltf(indices.size(), "", bin.size(), mode), bin);
    return errorOf([&] { loadMeshFromMemory(file, ".glb", "m.glb"); });
  };
  const std::string at = "m.glb: mesh 'tri' primitive 0: ";
  EXPECT_EQ(load({5, 1, 2}, 2), at + "line 0 uses vertex index 5 but the primitive has 3 vertices");
  EXPECT_EQ(load({0, 1, 2, 99}, 5), at + "face 1 uses vertex index 99 but the primitive has 3 vertices");
  EXPECT_EQ(load({0, 1, 7}, 0), at + "point 2 uses vertex index 7 but the primitive has 3 vertices");
  EXPECT_EQ(load({0}, 3), at + "mode 3 (line strip) needs at least 2 indices but index accessor 1 has 1");
  EXPECT_EQ(load({}, 3), at + "accessor 1 needs a type (SCALAR, VEC2-4, MAT2-4), a component type (5120-5126) and a "
                              "count from 1 to 2^32 - 1");
  EXPECT_EQ(load({0, 1}, 6), at + "mode 6 (triangle fan) needs at least 3 indices but index accessor 1 has 2");
  EXPECT_EQ(load({0}, 1), at + "mode 1 (lines) needs at least 2 indices but index accessor 1 has 1");
  // Bytes past the length in the GLB's header are not the GLB's, as the importer reads it: the check reads the same.
  const std::string bin = triangleBuffer({5, 1, 2});
  const std::string junk = glb(triangleGltf(3, "", bin.size(), 2), bin) + "junk, 13 long";
  EXPECT_EQ(errorOf([&] { loadMeshFromMemory(junk, ".glb", "j.glb"); }),
            "j.glb: mesh 'tri' primitive 0: line 0 uses vertex index 5 but the primitive has 3 vertices");
  // A JSON chunk's stated length need not be a multiple of 4: the importer skips its padding to the BIN chunk, and
  // the check finds the BIN chunk there too.
  std::string unpadded = triangleGltf(3, "", bin.size(), 2) + "    ";
  while (unpadded.size() % 4) unpadded += ' ';
  EXPECT_EQ(errorOf([&] { loadMeshFromMemory(glb(unpadded, bin, unpadded.size() - 1), ".glb", "p.glb"); }),
            "p.glb: mesh 'tri' primitive 0: line 0 uses vertex index 5 but the primitive has 3 vertices");
  // Without indices the vertices are the elements.
  std::string unindexed = triangleGltf(0, "", 36, 5);
  unindexed.replace(unindexed.find(R"("indices":1,)"), 12, "");
  const std::string two = std::string(R"("count":2,"type":"VEC3")");
  unindexed.replace(unindexed.find(R"("count":3,"type":"VEC3")"), two.size(), two);
  EXPECT_EQ(errorOf([&] { loadMeshFromMemory(glb(unindexed, triangleBuffer({})), ".glb", "u.glb"); }),
            "u.glb: mesh 'tri' primitive 0: mode 5 (triangle strip) needs at least 3 vertices but the primitive has 2 "
            "vertices");
  // A primitive without a POSITION attribute has no vertices: its indices, if any, point past them, and a strip
  // or fan without indices has too few (others are left to the importer: not drawn).
  std::string noPositions = triangleGltf(3, "", bin.size(), 2);
  noPositions.replace(noPositions.find(R"("POSITION":0)"), 12, R"("NORMAL":0)");
  EXPECT_EQ(errorOf([&] { loadMeshFromMemory(glb(noPositions, bin), ".glb", "n.glb"); }),
            "n.glb: mesh 'tri' primitive 0: line 0 uses vertex index 5 but the primitive has no vertices (no POSITION "
            "attribute)");
  noPositions.replace(noPositions.find(R"(,"indices":1)"), 12, "");
  noPositions.replace(noPositions.find(R"("mode":2)"), 8, R"("mode":6)");
  EXPECT_EQ(errorOf([&] { loadMeshFromMemory(glb(noPositions, bin), ".glb", "n.glb"); }),
            "n.glb: mesh 'tri' primitive 0: mode 6 (triangle fan) needs at least 3 vertices but the primitive has no "
            "vertices (no POSITION attribute)");
  // Members of another type are read as the importer reads them: a mode that is not a whole number is triangles,
  // and indices that are not an index are none.
  std::string typed = triangleGltf(3, "", bin.size(), 2);
  typed.replace(typed.find(R"("mode":2)"), 8, R"("mode":"2")");
  EXPECT_EQ(errorOf([&] { loadMeshFromMemory(glb(typed, bin), ".glb", "t.glb"); }),
            "t.glb: mesh 'tri' primitive 0: face 0 uses vertex index 5 but the primitive has 3 vertices");
  typed.replace(typed.find(R"("indices":1)"), 11, R"("indices":-1)");
  typed.replace(typed.find(R"("count":3,"type":"VEC3")"), two.size(), two);
  EXPECT_EQ(errorOf([&] { loadMeshFromMemory(glb(typed, bin), ".glb", "t.glb"); }),
            "t.glb: mesh 'tri' primitive 0: mode 4 (triangles) needs at least 3 vertices but the primitive has 2 "
            "vertices");
  // A well-formed strip and fan load their triangle; the file path checks too.
  for (const int mode : {5, 6}) {
    const std::string ok = triangleBuffer({0, 1, 2});
    EXPECT_EQ(loadMeshFromMemory(glb(triangleGltf(3, "", ok.size(), mode), ok), ".glb", "ok.glb").triangles.size(), 1u);
  }
  TempDir dir;
  writeText(dir / "t.bin", triangleBuffer({1}));
  writeText(dir / "t.gltf", triangleGltf(1, "t.bin", 40, 2));
  EXPECT_EQ(errorOf([&] { loadMeshFile(dir / "t.gltf"); }),
            (dir / "t.gltf").string() +
                ": mesh 'tri' primitive 0: mode 2 (line loop) needs at least 2 indices but index accessor 1 has 1");
}

TEST(InputChecks, NamesOfAMegabyteAreCutInMessages) {
  const std::string huge(1 << 20, 'n');
  const std::vector<std::string> scenes = {
      R"({"meshes": {"b": {"box": [1, 1, 1]}}, "instances": [{"mesh": ")" + huge + R"("}]})",
      R"({"meshes": {"b": {"box": [1, 1, 1]}}, "instances": [{"mesh": "b", "name": ")" + huge +
          R"("}, {"mesh": "b", "name": ")" + huge + R"("}]})",
      R"({"meshes": {")" + huge + R"(": {"box": [1, 1, 0]}}, "instances": [{"mesh": "b"}]})",
      R"({"meshes": {"b": {"box": [1, 1, 1]}}, "instances": [{"mesh": "b", ")" + huge + R"(": 1}]})",
      R"({"meshes": {"b": {"box": [1, 1, 1], "box": [2, 2, 2]}}, ")" + huge + R"(": 1, ")" + huge + R"(": 2})",
      R"({"meshes": {"b": {"path": ")" + huge + R"(.obj"}}, "instances": [{"mesh": "b"}]})"};
  for (const std::string& text : scenes) {
    std::string msg;
    try {
      parseScene(text, "s.json");
    } catch (const Error& e) {
      msg = e.what();
    }
    EXPECT_FALSE(msg.empty());
    EXPECT_LE(msg.size(), 300u) << msg.substr(0, 400);
    EXPECT_EQ(msg.find('\n'), std::string::npos);
  }
}

TEST(InputChecks, AMillionKeyframesParse) {
  // The parse used to be quadratic in the keyframes (1e5 took 4.6 s); docs/reliability.md has the timings.
  std::string text =
      R"({"meshes": {"b": {"box": [1, 1, 1]}}, "instances": [{"mesh": "b", "animation": {"keyframes": [)";
  constexpr int kFrames = 200000;
  for (int i = 0; i < kFrames; ++i)
    text += std::string(i ? "," : "") + R"({"time": )" + std::to_string(i) + R"(, "translate": [1, 0, 0]})";
  text += "]}}]}";
  const Scene s = parseScene(text, "k.json");
  ASSERT_EQ(s.instances.size(), 1u);
  EXPECT_EQ(s.instances[0].animation.keyframes.size(), std::size_t(kFrames));
  EXPECT_EQ(s.instances[0].animation.keyframes.back().time, kFrames - 1);
}

// A .glb without the binary glTF magic, or a .gltf that is not JSON, is refused before assimp sees it: assimp went on to
// try every other importer on such bytes, and one read past the end of a short buffer (fuzz_gltf's finding, kept in
// fuzz/regressions/fuzz_gltf). A real glTF of either kind still reaches the importer.
TEST(InputChecks, AGlbWithoutItsMagicOrAGltfThatIsNotJsonIsRefused) {
  const std::string finding("g\0gindexarrayl\0JSON{\"a\0glT", 27);
  const std::string glb = errorOf([&] { loadMeshFromMemory(finding, ".glb", "f.glb"); });
  EXPECT_NE(glb.find("f.glb: not a binary glTF"), std::string::npos) << glb;
  const std::string gltf = errorOf([&] { loadMeshFromMemory(finding, "gltf", "f.gltf"); });
  EXPECT_NE(gltf.find("f.gltf: not a glTF"), std::string::npos) << gltf;
  // JSON (after white space and a byte order mark) gets past the form check to the importer, which says what is wrong.
  const std::string json = errorOf([&] { loadMeshFromMemory("\xEF\xBB\xBF  {\"asset\": {}}", ".gltf", "j.gltf"); });
  EXPECT_EQ(json.find("not a glTF"), std::string::npos) << json;
  EXPECT_NE(json.find("j.gltf"), std::string::npos) << json;
  // JSON that does not parse: both glTF importers declined it, and assimp sniffed it with every other importer (the
  // OBJ importer read through a null pointer: fuzz/regressions/fuzz_gltf/gltf-malformed-json-sniffed-as-obj).
  const std::string broken = errorOf([&] { loadMeshFromMemory("{\"asset\" mtllib {}}", ".gltf", "b.gltf"); });
  EXPECT_EQ(broken.rfind("b.gltf: not a glTF: malformed JSON: ", 0), 0u) << broken;
  const std::string array = errorOf([&] { loadMeshFromMemory("[1, 2]", ".gltf", "a.gltf"); });
  EXPECT_EQ(array, "a.gltf: not a glTF: a .gltf is a JSON object (it starts with '{') or a GLB") << array;
}

// Every accessor a primitive names is checked as the spec lays it out before the importer reads it: the importer
// trusts a count times one component, reads an index accessor of any type as packed integers, reads buffer 0 of a
// GLB from its BIN chunk whatever its uri says, patches sparse values through indices it never checks, and hands
// a glTF 1.0 file to its older importer, which counts a strip's lines without a check (a review's crafted files).
TEST(InputChecks, GltfAccessorsAreCheckedAsTheSpecLaysThemOut) {
  const std::string bin = triangleBuffer({0, 1, 2});
  const auto load = [&bin](const std::string& json, const std::string& extension = ".glb") {
    const std::string file = extension == ".glb" ? glb(json, bin) : json;
    return errorOf([&] { loadMeshFromMemory(file, extension, "a" + extension); });
  };
  const auto edited = [](std::string json, const std::string& from, const std::string& to) {
    return json.replace(json.find(from), from.size(), to);
  };
  const std::string good = triangleGltf(3, "", bin.size());
  EXPECT_EQ(load(good), "");
  const std::string at = "a.glb: mesh 'tri' primitive 0";
  EXPECT_EQ(load(edited(good, R"("componentType":5123)", R"("componentType":5122)")),
            at + ": index accessor 1 must hold tightly packed unsigned SCALARs (component type 5121, 5123 or 5125) "
                 "without a sparse part");
  EXPECT_EQ(load(edited(good, R"("byteOffset":36,"byteLength":6)", R"("byteOffset":36,"byteLength":6,"byteStride":3)")),
            at + ": accessor 1: buffer view 1 has a byteStride of 3, not a multiple of 4 from 2 to 252");
  EXPECT_EQ(load(edited(good, R"("count":3,"type":"VEC3")", R"("count":4,"type":"VEC3")")),
            at + " POSITION: accessor 0: 48 bytes from byte 0 reach past the 36 bytes of buffer view 0");
  EXPECT_EQ(load(edited(good, R"("type":"VEC3",)", R"("type":"VEC3","sparse":{"count":1},)")),
            at + " POSITION: accessor 0: a sparse part needs a count of 1 to 3, and indices and values with a buffer "
                 "view each");
  // Buffer 0 of a GLB is its BIN chunk, whatever its uri says.
  const std::string past = triangleBuffer({0, 1, 9});
  EXPECT_EQ(errorOf([&] { loadMeshFromMemory(glb(triangleGltf(3, "elsewhere.bin", 44), past), ".glb", "u.glb"); }),
            "u.glb: mesh 'tri' primitive 0: face 0 uses vertex index 9 but the primitive has 3 vertices");
  // A .gltf's data URI is base64, wholly.
  const std::string uri =
      "data:application/octet-stream;base64,AAAAAAAAAAAAAAAAAACAPwAAAAAAAAAAAAAAAAAAgD8AAAAAAAABAAIAAAA=";
  const std::string inline_ = triangleGltf(3, uri, 44);
  EXPECT_EQ(load(inline_, ".gltf"), "");
  EXPECT_EQ(load(edited(inline_, "AAABAAIA", "AAAB!AIA"), ".gltf"),
            "a.gltf: buffer 0: its data URI holds a character outside base64");
  EXPECT_EQ(load(edited(inline_, ";base64,", ","), ".gltf"),
            "a.gltf: buffer 0: a data URI that is not base64 (a glTF's are)");
  // glTF 2.0 only, and JSON of a handful of levels.
  EXPECT_EQ(load(edited(inline_, R"("version":"2.0")", R"("version":"1.0")"), ".gltf"),
            "a.gltf: asset.version is \"1.0\": only glTF 2.0 is read");
  std::string v1 = glb(good, bin);
  v1[4] = 1;
  EXPECT_EQ(errorOf([&] { loadMeshFromMemory(v1, ".glb", "v.glb"); }), "v.glb: GLB version 1: only glTF 2.0 is read");
  const std::string deep = R"("scene":0,"x":)" + std::string(65, '[') + std::string(65, ']') + ",";
  EXPECT_EQ(load(edited(inline_, R"("scene":0,)", deep), ".gltf"),
            "a.gltf: not a glTF: its JSON nests deeper than 64 levels");
}

// The importer reads a glTF's skins and animations whatever uses them, and trusts them: a skin without inverse bind
// matrices (valid glTF) ended it. It reads only the surface now (gltfGeometry): node tree, positions, indices and
// modes. Duplicate keys, which the importer's JSON reader takes first and the checks' last, reach it as the checks
// saw them.
TEST(InputChecks, GltfIsReadAsItsSurfaceOnly) {
  const std::string bin = triangleBuffer({0, 1, 2});
  std::string skinned = triangleGltf(3, "", bin.size());
  const std::string skin = R"("nodes":[{"mesh":0,"skin":0}],"skins":[{"joints":[0]}])";
  skinned.replace(skinned.find(R"("nodes":[{"mesh":0}])"), 20, skin);
  EXPECT_EQ(loadMeshFromMemory(glb(skinned, bin), ".glb", "s.glb").triangles.size(), 1u);
  std::string twice = triangleGltf(3, "", bin.size(), 2);
  twice.replace(twice.find(R"(,"buffers")"), 10, R"(,"meshes":[],"buffers")");
  const std::string twiceGlb = glb(twice, triangleBuffer({9, 1, 2}));
  EXPECT_EQ(errorOf([&] { loadMeshFromMemory(twiceGlb, ".glb", "t.glb"); }).rfind("t.glb: ", 0), 0u);
  // Members it does not have are read as absent (fuzz/regressions/fuzz_gltf/gltf-without-nodes-read-as-missing-key).
  std::string bare = triangleGltf(3, "", bin.size());
  bare.replace(bare.find(R"("nodes":[{"mesh":0}],)"), 21, "");
  EXPECT_EQ(errorOf([&] { loadMeshFromMemory(glb(bare, bin), ".glb", "b.glb"); }).rfind("b.glb: ", 0), 0u);
}

// Only the importers that claim a file's extension read it: where they decline it (both glTF importers decline a
// .gltf they cannot parse), assimp used to try every other importer's sniffing on the bytes, and the OBJ importer
// read a broken .gltf through a null pointer. An OBJ under a name no importer claims is no longer read as an OBJ.
TEST(InputChecks, AFileIsReadOnlyByTheImportersOfItsExtension) {
  EXPECT_EQ(loadMeshFromMemory(kTetraObj, ".obj", "t.obj").triangles.size(), 4u);
  const std::string msg = errorOf([&] { loadMeshFromMemory(kTetraObj, ".xyz", "t.xyz"); });
  EXPECT_EQ(msg.rfind("t.xyz: cannot read mesh: ", 0), 0u) << msg;
}
