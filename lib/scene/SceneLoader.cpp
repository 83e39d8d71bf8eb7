#include "scene/SceneLoader.h"

#include "scene/ConfinedFiles.h"
#include "scene/MeshIO.h"
#include "util/Error.h"
#include "util/InputFile.h"
#include "util/Text.h"

#include <fmt/format.h>
#include <glm/gtc/quaternion.hpp>
#include <nlohmann/json.hpp>
#include <spdlog/spdlog.h>

#include <algorithm>
#include <cmath>
#include <fstream>
#include <map>
#include <set>
#include <unordered_set>
#include <sstream>

namespace rtsdf {
namespace fs = std::filesystem;
using json = nlohmann::json;

namespace {

/// Names and keys come from the file: a message quotes at most this many characters of one (a hostile scene
/// must not make an error line of a megabyte).
constexpr std::size_t kQuoteChars = 60;

/// Reads values from a JSON object while naming the file and the key path in every error.
class Reader {
public:
  Reader(std::string file) : mFile(std::move(file)) {}

  /// The scene file every error names.
  const std::string& file() const { return mFile; }

  [[noreturn]] void fail(const std::string& where, const std::string& what) const {
    // Keys and names come from the file: each piece is cut to one line of bounded length.
    throw Error(fmt::format("{}: {}: {}", mFile, oneLine(where, 100), oneLine(what, 180)));
  }

  void allowOnly(const json& obj, const std::string& where, std::initializer_list<const char*> keys) const {
    if (!obj.is_object()) fail(where, "must be an object");
    std::set<std::string> allowed(keys.begin(), keys.end());
    for (const auto& [k, v] : obj.items())
      if (!allowed.count(k)) {
        std::string list;
        for (const auto& a : allowed) list += (list.empty() ? "" : ", ") + a;
        fail(where, fmt::format("unknown key '{}' (allowed: {})", oneLine(k, kQuoteChars), list));
      }
  }

  double number(const json& v, const std::string& where) const {
    if (!v.is_number()) fail(where, "must be a number");
    const double d = v.get<double>();
    if (!std::isfinite(d)) fail(where, "must be finite");
    return d;
  }

  double positive(const json& v, const std::string& where) const {
    const double d = number(v, where);
    if (!(d > 0.0)) fail(where, fmt::format("must be positive (got {})", d));
    return d;
  }

  glm::dvec3 vec3(const json& v, const std::string& where) const {
    if (!v.is_array() || v.size() != 3) fail(where, "must be an array of 3 numbers");
    return {number(v[0], where + "[0]"), number(v[1], where + "[1]"), number(v[2], where + "[2]")};
  }

  glm::dvec3 unit(const json& v, const std::string& where) const {
    const glm::dvec3 d = vec3(v, where);
    const double len = glm::length(d);
    if (!(len > 1e-12)) fail(where, "must be a non-zero vector");
    return d / len;
  }

  std::string string(const json& v, const std::string& where) const {
    if (!v.is_string()) fail(where, "must be a string");
    return v.get<std::string>();
  }

  /// "rotate": [x, y, z] Euler degrees (applied X, then Y, then Z) or {"axis": [..], "degrees": a}.
  glm::dquat rotation(const json& v, const std::string& where) const {
    if (v.is_array()) {
      const glm::dvec3 e = glm::radians(vec3(v, where));
      return glm::angleAxis(e.z, glm::dvec3(0, 0, 1)) * glm::angleAxis(e.y, glm::dvec3(0, 1, 0)) *
             glm::angleAxis(e.x, glm::dvec3(1, 0, 0));
    }
    allowOnly(v, where, {"axis", "degrees"});
    if (!v.contains("axis") || !v.contains("degrees")) fail(where, "needs 'axis' and 'degrees'");
    return glm::angleAxis(glm::radians(number(v["degrees"], where + ".degrees")), unit(v["axis"], where + ".axis"));
  }

  /// A number or [x, y, z]; negative factors mirror, zero would flatten the mesh.
  glm::dvec3 scale(const json& v, const std::string& where) const {
    const glm::dvec3 s = v.is_number() ? glm::dvec3(number(v, where)) : vec3(v, where);
    if (s.x == 0.0 || s.y == 0.0 || s.z == 0.0) fail(where, "scale factors must not be zero");
    return s;
  }

