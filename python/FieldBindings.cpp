// rtsdf.Field: a baked field as numpy arrays, sampled and differentiated at points, written as .vdb.
#include "Bindings.h"

#include "grid/GridSampling.h"
#include "grid/VdbIO.h"
#include "util/AtomicFile.h"

#include <fmt/format.h>
#include <pybind11/numpy.h>
#include <pybind11/stl/filesystem.h>

#include <algorithm>
#include <vector>

namespace rtsdf::python {
namespace {

/// An x-fastest (Fortran-order) array of the grid's shape.
template <class T> py::array_t<T> gridArray(const GridSpec& spec) {
  const std::vector<py::ssize_t> shape{spec.dims.x, spec.dims.y, spec.dims.z};
  const std::vector<py::ssize_t> strides{py::ssize_t(sizeof(T)), py::ssize_t(sizeof(T)) * spec.dims.x,
                                         py::ssize_t(sizeof(T)) * spec.dims.x * spec.dims.y};
  return py::array_t<T>(shape, strides);
}

py::array_t<float> values(const Field& f) {
  const std::vector<float> dense = levelSetToDense(*f.grid, f.spec);
  py::array_t<float> out = gridArray<float>(f.spec);
  std::copy(dense.begin(), dense.end(), out.mutable_data());
  return out;
}

py::array_t<bool> active(const Field& f) {
  py::array_t<bool> out = gridArray<bool>(f.spec);
  bool* on = out.mutable_data();
  std::fill_n(on, f.spec.voxelCount(), false);
  for (auto it = f.grid->cbeginValueOn(); it; ++it) {
    const openvdb::Coord c = it.getCoord();
    if (f.spec.contains({c.x(), c.y(), c.z()})) on[f.spec.linear(c.x(), c.y(), c.z())] = true;
  }
  return out;
}

/// Values (components 1) or gradients (3) at points of shape (..., 3), in the points' precision: float32 stays
/// float32, anything else is read as float64.
template <class Real>
py::array atPoints(const Field& f, const py::array& points, int components) {
  const auto p = py::array_t<Real, py::array::c_style | py::array::forcecast>::ensure(points);
  std::vector<py::ssize_t> shape(p.shape(), p.shape() + p.ndim());
  shape.back() = components;
  if (components == 1) shape.pop_back();
  py::array_t<Real> out(shape);
  const std::size_t n = std::size_t(p.size() / 3);
  {
    py::gil_scoped_release release;
    if (components == 1) sampleWorldPoints(*f.grid, p.data(), n, out.mutable_data());
    else gradientWorldPoints(*f.grid, p.data(), n, out.mutable_data());
  }
  return std::move(out);
}

py::array pointQuery(const Field& f, const py::handle& points, int components) {
  const py::array a = py::module_::import("numpy").attr("asarray")(points);
  if (a.ndim() < 1 || a.shape(a.ndim() - 1) != 3)
    throw py::value_error("points: the last axis must hold x, y, z (shape (..., 3))");
  if (a.dtype().kind() != 'f' && a.dtype().kind() != 'i' && a.dtype().kind() != 'u')
    throw py::type_error("points: dtype " + std::string(py::str(a.dtype())) + " is not a number type");
  if (a.dtype().kind() == 'f' && a.itemsize() == 4) return atPoints<float>(f, a, components);
  return atPoints<double>(f, a, components);
}

std::string fieldRepr(const Field& f) {
  return fmt::format("rtsdf.Field({}: {} x {} x {} voxels of {:g}, origin ({:g}, {:g}, {:g}), band {:g}, {} active)",
                     f.method, f.spec.dims.x, f.spec.dims.y, f.spec.dims.z, f.spec.voxelSize, f.spec.origin.x,
                     f.spec.origin.y, f.spec.origin.z, f.band, f.grid->activeVoxelCount());
}

void write(const Field& f, const std::filesystem::path& path, const py::object& up) {
  checkOutputPath(path, ".vdb");
  VdbWriteOptions o;
  o.up = up.is_none() ? f.up : parseEnum<UpAxis>(up.cast<std::string>());
  writeVdb(path, {f.grid}, o);
}

/// The level set of a .vdb that rtsdf wrote as a Field in its scene's frame: the grid named @a grid, else the
/// one candidate (as `rtsdf compare --grid`); the Field writes with the up axis it was read with.
Field read(const std::filesystem::path& path, const py::object& grid) {
  Field f;
  py::gil_scoped_release release;
  const openvdb::FloatGrid::Ptr read = readLevelSet(path, grid.is_none() ? std::string() : grid.cast<std::string>());
  f.up = upAxisOf(*read);
  f.grid = inSceneFrame(read);
  try {
    f.spec = gridSpecOf(*f.grid); // the voxels of the arrays
  } catch (const Error& e) {
    throw Error(fmt::format("{}: {}: rtsdf.read reads the level sets rtsdf writes (rtsdf.compare reads any)",
                            path.string(), e.what()));
  }
  f.band = double(f.grid->background());
  const std::string method = stringMeta(*f.grid, "rtsdf:method");
  f.method = method.empty() ? "file" : method;
  return f;
}

py::object toPyopenvdb(const Field& f) {
  // Through a file: pyopenvdb's grids are its own build's objects.
  const py::module_ vdb = py::module_::import("pyopenvdb");
  const py::module_ tempfile = py::module_::import("tempfile");
  const py::object dir = tempfile.attr("TemporaryDirectory")();
  const std::string path = py::str(dir.attr("name")).cast<std::string>() + "/field.vdb";
  writeVdb(path, {f.grid});
  py::object grid = vdb.attr("read")(path, f.grid->getName());
  dir.attr("cleanup")();
  return grid;
}

} // namespace

void bindFields(py::module_& m) {
  py::class_<Field>(m, "Field", "A baked signed distance field (negative inside) on a grid of cubic voxels: a "
                                "narrow band of active voxels, +-band elsewhere")
      .def_property_readonly("values", &values,
                             "float32 (nx, ny, nz), [i, j, k] = x, y, z; voxel (i, j, k)'s value at its centre, "
                             "origin + (i + 0.5, j + 0.5, k + 0.5) * voxel_size; +-band outside the band")
      .def_property_readonly("active", &active, "bool (nx, ny, nz): the narrow band's voxels")
      .def_property_readonly("shape", [](const Field& f) { return py::make_tuple(f.spec.dims.x, f.spec.dims.y,
                                                                                 f.spec.dims.z); },
                             "(nx, ny, nz): voxels along x, y, z")
      .def_property_readonly("origin", [](const Field& f) {
        return py::make_tuple(f.spec.origin.x, f.spec.origin.y, f.spec.origin.z); }, "World corner of voxel 0")
      .def_property_readonly("voxel_size", [](const Field& f) { return f.spec.voxelSize; }, "Edge of a voxel")
      .def_property_readonly("band", [](const Field& f) { return f.band; },
                             "Half-width of the narrow band: active voxels have |value| <= band")
      .def_property_readonly("method", [](const Field& f) { return f.method; },
                             "What made it: exact, openvdb, jfa, rtsdf or pipeline")
      .def("sample", [](const Field& f, const py::handle& p) { return pointQuery(f, p, 1); }, py::arg("points"),
           "Trilinear samples (OpenVDB's BoxSampler) at world points of shape (..., 3); shape (...). At a voxel "
           "centre the voxel's value; +-band where the eight voxels around a point are outside the band. float32 "
           "points give float32, others float64")
      .def("gradient", [](const Field& f, const py::handle& p) { return pointQuery(f, p, 3); }, py::arg("points"),
           "World-space gradient of the same trilinear interpolant (OpenVDB's BoxStencil) at points of shape "
           "(..., 3); shape (..., 3). 0 where the eight voxels around a point are outside the band; dtype as sample")
      .def("write", &write, py::arg("path"), py::arg("up") = py::none(),
           "Write the level set (grid 'surface') to a .vdb file; raises rtsdf.Error for another extension. up: "
           "'y' or 'z' (as the command line's --up: 'z' turns the file upright for Blender); None: the bake's up")
      .def("to_pyopenvdb", &toPyopenvdb, "The level set as a pyopenvdb.FloatGrid (needs pyopenvdb)")
      .def("__repr__", &fieldRepr);
  m.def("read", &read, py::arg("path"), py::kw_only(), py::arg("grid") = py::none(),
        "Read a level set rtsdf wrote (.vdb) as a Field in its scene's frame (a file written with up='z' is turned "
        "back; write() turns it again). grid: the grid's name (as `rtsdf compare --grid`); None: the one named "
        "'surface' or the only level set. Raises rtsdf.Error naming the file and listing its grids when there is "
        "no such grid, rtsdf.SettingError when several could be meant");
}

} // namespace rtsdf::python
