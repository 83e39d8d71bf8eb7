// The native calls of the package's batch and tiled bakes (rtsdf.batch): a worker's thread count, the tiles of
// one scene's exact bake, their merge, and the comparison of two level sets. Each binds one library call.
#include "Bindings.h"
#include "grid/VdbIO.h"
#include "jobs/TileBake.h"
#include "scene/SceneLoader.h"
#include "util/EnumNames.h"
#include "util/Knobs.h"

#include <pybind11/pybind11.h>
#include <pybind11/stl.h>
#include <pybind11/stl/filesystem.h>
#include <tbb/global_control.h>

#include <memory>
#include <string>
#include <vector>

namespace py = pybind11;
using namespace rtsdf;

namespace {

TileBakeOptions tileOptions(const std::string& scene, int tile, int tiles, int res, const py::object& band,
                            const py::kwargs& kw) {
  TileBakeOptions o;
  o.bake.scene = scene;
  if (!band.is_none()) o.bake.pipeline.band = python::lengthOf(band);
  setOutputResolution(o.bake, res); // as rtsdf.bake sets it
  o.tile = tile;
  o.tiles = tiles;
  for (const auto& [key, value] : kw) {
    const std::string k = py::str(key);
    const python::SetFromPython set{value};
    if (!visitKnobByKeyword(o.bake.pipeline, k, set) && !visitKnobByKeyword(o.bake, k, set))
      throw py::type_error("unknown setting '" + k + "'");
  }
  return o;
}

py::dict bakeTileToFile(const std::string& scene, const std::filesystem::path& output, int tile, int tiles, int res,
                        const py::object& band, const py::kwargs& kw) {
  const TileBakeOptions o = tileOptions(scene, tile, tiles, res, band, kw);
  BakeResult r;
  std::size_t triangles = 0;
  {
    py::gil_scoped_release release;
    const Scene loaded = loadScene(scene);
    for (const Instance& i : loaded.instances) triangles += loaded.meshes.at(i.mesh).triangles.size();
    r = bakeTile(loaded, o);
    writeVdb(output, {r.grid});
  }
  py::dict d;
  d["active_voxels"] = r.grid->activeVoxelCount();
  d["triangles"] = triangles;
  d["seconds"] = r.seconds;
  return d;
}

py::dict mergeTileBytes(const std::vector<py::bytes>& tiles, const std::filesystem::path& output) {
  std::vector<std::string> blobs(tiles.begin(), tiles.end());
  openvdb::FloatGrid::Ptr merged;
  {
    py::gil_scoped_release release;
    std::vector<openvdb::FloatGrid::Ptr> grids;
    for (std::size_t i = 0; i < blobs.size(); ++i) {
      const openvdb::GridPtrVec read = readVdbBytes(blobs[i], "tile " + std::to_string(i));
      auto grid = read.empty() ? nullptr : openvdb::gridPtrCast<openvdb::FloatGrid>(read.front());
      if (!grid) throw Error("tile " + std::to_string(i) + ": no float grid");
      grids.push_back(grid);
    }
    merged = mergeTiles(grids);
    writeVdb(output, {merged});
  }
  py::dict d;
  d["active_voxels"] = merged->activeVoxelCount();
  return d;
}

std::uint64_t differentValues(const std::filesystem::path& a, const std::filesystem::path& b) {
  py::gil_scoped_release release;
  return countDifferentValues(*readLevelSet(a), *readLevelSet(b));
}

} // namespace

void bindBatch(py::module_& m) {
  m.def("set_threads", [](int threads) {
    // One limit per process (a batch worker's thread count); a new one replaces the last.
    static std::unique_ptr<tbb::global_control> limit;
    limit.reset();
    if (threads > 0)
      limit = std::make_unique<tbb::global_control>(tbb::global_control::max_allowed_parallelism, std::size_t(threads));
  }, py::arg("threads"), "Let the library's parallel loops use at most this many threads (0: no limit)");
  m.def("bake_tile", &bakeTileToFile, py::arg("scene"), py::arg("output"), py::arg("tile"), py::arg("tiles"),
        py::arg("res") = 128, py::arg("band") = py::none(),
        "Bake tile `tile` of `tiles` of the scene's exact bake (the whole bake's settings as keywords, as bake's) to "
        "a .vdb holding that tile's leaves; returns its active voxels, triangles and seconds");
  m.def("merge_tiles", &mergeTileBytes, py::arg("tiles"), py::arg("output"),
        "Merge the .vdb bytes of every tile of one bake (bake_tile) into one level set written to `output`, equal "
        "to the whole bake voxel for voxel; returns its active voxels");
  m.def("count_different_values", &differentValues, py::arg("a"), py::arg("b"),
        "Voxels and tiles where the level sets of two .vdb files differ in value or active state (0: the same)");
}