  Transform transform(const json& obj, const std::string& where) const {
    Transform t;
    if (obj.contains("translate")) t.translation = vec3(obj["translate"], where + ".translate");
    if (obj.contains("rotate")) t.rotation = rotation(obj["rotate"], where + ".rotate");
    if (obj.contains("scale")) t.scale = scale(obj["scale"], where + ".scale");
    return t;
  }

private:
  std::string mFile;
};

Animation parseAnimation(const Reader& rd, const json& a, const std::string& where) {
  rd.allowOnly(a, where, {"orbit", "keyframes"});
  Animation anim;
  if (a.contains("orbit") == a.contains("keyframes")) rd.fail(where, "needs exactly one of 'orbit' or 'keyframes'");
  if (a.contains("orbit")) {
    const json& o = a["orbit"];
    const std::string w = where + ".orbit";
    rd.allowOnly(o, w, {"center", "axis", "period", "phase_deg", "rotate_with_orbit"});
    anim.kind = Animation::Kind::Orbit;
    if (o.contains("center")) anim.center = rd.vec3(o["center"], w + ".center");
    if (o.contains("axis")) anim.axis = rd.unit(o["axis"], w + ".axis");
    if (!o.contains("period")) rd.fail(w, "needs 'period' (seconds per revolution)");
    anim.period = rd.positive(o["period"], w + ".period");
    if (o.contains("phase_deg")) anim.phase = glm::radians(rd.number(o["phase_deg"], w + ".phase_deg"));
    if (o.contains("rotate_with_orbit")) {
      if (!o["rotate_with_orbit"].is_boolean()) rd.fail(w + ".rotate_with_orbit", "must be true or false");
      anim.faceAlong = o["rotate_with_orbit"].get<bool>();
    }
  } else {
    const json& k = a["keyframes"];
    const std::string w = where + ".keyframes";
    if (!k.is_array() || k.empty()) rd.fail(w, "must be a non-empty array");
    anim.kind = Animation::Kind::Keyframes;
    for (std::size_t i = 0; i < k.size(); ++i) {
      const std::string wi = fmt::format("{}[{}]", w, i);
      rd.allowOnly(k[i], wi, {"time", "translate", "rotate", "scale"});
      if (!k[i].contains("time")) rd.fail(wi, "needs 'time' (seconds)");
      Keyframe f;
      f.time = rd.number(k[i]["time"], wi + ".time");
      f.transform = rd.transform(k[i], wi);
      if (!anim.keyframes.empty() && f.time <= anim.keyframes.back().time)
        rd.fail(wi + ".time", "keyframe times must increase");
      anim.keyframes.push_back(f);
    }
  }
  return anim;
}

/// nlohmann's DOM builder, told every key as it is read: it keeps the key path (for errors) and the keys each
/// open object has had (duplicates are errors: JSON leaves them undefined, and nlohmann would silently keep the
/// last). A SAX handler, not a parser callback: nlohmann's callback parser scans the whole parent container each
/// time an object ends, which made a scene with 1e6 keyframes take minutes (quadratic); this is linear.
/// sax_parse takes the handler by its type, so hiding the builder's (non-virtual) members is enough.
class TrackingDomParser : public nlohmann::detail::json_sax_dom_parser<json> {
  using Base = nlohmann::detail::json_sax_dom_parser<json>;

public:
  TrackingDomParser(json& doc, const Reader& rd) : Base(doc), mRd(rd) {}

  bool start_object(std::size_t n) { return open(false), Base::start_object(n); }
  bool start_array(std::size_t n) { return open(true), Base::start_array(n); }
  bool end_object() { return close(), Base::end_object(); }
  bool end_array() { return close(), Base::end_array(); }
  bool key(std::string& k) {
    if (!mOpen.empty()) {
      Level& top = mOpen.back();
      top.last.clear(); // the path names the object, not its previous key
      if (!top.keys.insert(k).second)
        mRd.fail(path(), fmt::format("the key '{}' appears twice in one object", oneLine(k, kQuoteChars)));
      top.last = k;
    }
    return Base::key(k);
  }

