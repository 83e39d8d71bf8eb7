#include "jobs/Compare.h"

#include "grid/VdbIO.h"
#include "util/Error.h"

#include <fmt/format.h>

namespace rtsdf {

FileComparison compareFiles(const std::filesystem::path& pa, const std::filesystem::path& pb) {
  const auto a = readLevelSet(pa);
  const auto b = readLevelSet(pb);
  FileComparison c;
  try {
    c.error = compareFields(*a, *b);
  } catch (const Error& err) {
    throw Error(fmt::format("{} vs {}: {}", pa.string(), pb.string(), err.what()));
  }
  c.activeA = a->activeVoxelCount();
  c.activeB = b->activeVoxelCount();
  c.voxelSize = a->voxelSize()[0];
  return c;
}

std::string FileComparison::report(const std::filesystem::path& a, const std::filesystem::path& b) const {
  const FieldError& e = error;
  std::string t = fmt::format("A          {} ({} active voxels)\n", a.string(), activeA);
  t += fmt::format("B          {} ({} active voxels)\n", b.string(), activeB);
  t += fmt::format("voxel size {}\n", voxelSize);
  t += fmt::format("compared   {} voxels active in both ({} only in A, {} only in B)\n", e.voxels, e.onlyInA,
                   e.onlyInB);
  t += fmt::format("|A - B|    mean {:.4f}, RMS {:.4f}, max {:.4f} voxels\n", e.meanAbs, e.rms, e.maxAbs);
  t += fmt::format("sign       {} voxels disagree ({:.4f}%)\n", e.signMismatches, 100.0 * e.signErrorRate());
  return t;
}

} // namespace rtsdf
