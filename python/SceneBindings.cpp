// rtsdf.Scene, rtsdf.Mesh (triangles from arrays) and load_scene: what every call that takes a scene accepts.
#include "Bindings.h"

#include "scene/SceneLoader.h"

#include <fmt/format.h>
#include <pybind11/numpy.h>

#include <cmath>

namespace rtsdf::python {
namespace {

std::size_t triangleCount(const Scene& s) {
  std::size_t n = 0;
  for (const Instance& i : s.instances) n += s.meshes.at(i.mesh).triangles.size();
  return n;
}

std::string typeName(const py::handle& h) { return py::str(py::type::handle_of(h).attr("__name__")); }

/// @a value as a 2-D numpy array of @a columns columns whose dtype is of the @a kinds ("f", "iu").
py::array tableArgument(const py::handle& value, const char* argument, const char* kinds, const char* expected) {
  const py::array a = py::module_::import("numpy").attr("asarray")(value);
  const char kind = a.dtype().kind();
  if (std::string(kinds).find(kind) == std::string::npos || (kind == 'f' && a.itemsize() != 4 && a.itemsize() != 8))
    throw py::type_error(fmt::format("{}: dtype {} is not {}", argument, std::string(py::str(a.dtype())), expected));
  if (a.ndim() != 2 || a.shape(1) != 3 || a.shape(0) == 0) {
    std::string shape;
    for (py::ssize_t d = 0; d < a.ndim(); ++d) shape += (d ? ", " : "") + std::to_string(a.shape(d));
    throw py::value_error(fmt::format("{}: shape ({}) is not ({}, 3) with at least one row", argument, shape,
                                      argument[0] == 'v' ? "V" : "F"));
  }
  return a;
}

ArrayMesh makeMesh(const py::handle& vertices, const py::handle& faces, const std::string& name) {
  const auto v = py::array_t<double, py::array::c_style | py::array::forcecast>::ensure(
      tableArgument(vertices, "vertices", "f", "float32 or float64"));
  const auto f = py::array_t<std::int64_t, py::array::c_style | py::array::forcecast>::ensure(
      tableArgument(faces, "faces", "iu", "an integer type"));
  Mesh mesh;
  mesh.name = name;
  mesh.source = "<arrays>";
  const std::size_t nv = std::size_t(v.shape(0)), nf = std::size_t(f.shape(0));
  const double* p = v.data();
  for (std::size_t i = 0; i < 3 * nv; ++i)
    if (!std::isfinite(p[i]))
      throw py::value_error(fmt::format("vertices: row {} is not finite ({}, {}, {})", i / 3, p[i / 3 * 3],
                                        p[i / 3 * 3 + 1], p[i / 3 * 3 + 2]));
  mesh.positions.resize(nv);
  for (std::size_t i = 0; i < nv; ++i)
    mesh.positions[i] = glm::vec3(float(p[3 * i]), float(p[3 * i + 1]), float(p[3 * i + 2]));
  const std::int64_t* t = f.data();
  for (std::size_t i = 0; i < 3 * nf; ++i)
    if (t[i] < 0 || std::uint64_t(t[i]) >= nv)
      throw py::value_error(fmt::format("faces: row {} uses vertex {}, outside 0 .. {} (the vertices' rows)", i / 3,
                                        t[i], nv - 1));
  mesh.triangles.resize(nf);
  for (std::size_t i = 0; i < nf; ++i)
    mesh.triangles[i] = glm::uvec3(unsigned(t[3 * i]), unsigned(t[3 * i + 1]), unsigned(t[3 * i + 2]));
  ArrayMesh m;
  {
    py::gil_scoped_release release; // orientation repair of a large mesh takes a while
    m.scene = std::make_shared<const Scene>(sceneFromMesh(std::move(mesh)));
  }
  return m;
}

const Mesh& meshOf(const ArrayMesh& m) { return m.scene->meshes.front(); }
const MeshReport& reportOf(const ArrayMesh& m) { return m.scene->meshReports.front(); }

std::string meshRepr(const ArrayMesh& m) {
  const Mesh& mesh = meshOf(m);
  return fmt::format("rtsdf.Mesh('{}', {} vertices, {} triangles, {})", mesh.name, mesh.positions.size(),
                     mesh.triangles.size(), reportOf(m).watertight() ? "watertight" : "open");
}

std::string sceneRepr(const Scene& s) {
  return fmt::format("rtsdf.Scene('{}', {} mesh{}, {} instance{}, {} triangles, {} light{}{})", s.path,
                     s.meshes.size(), s.meshes.size() == 1 ? "" : "es", s.instances.size(),
                     s.instances.size() == 1 ? "" : "s", triangleCount(s), s.lights.size(),
                     s.lights.size() == 1 ? "" : "s", s.hasCamera ? ", camera" : "");
}

} // namespace

ScenePtr sceneOf(const py::handle& sceneOrPath, const char* argument) {
  if (py::isinstance<Scene>(sceneOrPath)) return sceneOrPath.cast<std::shared_ptr<Scene>>();
  if (py::isinstance<ArrayMesh>(sceneOrPath)) return sceneOrPath.cast<const ArrayMesh&>().scene;
  const py::module_ os = py::module_::import("os");
  if (py::isinstance<py::str>(sceneOrPath) || py::isinstance(sceneOrPath, os.attr("PathLike"))) {
    const std::string path = py::str(os.attr("fspath")(sceneOrPath));
    return std::make_shared<const Scene>(loadScene(path));
  }
  throw py::type_error(fmt::format("{}: expected an rtsdf.Scene, an rtsdf.Mesh or a path, not {} (arrays: "
                                   "rtsdf.Mesh(vertices, faces))", argument, typeName(sceneOrPath)));
}

void bindScenes(py::module_& m) {
  py::class_<Scene, std::shared_ptr<Scene>>(m, "Scene", "A scene loaded from a .json scene or a mesh file "
                                                        "(load_scene): meshes, instances, lights and a camera")
      .def_property_readonly("path", [](const Scene& s) { return s.path; }, "The file it was loaded from")
      .def_property_readonly("meshes", [](const Scene& s) { return s.meshes.size(); }, "Number of meshes")
      .def_property_readonly("instances", [](const Scene& s) { return s.instances.size(); },
                             "Number of mesh instances")
      .def_property_readonly("triangles", &triangleCount, "Triangles over all instances (after validation)")
      .def("__repr__", &sceneRepr);
  m.def("load_scene", [](const std::string& path) { return std::make_shared<Scene>(loadScene(path)); },
        py::arg("path"), "Load a scene (.json) or a mesh file (OBJ, PLY, STL, glTF ...); raises rtsdf.Error naming "
                         "the file and the problem");

  py::class_<ArrayMesh>(m, "Mesh", R"(A triangle mesh from arrays, accepted wherever a scene or mesh path is.

vertices: (V, 3) float32 or float64; faces: (F, 3) integers indexing the vertices' rows, counter-clockwise seen
from outside. Validated and repaired as a mesh file is: identical vertices welded, zero-area triangles dropped,
each connected piece oriented consistently and each closed piece turned outward. Coordinates are stored as
float32. Raises TypeError or ValueError naming the argument, rtsdf.Error when no triangle is left.)")
      .def(py::init(&makeMesh), py::arg("vertices"), py::arg("faces"), py::arg("name") = "mesh")
      .def_property_readonly("name", [](const ArrayMesh& a) { return meshOf(a).name; }, "Name used in messages")
      .def_property_readonly("vertices", [](const ArrayMesh& a) {
        const auto& p = meshOf(a).positions;
        py::array_t<float> out({py::ssize_t(p.size()), py::ssize_t(3)});
        std::copy_n(&p.front().x, 3 * p.size(), out.mutable_data());
        return out;
      }, "float32 (V, 3): the vertices after welding")
      .def_property_readonly("faces", [](const ArrayMesh& a) {
        const auto& t = meshOf(a).triangles;
        py::array_t<std::uint32_t> out({py::ssize_t(t.size()), py::ssize_t(3)});
        std::copy_n(&t.front().x, 3 * t.size(), out.mutable_data());
        return out;
      }, "uint32 (F, 3): the triangles kept, oriented by solid")
      .def_property_readonly("triangles", [](const ArrayMesh& a) { return meshOf(a).triangles.size(); },
                             "Number of triangles kept")
      .def_property_readonly("dropped_triangles", [](const ArrayMesh& a) { return reportOf(a).degenerateDropped; },
                             "Zero-area triangles dropped")
      .def_property_readonly("reoriented_triangles",
                             [](const ArrayMesh& a) { return reportOf(a).orientation.reorientedTriangles; },
                             "Triangles whose corner order the orientation repair reversed")
      .def_property_readonly("watertight", [](const ArrayMesh& a) { return reportOf(a).watertight(); },
                             "Closed, manifold and consistently oriented")
      .def("__repr__", &meshRepr);
}

} // namespace rtsdf::python
