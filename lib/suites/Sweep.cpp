#include "suites/Sweep.h"

#include "util/Error.h"

#include <fmt/format.h>

#include <algorithm>
#include <cmath>
#include <map>
#include <tuple>

namespace rtsdf::bench {
namespace {

struct Size {
  const char* name;
  int coarse, fine;
};
constexpr Size kXS{"XS", 32, 64}, kS{"S", 64, 128}, kM{"M", 128, 256}, kL{"L", 256, 512};

SweepPoint point(SweepGroup g, const Size& size, RefineMode mode, int rays, double band, double alpha, int frames) {
  SweepPoint p;
  p.group = g;
  p.size = size.name;
  p.pipeline.coarseRes = size.coarse;
  p.pipeline.fineRes = size.fine;
  p.pipeline.mode = mode;
  p.pipeline.rays = rays;
  p.pipeline.band = band;
  p.pipeline.alpha = alpha;
  // The sweep measures the paper's knobs on the paper's frame: every masked voxel refined every frame (the
  // incremental frame, whose static frames refine almost nothing, is the frame suite's).
  p.pipeline.fullRecompute = true;
  p.frames = frames;
  return p;
}

/// The values a preset sweeps per knob, and the size and rays the knob tables (band, alpha, frames, JFA, dynamic)
/// run at.
struct PresetKnobs {
  std::vector<int> xs, bandXs;
  std::vector<double> bands, alphas;
  std::vector<int> frameCounts, storageFine{128, 256, 512};
  Size knobSize = kS;
  int dynamicFrames = 16, knobX = 5;
};

/// Quick: tiny grids, a few values per knob; Default: the full knobs at size S; Paper: more rays, knobs at M.
PresetKnobs presetKnobs(SweepPreset preset) {
  PresetKnobs k;
  switch (preset) {
  case SweepPreset::Quick:
    k.xs = {0, 1, 4};
    k.bands = {0.02, 0.1};
    k.bandXs = {1};
    k.alphas = {0.0, 1.0};
    k.frameCounts = {1, 4};
    k.knobSize = kXS;
    k.knobX = 1;
    k.dynamicFrames = 4;
    k.storageFine = {32, 64};
    break;
  case SweepPreset::Default:
    k.xs = {0, 1, 5, 10};
    k.bands = {0.01, 0.05, 0.1, 0.5};
    k.bandXs = {1, 5};
    k.alphas = {0.0, 0.5, 0.9, 0.95, 1.0};
    k.frameCounts = {1, 2, 4, 8, 16};
    break;
  case SweepPreset::Paper:
    k.xs = {0, 1, 5, 10};
    k.bands = {0.01, 0.05, 0.1, 0.5};
    k.bandXs = {1, 5, 10, 15};
    k.alphas = {0.0, 0.5, 0.9, 0.95, 1.0};
    k.frameCounts = {1, 2, 4, 8, 16};
    k.knobSize = kM;
    break;
  }
  return k;
}

/// Numbers for tables: empty when not measured.
std::string num(double v, int digits) { return std::isfinite(v) ? fmt::format("{:.{}f}", v, digits) : ""; }
std::string pct(double v) { return std::isfinite(v) ? fmt::format("{:.3f}%", 100.0 * v) : ""; }
std::string err(const SweepRecord& r) {
  if (!r.ok()) return "failed: " + r.note;
  return fmt::format("{} / {} / {}", num(r.meanAbs, 3), num(r.rms, 3), num(r.maxAbs, 2));
}
std::string shadow(const SweepRecord& r) {
  return std::isfinite(r.shadowRmse) ? fmt::format("{} / {}", num(r.shadowRmse, 4), num(r.shadowFlip, 4)) : "";
}
std::string peak(const SweepRecord& r) {
  if (!std::isfinite(r.peakMiB)) return "";
  return std::isfinite(r.peakGrowthMiB) ? fmt::format("{:.0f} (+{:.0f})", r.peakMiB, r.peakGrowthMiB)
                                        : fmt::format("{:.0f}", r.peakMiB);
}
std::string band(const SweepPoint& p) { return p.bruteForce ? "inf" : fmt::format("{:g}", double(p.pipeline.band)); }
std::string quoted(const std::string& s) {
  std::string q = "\"";
  for (char c : s) q += c == '"' ? std::string("\"\"") : std::string(1, c);
  return q + "\"";
}

} // namespace

std::string SweepPoint::label() const {
  if (group == SweepGroup::Storage)
    return storageBandVoxels > 0 ? fmt::format("storage fine {} band {:g} voxels", pipeline.fineRes, storageBandVoxels)
                                 : fmt::format("storage fine {} band d", pipeline.fineRes);
  if (anchor != AnchorKind::None) return fmt::format("{} {} fine {}", size, toString(anchor), pipeline.fineRes);
  std::string s = fmt::format("{} {}", size, toString(pipeline.mode));
  if (pipeline.mode == RefineMode::Rays) s += fmt::format(" x={}", pipeline.rays);
  s += fmt::format(" d={}", band(*this));
  if (group == SweepGroup::Alpha || group == SweepGroup::Dynamic) s += fmt::format(" alpha={:g}", pipeline.alpha);
  if (group == SweepGroup::Frames || group == SweepGroup::Alpha || group == SweepGroup::Dynamic)
    s += fmt::format(" frames={}", frames);
  if (group == SweepGroup::Jfa) s += fmt::format(" {}", toString(pipeline.coarseMethod));
  return s;
}

double SweepPoint::estimatedCost(int repeats) const {
  const double voxels = std::pow(double(pipeline.fineRes) / 64.0, 3.0);
  if (group == SweepGroup::Storage) return 4.0 * voxels;
  if (anchor != AnchorKind::None) return 2.0 * (repeats + 1) * voxels;
  const double work = pipeline.mode == RefineMode::Closest ? 3.0 : 1.0 + pipeline.rays;
  const double maskShare = bruteForce ? 1.0 : std::min(1.0, 0.3 + 2.0 * pipeline.band);
  // Every point also pays the exact reference for its error (every frame for Dynamic points).
  const int run = group == SweepGroup::Dynamic ? frames : std::max(frames, repeats + 1);
  return voxels * (run * (0.5 + work * maskShare) + (group == SweepGroup::Dynamic ? 2.0 * frames : 2.0));
}

double bruteForceBand(double sceneExtent) { return 4.0 * std::max(sceneExtent, 1e-6); }

std::vector<SweepPoint> makeSweepPlan(SweepPreset preset, bool animated, double sceneExtent) {
  std::vector<SweepPoint> plan;
  const RefineMode R = RefineMode::Rays, C = RefineMode::Closest;
  const double d = 0.1, a = 0.95;
  // Built in place: assigning brace lists of Size trips a GCC 12 -Wnonnull false positive.
  const std::vector<Size> sizes = preset == SweepPreset::Quick     ? std::vector<Size>{kXS}
                                  : preset == SweepPreset::Default ? std::vector<Size>{kS, kM}
                                                                   : std::vector<Size>{kS, kM, kL};
  const PresetKnobs k = presetKnobs(preset);
  for (const Size& s : sizes) {
    for (int x : k.xs) plan.push_back(point(SweepGroup::Sizes, s, R, x, d, a, 2));
    plan.push_back(point(SweepGroup::Sizes, s, C, 0, d, a, 2));
  }
  for (const Size& s : sizes)
    for (AnchorKind kind : {AnchorKind::OpenVdb, AnchorKind::Exact}) {
      SweepPoint p = point(SweepGroup::Anchor, s, C, 0, d, a, 1);
      p.anchor = kind;
      plan.push_back(p);
    }
  for (int x : k.bandXs) {
    for (double b : k.bands) plan.push_back(point(SweepGroup::Band, k.knobSize, R, x, b, a, 2));
    SweepPoint p = point(SweepGroup::Band, k.knobSize, R, x, bruteForceBand(sceneExtent), a, 2);
    p.bruteForce = true;
    plan.push_back(p);
  }
  for (double al : k.alphas) plan.push_back(point(SweepGroup::Alpha, k.knobSize, R, 1, d, al, 8));
  for (int f : k.frameCounts) plan.push_back(point(SweepGroup::Frames, k.knobSize, R, 1, d, a, f));
  for (CoarseMethod v : {CoarseMethod::Edt, CoarseMethod::Jfa, CoarseMethod::OnePlusJfa, CoarseMethod::JfaPlusTwo}) {
    SweepPoint p = point(SweepGroup::Jfa, k.knobSize, R, k.knobX, d, a, 2);
    p.pipeline.coarseMethod = v;
    plan.push_back(p);
  }
  if (animated) {
    for (double al : {0.5, 0.95})
      plan.push_back(point(SweepGroup::Dynamic, k.knobSize, R, k.knobX, d, al, k.dynamicFrames));
    plan.push_back(point(SweepGroup::Dynamic, k.knobSize, C, 0, d, a, k.dynamicFrames));
  }
  for (double voxels : {0.0, 3.0})
    for (int fine : k.storageFine) {
      SweepPoint p = point(SweepGroup::Storage, Size{"", fine / 2, fine}, C, 0, d, a, 1);
      p.size = fmt::format("{}", fine);
      p.storageBandVoxels = voxels;
      plan.push_back(p);
    }
  return plan;
}

std::string csvHeader() {
  return "group,label,size,anchor,coarse,fine,mode,coarse_method,rays,band,alpha,frames,frame,time,mask_voxels,voxelize_ms,"
         "transform_ms,distance_ms,host_ms,upsample_ms,refine_ms,frame_ms,mean_abs_vox,rms_vox,max_abs_vox,"
         "sign_error_rate,error_voxels,shadow_rmse,shadow_penumbra_rmse,shadow_flip,storage_band_voxels,vdb_bytes,dense_bytes,peak_mib,peak_growth_mib,note";
}

std::string csvRow(const SweepRecord& r) {
  const SweepPoint& p = r.point;
  auto g = [](double v) { return std::isfinite(v) ? fmt::format("{:.6g}", v) : std::string(); };
  return fmt::format("{},{},{},{},{},{},{},{},{},{},{},{},{},{},{},{},{},{},{},{},{},{},{},{},{},{},{},{},{},{},{},{},{},{},{},{}",
                     toString(p.group), quoted(p.label()), p.size, quoted(toString(p.anchor)), p.pipeline.coarseRes,
                     p.pipeline.fineRes, toString(p.pipeline.mode), toString(p.pipeline.coarseMethod), p.pipeline.rays,
                     p.bruteForce ? "inf" : g(p.pipeline.band), g(p.pipeline.alpha), p.frames, r.frame, g(r.time),
                     r.maskVoxels, g(r.voxelizeMs), g(r.transformMs), g(r.distanceMs), g(r.hostMs), g(r.upsampleMs),
                     g(r.refineMs), g(r.frameMs), g(r.meanAbs), g(r.rms), g(r.maxAbs), g(r.signErrorRate),
                     r.errorVoxels, g(r.shadowRmse), g(r.shadowPenumbraRmse), g(r.shadowFlip),
                     p.storageBandVoxels > 0 ? g(p.storageBandVoxels) : std::string(), r.vdbBytes, r.denseBytes, g(r.peakMiB),
                     g(r.peakGrowthMiB), quoted(r.note));
}

std::vector<std::size_t> paretoFront(const std::vector<SweepRecord>& records, double maxSignErrorRate) {
  std::vector<std::size_t> cand;
  for (std::size_t i = 0; i < records.size(); ++i) {
    const SweepRecord& r = records[i];
    if (!r.ok() || r.point.anchor != AnchorKind::None || r.point.group == SweepGroup::Storage ||
        r.point.group == SweepGroup::Dynamic || r.errorVoxels == 0 || !std::isfinite(r.meanAbs) ||
        !std::isfinite(r.frameMs) || !(r.signErrorRate <= maxSignErrorRate))
      continue;
    cand.push_back(i);
  }
  std::vector<std::size_t> front;
  for (std::size_t i : cand) {
    const SweepRecord& a = records[i];
    bool dominated = false;
    for (std::size_t j : cand) {
      const SweepRecord& b = records[j];
      if (j == i) continue;
      const bool noWorse = b.frameMs <= a.frameMs && b.meanAbs <= a.meanAbs;
      const bool better = b.frameMs < a.frameMs || b.meanAbs < a.meanAbs;
      // Exact ties: keep the first of equal points only.
      if (noWorse && (better || j < i)) { dominated = true; break; }
    }
    if (!dominated) front.push_back(i);
  }
  std::sort(front.begin(), front.end(), [&](std::size_t x, std::size_t y) {
    return std::tie(records[x].frameMs, records[x].meanAbs) < std::tie(records[y].frameMs, records[y].meanAbs);
  });
  return front;
}

namespace {

using RecordList = std::vector<const SweepRecord*>;

/// The records of group @a g, in the order they ran.
RecordList ofGroup(const std::vector<SweepRecord>& rs, SweepGroup g) {
  RecordList v;
  for (const SweepRecord& r : rs)
    if (r.point.group == g) v.push_back(&r);
  return v;
}

/// The title, what ran where, how each column is measured, and the plots.
std::string reportHeader(const SweepContext& c, const std::vector<SweepRecord>& rs) {
  std::string md;
  md += fmt::format("# rtsdf bench sweep: {}\n\n", c.scene);
  md += fmt::format("- Command: `{}`\n- Machine: {}\n- Vulkan device: {}\n- Date: {}\n- Sweep: {} ({} of {} points "
                    "finished{})\n",
                    c.command, c.machine, c.device, c.date, toString(c.preset),
                    std::count_if(rs.begin(), rs.end(),
                                  [](const SweepRecord& r) {
                                    return r.point.group != SweepGroup::Dynamic || r.frame + 1 == r.point.frames ||
                                           !r.ok();
                                  }),
                    c.planned, c.interrupted ? ", INTERRUPTED: the tables hold the points finished before Ctrl-C" : "");
  md += fmt::format(
      "- Times: GPU timestamps per pass, median over at least {} frames after a warm-up frame (a point with fewer "
      "frames runs more after its error is measured, for timing only; a moving scene's frames are timed one by one); "
      "`host` is the CPU time of a frame outside its wait for the GPU (the ray mask is compacted on the GPU); `frame` "
      "= GPU passes + host. Anchors: CPU "
      "wall time, median of as many runs.\n"
      "- Field error: |fine - exact| in fine voxels (mean / RMS / max) and the rate of wrong signs, after the "
      "point's last frame, over every fine voxel with |exact| <= {:g} scene units.\n",
      c.repeats, c.errorBand);
  if (c.shadowWidth > 0)
    md += fmt::format("- Shadow error: SDF soft shadows of the scene camera at {}x{} against the ray-traced truth "
                      "({} samples per pixel): visibility RMSE over lit surfaces / mean LDR-FLIP.\n",
                      c.shadowWidth, c.shadowHeight, c.truthSamples);
  md += "- Peak MiB: the process's peak resident memory while the point ran (host and, on a CPU Vulkan driver, "
        "device), and in brackets how far it rose above the resident memory at the point's start (freed memory is "
        "returned to the system first, and the exact field a point is measured against is built before it "
        "starts).\n\n";
  for (const std::string& p : c.plots) md += fmt::format("![{}]({})\n", p, p);
  if (!c.plots.empty()) md += "\n";
  return md;
}

/// The paper's pass durations and sizes x rays in one table.
std::string sizesTable(const RecordList& v) {
  std::string md = "## Pass durations and sizes x rays (d = 0.1, alpha = 0.95, 1+JFA, 2 frames)\n\n";
  md += "| size | coarse/fine | mode | x | mask voxels | voxelize | transform | distance | host (CPU) | upsample | "
        "refine | frame (ms) | mean / RMS / max error | wrong sign | shadow RMSE / FLIP | peak MiB |\n";
  md += "|---|---|---|---|---|---|---|---|---|---|---|---|---|---|---|---|\n";
  for (const SweepRecord* r : v)
    md += fmt::format("| {} | {}/{} | {} | {} | {} | {} | {} | {} | {} | {} | {} | **{}** | {} | {} | {} | {} |\n",
                      r->point.size, r->point.pipeline.coarseRes, r->point.pipeline.fineRes,
                      toString(r->point.pipeline.mode),
                      r->point.pipeline.mode == RefineMode::Rays ? fmt::format("{}", r->point.pipeline.rays) : "-",
                      r->maskVoxels, num(r->voxelizeMs, 2), num(r->transformMs, 2), num(r->distanceMs, 2),
                      num(r->hostMs, 2), num(r->upsampleMs, 2), num(r->refineMs, 2), num(r->frameMs, 1), err(*r),
                      pct(r->signErrorRate), shadow(*r), peak(*r));
  return md + "\n";
}

/// The frame time of the first Sizes point of anchor @a a's size with refinement @a m (and x = @a x rays) over
/// the anchor's time; empty when there is none or either failed.
std::string anchorRatio(const std::vector<SweepRecord>& rs, const SweepRecord& a, RefineMode m, int x) {
  for (const SweepRecord& r : rs)
    if (r.point.group == SweepGroup::Sizes && r.ok() && r.point.size == a.point.size && r.point.pipeline.mode == m &&
        (m == RefineMode::Closest || r.point.pipeline.rays == x) && a.ok() && a.frameMs > 0.0)
      return fmt::format("{:.3f}", r.frameMs / a.frameMs);
  return "";
}

/// Anchors, with the pipeline's closest-point and x = 1 frames at the same fine resolution beside them.
std::string anchorsTable(const RecordList& v, const std::vector<SweepRecord>& rs) {
  std::string md =
      fmt::format("## Anchors at the same fine voxels and band (d = {:g})\n\n", double(v.front()->point.pipeline.band));
  md += "| fine | anchor | time (ms) | mean / RMS / max error | wrong sign | peak MiB | rtsdf closest frame / anchor "
        "| rtsdf rays x=1 frame / anchor |\n|---|---|---|---|---|---|---|---|\n";
  for (const SweepRecord* a : v)
    md += fmt::format("| {} | {} | {} | {} | {} | {} | {} | {} |\n", a->point.pipeline.fineRes,
                      toString(a->point.anchor), num(a->frameMs, 1), err(*a), pct(a->signErrorRate), peak(*a),
                      anchorRatio(rs, *a, RefineMode::Closest, 0), anchorRatio(rs, *a, RefineMode::Rays, 1));
  return md + "\n";
}

/// Band d x rays at the knob size, d = inf (brute force) included.
std::string bandTable(const RecordList& v) {
  std::string md = fmt::format("## Band d x rays at size {} (alpha = 0.95, 2 frames; d = inf is brute-force ray "
                               "sampling of every voxel)\n\n",
                               v.front()->point.size);
  md += "The grid is padded by min(d, extent / 4) to keep the band inside it: d changes the grid's size, not its "
        "voxel h (the unit of the error).\n\n";
  md += "| d | x | fine voxel h | mask voxels | refine (ms) | frame (ms) | mean / RMS / max error | wrong sign | "
        "shadow RMSE / FLIP | peak MiB |\n|---|---|---|---|---|---|---|---|---|---|\n";
  for (const SweepRecord* r : v)
    md += fmt::format("| {} | {} | {} | {} | {} | {} | {} | {} | {} | {} |\n", band(r->point), r->point.pipeline.rays,
                      r->voxelSize > 0.0 ? fmt::format("{:.4g}", r->voxelSize) : "",
                      r->maskVoxels, num(r->refineMs, 1), num(r->frameMs, 1), err(*r), pct(r->signErrorRate),
                      shadow(*r), peak(*r));
  return md + "\n";
}

/// One knob's table (alpha, frames or JFA variant): @a value gives the knob's cell of a record.
template <class Value>
std::string knobTable(const RecordList& v, const std::string& title, const std::string& column, Value value) {
  std::string md = fmt::format("## {} at size {}\n\n", title, v.front()->point.size);
  md += fmt::format("| {} | mode | x | frames | transform (ms) | frame (ms) | mean / RMS / max error | wrong sign | "
                    "shadow RMSE / FLIP | peak MiB |\n|---|---|---|---|---|---|---|---|---|---|\n",
                    column);
  for (const SweepRecord* r : v)
    md += fmt::format("| {} | {} | {} | {} | {} | {} | {} | {} | {} | {} |\n", value(*r),
                      toString(r->point.pipeline.mode), r->point.pipeline.rays, r->point.frames,
                      num(r->transformMs, 2), num(r->frameMs, 1), err(*r), pct(r->signErrorRate), shadow(*r),
                      peak(*r));
  return md + "\n";
}

/// One row of the dynamic table: series @a k's frames @a s summed up (or why its last frame failed).
std::string dynamicSeriesRow(const std::string& k, const RecordList& s) {
  if (!s.back()->ok())
    return fmt::format("| {} | {} | failed: {} | | | | |\n", k, s.back()->point.frames, s.back()->note);
  double sum = 0.0, worst = 0.0;
  int n = 0;
  for (const SweepRecord* r : s)
    if (std::isfinite(r->meanAbs)) sum += r->meanAbs, worst = std::max(worst, r->meanAbs), ++n;
  const SweepRecord* last = s.back();
  return fmt::format("| {} | {} | {} | {} | {} / {} | {} | {} |\n", k, s.size(), num(last->frameMs, 1),
                     n ? num(sum / n, 3) : "", num(last->meanAbs, 3), num(last->maxAbs, 2), n ? num(worst, 3) : "",
                     pct(last->signErrorRate));
}

/// The dynamic scene: one row per series (a point's label), in the order the series first ran.
std::string dynamicTable(const RecordList& v) {
  std::string md = fmt::format(
      "## Dynamic scene at size {}: error against the exact field of the same moment, per frame\n\n",
      v.front()->point.size);
  md += "| series | frames | frame (ms, median) | mean error over frames | last frame mean / max | worst frame mean | "
        "wrong sign (last) |\n|---|---|---|---|---|---|---|\n";
  std::map<std::string, RecordList> series;
  std::vector<std::string> order;
  for (const SweepRecord* r : v) {
    const std::string k = r->point.label();
    if (!series.count(k)) order.push_back(k);
    series[k].push_back(r);
  }
  for (const std::string& k : order) md += dynamicSeriesRow(k, series[k]);
  return md + "\n";
}

/// Storage of the band as a sparse .vdb against a dense grid, with each resolution's growth over the previous one.
std::string storageTable(const RecordList& v, double errorBand) {
  std::string md = "## Storage: the band as a sparse .vdb vs a dense grid (exact field, float, blosc)\n\n";
  md += "A band of fixed width in voxels (3, OpenVDB's default) grows with the surface's area: x4 per doubling of "
        "the resolution, where a dense grid grows x8. The ray-mask band d is fixed in scene units, so it gets "
        "thicker in voxels as they shrink; it stays the same share of the box.\n\n";
  md += "| fine | band | grid | active voxels | growth vs previous | .vdb size (MiB) | dense float grid (MiB) | .vdb / "
        "dense | peak MiB |\n|---|---|---|---|---|---|---|---|---|\n";
  const SweepRecord* prev = nullptr;
  for (const SweepRecord* r : v) {
    const bool sameSeries = prev && prev->point.storageBandVoxels == r->point.storageBandVoxels && prev->ok();
    md += fmt::format("| {} | {} | {} | {} | {} | {} | {} | {} | {} |\n", r->point.pipeline.fineRes,
                      r->point.storageBandVoxels > 0 ? fmt::format("{:g} voxels", r->point.storageBandVoxels)
                                                     : fmt::format("d = {:g}", errorBand),
                      r->ok() ? r->grid : "failed: " + r->note, r->maskVoxels,
                      sameSeries && prev->maskVoxels ? fmt::format("x{:.2f}", double(r->maskVoxels) / prev->maskVoxels)
                                                     : "",
                      num(r->vdbBytes / 1048576.0, 2), num(r->denseBytes / 1048576.0, 1),
                      r->denseBytes ? fmt::format("{:.2f}%", 100.0 * r->vdbBytes / r->denseBytes) : "", peak(*r));
    prev = r;
  }
  return md + "\n";
}

/// The Pareto front's points, fastest first.
std::string paretoTable(const std::vector<SweepRecord>& rs, const std::vector<std::size_t>& front) {
  std::string md = fmt::format("## Pareto front (frame time vs mean error): no other point is both faster and more "
                               "accurate\n\nPoints with more than {:g}% wrong signs are not eligible: their fields "
                               "have holes.\n\n",
                               100.0 * kParetoMaxSignErrorRate);
  md += "| point | frame (ms) | mean error (voxels) | wrong sign |\n|---|---|---|---|\n";
  for (std::size_t i : front)
    md += fmt::format("| {} | {} | {} | {} |\n", rs[i].point.label(), num(rs[i].frameMs, 1), num(rs[i].meanAbs, 3),
                      pct(rs[i].signErrorRate));
  return md + "\n";
}

} // namespace

std::string markdownReport(const SweepContext& c, const std::vector<SweepRecord>& rs) {
  std::string md = reportHeader(c, rs);
  // A group without records (a smaller preset, a static scene, an interrupted sweep) has no table.
  if (const auto v = ofGroup(rs, SweepGroup::Sizes); !v.empty()) md += sizesTable(v);
  if (const auto v = ofGroup(rs, SweepGroup::Anchor); !v.empty()) md += anchorsTable(v, rs);
  if (const auto v = ofGroup(rs, SweepGroup::Band); !v.empty()) md += bandTable(v);
  if (const auto v = ofGroup(rs, SweepGroup::Alpha); !v.empty())
    md += knobTable(v, "History decay alpha (static scene)", "alpha",
                    [](const SweepRecord& r) { return fmt::format("{:g}", r.point.pipeline.alpha); });
  if (const auto v = ofGroup(rs, SweepGroup::Frames); !v.empty())
    md += knobTable(v, "Frames accumulated (static scene, alpha = 0.95)", "frames",
                    [](const SweepRecord& r) { return fmt::format("{}", r.point.frames); });
  if (const auto v = ofGroup(rs, SweepGroup::Jfa); !v.empty())
    md += knobTable(v, "Coarse method (exact transform or jump-flooding variant)", "coarse method",
                    [](const SweepRecord& r) { return std::string(toString(r.point.pipeline.coarseMethod)); });
  if (const auto v = ofGroup(rs, SweepGroup::Dynamic); !v.empty()) md += dynamicTable(v);
  if (const auto v = ofGroup(rs, SweepGroup::Storage); !v.empty()) md += storageTable(v, c.errorBand);
  if (const auto front = paretoFront(rs); !front.empty()) md += paretoTable(rs, front);
  return md;
}

} // namespace rtsdf::bench