  /// The key path of the value being read ("meshes.s.sphere.radius", "instances[]"), each key cut short.
  std::string path() const {
    std::string p;
    for (const Level& l : mOpen) {
      if (l.array) p += "[]";
      else if (!l.last.empty()) p += (p.empty() ? "" : ".") + oneLine(l.last, kQuoteChars);
    }
    return p.empty() ? "scene" : p;
  }

private:
  struct Level {
    bool array;
    std::unordered_set<std::string> keys;
    std::string last;
  };
  void open(bool array) { mOpen.push_back({array, {}, {}}); }
  void close() {
    if (!mOpen.empty()) mOpen.pop_back();
  }
  const Reader& mRd;
  std::vector<Level> mOpen;
};

/// The scene file's top-level object, with its keys and format version checked.
json parseDocument(const Reader& rd, const std::string& text) {
  json doc;
  TrackingDomParser parser(doc, rd);
  try {
    json::sax_parse(text, &parser);
  } catch (const json::parse_error& e) {
    throw Error(fmt::format("{}: malformed JSON: {}", rd.file(), oneLine(e.what())));
  } catch (const json::exception& e) {
    // e.g. out_of_range.406, a number beyond double (1e999): name where it is.
    throw Error(fmt::format("{}: {}: unreadable value: {}", rd.file(), parser.path(), oneLine(e.what())));
  }
  rd.allowOnly(doc, "scene", {"rtsdf_scene", "meshes", "instances", "lights", "camera", "comment"});
  if (doc.contains("rtsdf_scene") && (!doc["rtsdf_scene"].is_number_integer() || doc["rtsdf_scene"].get<int>() != 1))
    rd.fail("rtsdf_scene", "unsupported scene format version (this build reads version 1)");
  return doc;
}

/// A "sphere" mesh: {"radius": r, "subdivisions": n}, the radius finite as a float, n in [0, 7] (default 4).
Mesh sphereMesh(const Reader& rd, const json& sp, const std::string& where, const std::string& name) {
  rd.allowOnly(sp, where, {"radius", "subdivisions"});
  if (!sp.contains("radius")) rd.fail(where, "needs 'radius'");
  const double radius = rd.positive(sp["radius"], where + ".radius");
  if (!std::isfinite(float(radius))) rd.fail(where + ".radius", "must be finite as a 32-bit float");
  int subdivisions = 4;
  if (sp.contains("subdivisions")) {
    const json& n = sp["subdivisions"];
    if (!n.is_number_integer() || n.get<long long>() < 0 || n.get<long long>() > 7)
      rd.fail(where + ".subdivisions", fmt::format("must be an integer in [0, 7] (got {})", n.dump()));
    subdivisions = n.get<int>();
  }
  return makeSphereMesh(float(radius), subdivisions, name);
}

/// Where a scene's mesh paths must lead (unless the load options allow more): the folder that holds the scene's
/// folder, so that the bundled layout (data/scenes/*.json naming ../meshes/*.obj) reads as it is.
fs::path meshRoot(const fs::path& base) {
  const fs::path folder = fs::absolute(base).lexically_normal();
  const fs::path above = (folder.has_filename() ? folder : folder.parent_path()).parent_path();
  return above.empty() ? folder : above;
}

/// Where the meshes of a scene are read from, and how.
struct MeshSource {
  fs::path base;          ///< the scene's folder: relative paths start here
  MeshLoadOptions options; ///< allowOutsideReferences lifts the check against meshRoot(base)
};

/// One entry of "meshes": read from its file (relative to the scene's folder) or generated, then validated into
/// @a report. Errors from the mesh reader and validation get the scene file and the mesh's key in front.
Mesh sceneMesh(const Reader& rd, const MeshSource& source, const std::string& name, const json& m,
               MeshReport& report) {
  const std::string w = "meshes." + oneLine(name, kQuoteChars);
  rd.allowOnly(m, w, {"path", "box", "sphere"});
  Mesh mesh;
  if (int(m.contains("path")) + int(m.contains("box")) + int(m.contains("sphere")) != 1)
    rd.fail(w, "needs exactly one of 'path', 'box' or 'sphere'");
  try {
    if (m.contains("path")) {
      const std::string reference = rd.string(m["path"], w + ".path");
      fs::path p = reference;
      if (p.is_relative()) p = source.base / p;
      if (!source.options.allowOutsideReferences) requireInsideFolder(rd.file(), reference, p, meshRoot(source.base));
      mesh = loadMeshFile(p, source.options);
    } else if (m.contains("box")) {
      mesh = makeBoxMesh(glm::vec3(rd.vec3(m["box"], w + ".box")), name);
    } else {
      mesh = sphereMesh(rd, m["sphere"], w + ".sphere", name);
    }
    mesh.name = name;
    report = validateMesh(mesh);
  } catch (const Error& e) {
    const std::string msg = e.what();
    if (msg.rfind(rd.file(), 0) == 0) throw; // already names the scene file
    rd.fail(w, msg);
  }
  return mesh;
}

/// "meshes" into scene.meshes and scene.meshReports.
/// @return each mesh's index by its name, for the instances.
std::map<std::string, std::size_t> parseMeshes(const Reader& rd, const json& doc, const MeshSource& source,
                                               Scene& scene) {
  std::map<std::string, std::size_t> meshIndex;
  if (!doc.contains("meshes") || !doc["meshes"].is_object() || doc["meshes"].empty())
    rd.fail("meshes", "a scene needs a non-empty 'meshes' object (name -> {\"path\": ...}, {\"box\": [x, y, z]} "
                      "or {\"sphere\": {\"radius\": r}})");
  for (const auto& [name, m] : doc["meshes"].items()) {
    MeshReport report;
    Mesh mesh = sceneMesh(rd, source, name, m, report);
    if (report.degenerateDropped)
      spdlog::warn("{} (mesh '{}'): dropped {} zero-area triangle(s) of {}", oneLine(mesh.source, 200),
                   oneLine(name, kQuoteChars), report.degenerateDropped, report.inputTriangles);
    meshIndex[name] = scene.meshes.size();
    scene.meshes.push_back(std::move(mesh));
    scene.meshReports.push_back(report);
  }
  return meshIndex;
}

/// "instances" into scene.instances: each names a mesh of @a meshIndex and has a unique name.
void parseInstances(const Reader& rd, const json& doc, const std::map<std::string, std::size_t>& meshIndex,
                    Scene& scene) {
  if (!doc.contains("instances") || !doc["instances"].is_array() || doc["instances"].empty())
    rd.fail("instances", "a scene needs a non-empty 'instances' array");
  std::unordered_set<std::string> names;
  for (std::size_t i = 0; i < doc["instances"].size(); ++i) {
    const json& in = doc["instances"][i];
    const std::string w = fmt::format("instances[{}]", i);
    rd.allowOnly(in, w, {"name", "mesh", "translate", "rotate", "scale", "animation"});
    Instance inst;
    if (!in.contains("mesh")) rd.fail(w, "needs 'mesh' (a key of 'meshes')");
    const std::string meshName = rd.string(in["mesh"], w + ".mesh");
    const auto it = meshIndex.find(meshName);
    if (it == meshIndex.end()) rd.fail(w + ".mesh", fmt::format("no mesh named '{}'", oneLine(meshName, kQuoteChars)));
    inst.mesh = it->second;
    inst.name = in.contains("name") ? rd.string(in["name"], w + ".name") : fmt::format("{}#{}", meshName, i);
    if (!names.insert(inst.name).second)
      rd.fail(w + ".name", fmt::format("duplicate instance name '{}'", oneLine(inst.name, kQuoteChars)));
    inst.transform = rd.transform(in, w);
    if (in.contains("animation")) inst.animation = parseAnimation(rd, in["animation"], w + ".animation");
    scene.instances.push_back(std::move(inst));
  }
}

/// Light @a i of "lights": a directional light (a sun) or a sphere light.
Light parseLight(const Reader& rd, const json& l, std::size_t i) {
  const std::string w = fmt::format("lights[{}]", i);
  rd.allowOnly(l, w, {"name", "type", "direction", "angular_radius_deg", "position", "radius", "color",
                      "intensity"});
  Light light;
  light.name = l.contains("name") ? rd.string(l["name"], w + ".name") : fmt::format("light{}", i);
  const std::string type = l.contains("type") ? rd.string(l["type"], w + ".type") : "";
  if (type == "directional") {
    light.type = Light::Type::Directional;
    if (!l.contains("direction")) rd.fail(w, "a directional light needs 'direction'");
    light.direction = rd.unit(l["direction"], w + ".direction");
    if (l.contains("angular_radius_deg")) {
      const double deg = rd.number(l["angular_radius_deg"], w + ".angular_radius_deg");
      if (deg < 0.0 || deg >= 90.0) rd.fail(w + ".angular_radius_deg", "must be in [0, 90)");
      light.angularRadius = glm::radians(deg);
    }
  } else if (type == "sphere") {
    light.type = Light::Type::Sphere;
    if (!l.contains("position")) rd.fail(w, "a sphere light needs 'position'");
    light.position = rd.vec3(l["position"], w + ".position");
    if (l.contains("radius")) {
      light.radius = rd.number(l["radius"], w + ".radius");
      if (light.radius < 0.0) rd.fail(w + ".radius", "must not be negative");
    }
  } else {
    rd.fail(w + ".type", "must be \"directional\" or \"sphere\"");
  }
  if (l.contains("color")) light.color = rd.vec3(l["color"], w + ".color");
  if (l.contains("intensity")) light.intensity = rd.number(l["intensity"], w + ".intensity");
  return light;
}

/// A vertical field of view in degrees at @a where, in (0, 180), as radians.
double fieldOfView(const Reader& rd, const json& v, const std::string& where) {
  const double f = rd.number(v, where);
  if (!(f > 0.0 && f < 180.0)) rd.fail(where, fmt::format("must be in (0, 180) (got {})", f));
  return glm::radians(f);
}

/// The least |a + s (b - a)| over s in [0, 1]: how close a linearly interpolated vector comes to zero.
double leastNormBetween(const glm::dvec3& a, const glm::dvec3& b) {
  const glm::dvec3 d = b - a;
  const double dd = glm::dot(d, d);
  const double s = dd > 0.0 ? std::clamp(-glm::dot(a, d) / dd, 0.0, 1.0) : 0.0;
  return glm::length(a + s * d);
}

/// "camera.keyframes": times that increase, each with a position and a point to look at. Between two keyframes the
/// view direction is interpolated linearly, so it must not pass through zero or along `up` there (the camera would
/// have no orientation at that moment).
std::vector<CameraKeyframe> parseCameraPath(const Reader& rd, const json& k, const Camera& camera) {
  if (!k.is_array() || k.empty()) rd.fail("camera.keyframes", "must be a non-empty array");
  std::vector<CameraKeyframe> path;
  for (std::size_t i = 0; i < k.size(); ++i) {
    const std::string w = fmt::format("camera.keyframes[{}]", i);
    rd.allowOnly(k[i], w, {"time", "position", "look_at", "fov_deg"});
    for (const char* key : {"time", "position", "look_at"})
      if (!k[i].contains(key)) rd.fail(w, fmt::format("needs '{}'", key));
    CameraKeyframe f;
    f.time = rd.number(k[i]["time"], w + ".time");
    if (!path.empty() && f.time <= path.back().time) rd.fail(w + ".time", "keyframe times must increase");
    f.position = rd.vec3(k[i]["position"], w + ".position");
    f.target = rd.vec3(k[i]["look_at"], w + ".look_at");
    f.verticalFov = k[i].contains("fov_deg") ? fieldOfView(rd, k[i]["fov_deg"], w + ".fov_deg") : camera.verticalFov;
    const glm::dvec3 view = f.target - f.position;
    if (glm::length(view) < 1e-12) rd.fail(w, "position and look_at must differ");
    if (glm::length(glm::cross(view, camera.up)) <= 1e-9 * glm::length(view))
      rd.fail(w, "the view direction is parallel to the camera's 'up'");
    if (!path.empty()) {
      const glm::dvec3 before = path.back().target - path.back().position;
      const double least = leastNormBetween(glm::cross(before, camera.up), glm::cross(view, camera.up));
      if (least <= 1e-9 * std::max(glm::length(before), glm::length(view)))
        rd.fail(w, fmt::format("between keyframes {} and {} the view direction passes through zero or along 'up'",
                               i - 1, i));
    }
    path.push_back(f);
  }
  return path;
}

/// "camera": a position and a point to look at (they must differ), or a path of keyframes; optionally up and the
/// vertical field of view (the keyframes' default).
Camera parseCamera(const Reader& rd, const json& c, std::vector<CameraKeyframe>& path) {
  Camera camera;
  rd.allowOnly(c, "camera", {"position", "look_at", "up", "fov_deg", "keyframes"});
  if (c.contains("up")) camera.up = rd.unit(c["up"], "camera.up");
  if (c.contains("fov_deg")) camera.verticalFov = fieldOfView(rd, c["fov_deg"], "camera.fov_deg");
  if (c.contains("keyframes")) {
    if (c.contains("position") || c.contains("look_at"))
      rd.fail("camera", "takes 'position' and 'look_at', or 'keyframes', not both");
    path = parseCameraPath(rd, c["keyframes"], camera);
    camera.position = path.front().position;
    camera.target = path.front().target;
    camera.verticalFov = path.front().verticalFov;
    return camera;
  }
  if (!c.contains("position") || !c.contains("look_at"))
    rd.fail("camera", "needs 'position' and 'look_at' (or 'keyframes')");
  camera.position = rd.vec3(c["position"], "camera.position");
  camera.target = rd.vec3(c["look_at"], "camera.look_at");
  if (glm::length(camera.target - camera.position) < 1e-12) rd.fail("camera", "position and look_at must differ");
  return camera;
}

} // namespace

Scene parseScene(const std::string& text, const fs::path& origin, const MeshLoadOptions& options) {
  const std::string file = origin.string();
  const Reader rd(file);
  const json doc = parseDocument(rd, text);

  Scene scene;
  scene.path = file;
  const MeshSource source{origin.has_parent_path() ? origin.parent_path() : fs::path("."), options};
  const std::map<std::string, std::size_t> meshIndex = parseMeshes(rd, doc, source, scene);
  parseInstances(rd, doc, meshIndex, scene);
  if (doc.contains("lights")) {
    if (!doc["lights"].is_array()) rd.fail("lights", "must be an array");
    for (std::size_t i = 0; i < doc["lights"].size(); ++i) scene.lights.push_back(parseLight(rd, doc["lights"][i], i));
  }
  if (doc.contains("camera")) {
    scene.camera = parseCamera(rd, doc["camera"], scene.cameraPath);
    scene.hasCamera = true;
  }
  return scene;
}

Scene loadScene(const fs::path& path, const MeshLoadOptions& options) {
  // A scene larger than this is not a scene description (meshes live in their own files).
  constexpr std::uint64_t kMaxSceneBytes = 64u << 20;
  if (path.extension() == ".json") return parseScene(readFileBytes(path, "scene file", kMaxSceneBytes), path, options);
  checkInputFile(path, "scene file");
  if (!isMeshFile(path))
    throw Error(fmt::format("{}: neither a .json scene nor a mesh format assimp reads", path.string()));
  return sceneFromMesh(loadMeshFile(path, options), path.string());
}

Scene sceneFromMesh(Mesh mesh, std::string path) {
  Scene scene;
  scene.path = std::move(path);
  MeshReport report = validateMesh(mesh);
  if (report.degenerateDropped)
    spdlog::warn("{}: dropped {} zero-area triangle(s) of {}", scene.path.empty() ? mesh.source : scene.path,
                 report.degenerateDropped, report.inputTriangles);
  Instance inst;
  inst.name = mesh.name;
  scene.meshes.push_back(std::move(mesh));
  scene.meshReports.push_back(report);
  scene.instances.push_back(inst);
  return scene;
}

} // namespace rtsdf
