#pragma once
/// @file SceneLoader.h
/// @brief Loading scenes: the JSON scene format (docs/scene-format.md) or a single mesh file.
#include "scene/MeshIO.h"
#include "scene/Scene.h"

#include <filesystem>
#include <string>

namespace rtsdf {

/// @brief Load a scene from a .json scene file, or wrap a mesh file (.obj, .ply, .stl, .gltf, ...) as a
///        one-instance scene.
/// @param path the scene or mesh file; mesh paths inside a scene are relative to the scene's folder.
/// @param options whether referenced files may lie outside their referrer's folder. By default a scene's mesh
///        paths must resolve inside the folder that holds the scene's folder (the bundled layout: scenes/ next
///        to meshes/), and a mesh's own references (glTF buffers, OBJ material libraries) inside the mesh's folder.
/// @throw Error naming the file and the problem (missing file, malformed JSON, unknown keys, bad values,
///        invalid meshes, a reference that leads outside its folder).
/// @note Every mesh is validated (validateMesh); what was dropped is logged and kept in Scene::meshReports.
Scene loadScene(const std::filesystem::path& path, const MeshLoadOptions& options = {});

/// @brief Wrap a mesh held in memory (built by a program, or arrays handed over by a caller) as a one-instance
///        scene, validated and oriented exactly as a mesh file's (validateMesh, repairOrientation).
/// @param mesh the mesh; its name and source name it in messages (a source in angle brackets, "<arrays>", marks
///        it as no file: a bake's output may then take any name).
/// @param path what Scene::path records (empty for none).
/// @throw Error as validateMesh (non-finite or huge coordinates, an index out of range, no triangle left).
Scene sceneFromMesh(Mesh mesh, std::string path = {});

/// @brief Parse a scene from JSON text; @a origin names it in messages and anchors relative mesh paths.
Scene parseScene(const std::string& jsonText, const std::filesystem::path& origin,
                 const MeshLoadOptions& options = {});

} // namespace rtsdf
