// The sweep's plans, CSV rows, Pareto front and report (no GPU).
#include "suites/Suites.h"
#include "suites/Sweep.h"
#include "util/Error.h"

#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <set>

using namespace rtsdf;
using namespace rtsdf::bench;

namespace {

/// Split one CSV line, honouring quotes ("" inside quotes is a quote).
std::vector<std::string> splitCsv(const std::string& line) {
  std::vector<std::string> out(1);
  bool quoted = false;
  for (std::size_t i = 0; i < line.size(); ++i) {
    const char c = line[i];
    if (quoted) {
      if (c == '"' && i + 1 < line.size() && line[i + 1] == '"') out.back() += '"', ++i;
      else if (c == '"') quoted = false;
      else out.back() += c;
    } else if (c == '"') quoted = true;
    else if (c == ',') out.emplace_back();
    else out.back() += c;
  }
  return out;
}

std::size_t count(const std::vector<SweepPoint>& plan, SweepGroup g) {
  return std::count_if(plan.begin(), plan.end(), [&](const SweepPoint& p) { return p.group == g; });
}

SweepRecord record(SweepGroup g, double ms, double err) {
  SweepRecord r;
  r.point.group = g;
  r.point.frames = 1;
  r.frameMs = ms;
  r.meanAbs = err;
  r.errorVoxels = 100;
  r.signErrorRate = 0.0;
  return r;
}

} // namespace

TEST(SweepPlan, EveryPresetCoversEveryKnobAndItsAnchors) {
  for (SweepPreset preset : {SweepPreset::Quick, SweepPreset::Default, SweepPreset::Paper}) {
    SCOPED_TRACE(toString(preset));
    const auto plan = makeSweepPlan(preset, true, 3.0);
    std::set<std::string> sizes;
    bool closest = false, brute = false, alpha0 = false, alpha1 = false;
    std::set<CoarseMethod> variants;
    for (const SweepPoint& p : plan) {
      EXPECT_NO_THROW(p.pipeline.validate()) << p.label();
      EXPECT_GT(p.estimatedCost(), 0.0);
      EXPECT_FALSE(p.label().empty());
      if (p.group == SweepGroup::Sizes) sizes.insert(p.size), closest |= p.pipeline.mode == RefineMode::Closest;
      if (p.group == SweepGroup::Band && p.bruteForce) {
        brute = true;
        EXPECT_GE(p.pipeline.band, 3.0 * 4.0) << "d = inf must reach beyond the scene";
      }
      if (p.group == SweepGroup::Alpha) alpha0 |= p.pipeline.alpha == 0.0, alpha1 |= p.pipeline.alpha == 1.0;
      if (p.group == SweepGroup::Jfa) variants.insert(p.pipeline.coarseMethod);
    }
    EXPECT_TRUE(closest);
    EXPECT_TRUE(brute);
    EXPECT_TRUE(alpha0 && alpha1);
    EXPECT_EQ(variants.size(), 4u);
    EXPECT_GE(count(plan, SweepGroup::Frames), 2u);
    EXPECT_EQ(count(plan, SweepGroup::Dynamic), 3u);
    // One OpenVDB and one exact anchor per size.
    EXPECT_EQ(count(plan, SweepGroup::Anchor), 2 * sizes.size());
    EXPECT_GE(count(plan, SweepGroup::Storage), 4u);
    if (preset == SweepPreset::Quick) EXPECT_EQ(sizes, (std::set<std::string>{"XS"}));
    if (preset == SweepPreset::Default) EXPECT_EQ(sizes, (std::set<std::string>{"S", "M"}));
    if (preset == SweepPreset::Paper) EXPECT_EQ(sizes, (std::set<std::string>{"S", "M", "L"}));
  }
  // The storage table of the default sweep is the bunny's 128/256/512 with both bands.
  std::set<int> storage;
  for (const SweepPoint& p : makeSweepPlan(SweepPreset::Default, false, 2.0))
    if (p.group == SweepGroup::Storage) storage.insert(p.pipeline.fineRes);
  EXPECT_EQ(storage, (std::set<int>{128, 256, 512}));
}

TEST(SweepPlan, StaticScenesHaveNoDynamicPointsAndNamesAreParsed) {
  EXPECT_EQ(count(makeSweepPlan(SweepPreset::Default, false, 2.0), SweepGroup::Dynamic), 0u);
  EXPECT_EQ(parseEnum<SweepPreset>("paper"), SweepPreset::Paper);
  EXPECT_THROW(parseEnum<SweepPreset>("fast"), Error);
  for (SweepGroup g : {SweepGroup::Sizes, SweepGroup::Band, SweepGroup::Storage})
    EXPECT_EQ(parseEnum<SweepGroup>(toString(g)), g);
}

TEST(SweepCsv, RowsMatchTheHeaderAndKeepTextIntact) {
  const auto header = splitCsv(csvHeader());
  SweepRecord r = record(SweepGroup::Band, 12.5, 0.25);
  r.point.bruteForce = true;
  r.point.pipeline.band = 8.0;
  r.peakMiB = 100.0;
  r.note = "buffer 'fine SDF': 512 MiB exceeds \"limit\", sorry";
  const auto row = splitCsv(csvRow(r));
  ASSERT_EQ(row.size(), header.size());
  auto field = [&](const std::string& name) {
    const auto it = std::find(header.begin(), header.end(), name);
    EXPECT_NE(it, header.end()) << name;
    return row[std::size_t(it - header.begin())];
  };
  EXPECT_EQ(field("group"), "band");
  EXPECT_EQ(field("band"), "inf");
  EXPECT_EQ(field("frame_ms"), "12.5");
  EXPECT_EQ(field("mean_abs_vox"), "0.25");
  EXPECT_EQ(field("rms_vox"), "") << "unmeasured values are empty, never 'nan'";
  EXPECT_EQ(field("note"), r.note);
  EXPECT_EQ(field("label"), r.point.label());
}

TEST(SweepPareto, KeepsOnlyUndominatedMeasuredPipelinePoints) {
  std::vector<SweepRecord> rs;
  rs.push_back(record(SweepGroup::Sizes, 10, 1.0));   // 0 front
  rs.push_back(record(SweepGroup::Sizes, 20, 0.5));   // 1 front
  rs.push_back(record(SweepGroup::Sizes, 30, 0.7));   // 2 dominated by 1
  rs.push_back(record(SweepGroup::Band, 5, 2.0));     // 3 front (fastest)
  rs.push_back(record(SweepGroup::Anchor, 1, 0.0));   // 4 anchors never count
  rs[4].point.anchor = AnchorKind::Exact;
  rs.push_back(record(SweepGroup::Sizes, 1, 0.0));    // 5 failed: never counts
  rs[5].note = "out of memory";
  rs.push_back(record(SweepGroup::Dynamic, 1, 0.1));  // 6 not the last frame of its series
  rs[6].point.frames = 4;
  rs.push_back(record(SweepGroup::Sizes, 10, 1.0));   // 7 tie with 0: only the first is kept
  rs.push_back(record(SweepGroup::Sizes, 40, 0.5));   // 8 as accurate as 1 but slower
  rs.push_back(record(SweepGroup::Sizes, 2, 0.3));    // 9 fast and accurate, but 5% wrong signs: holes
  rs[9].signErrorRate = 0.05;
  rs[1].signErrorRate = 0.001;
  EXPECT_EQ(paretoFront(rs), (std::vector<std::size_t>{3, 0, 1}));
  EXPECT_EQ(paretoFront(rs, 1.0), (std::vector<std::size_t>{9}));
  rs[9].errorVoxels = 0; // measured over nothing: no evidence of accuracy
  EXPECT_EQ(paretoFront(rs, 1.0), (std::vector<std::size_t>{3, 0, 1}));
  rs[9].errorVoxels = 100;
  rs[9].signErrorRate = kNotMeasured; // an unknown sign error rate is not eligible either
  EXPECT_EQ(paretoFront(rs), (std::vector<std::size_t>{3, 0, 1}));
  EXPECT_TRUE(paretoFront({}).empty());
}

TEST(SweepReport, HoldsThePaperTablesAnchorsRatiosAndInterruptions) {
  SweepContext ctx;
  ctx.scene = "bunny.json";
  ctx.command = "rtsdf bench bunny.json --sweep quick";
  ctx.planned = 10;
  std::vector<SweepRecord> rs;
  SweepRecord a = record(SweepGroup::Sizes, 50.0, 0.5);
  a.point.size = "S";
  a.point.pipeline.rays = 1;
  rs.push_back(a);
  SweepRecord vdb = record(SweepGroup::Anchor, 200.0, 0.04);
  vdb.point.size = "S";
  vdb.point.anchor = AnchorKind::OpenVdb;
  rs.push_back(vdb);
  SweepRecord failed = record(SweepGroup::Band, kNotMeasured, kNotMeasured);
  failed.note = "exceeds maxStorageBufferRange";
  rs.push_back(failed);
  std::string md = markdownReport(ctx, rs);
  EXPECT_NE(md.find("Pass durations and sizes x rays"), std::string::npos);
  EXPECT_NE(md.find("OpenVDB meshToLevelSet"), std::string::npos);
  EXPECT_NE(md.find("| 0.250 |"), std::string::npos) << "rays x=1 frame / OpenVDB = 50 / 200\n" << md;
  EXPECT_NE(md.find("failed: exceeds maxStorageBufferRange"), std::string::npos);
  EXPECT_NE(md.find(ctx.command), std::string::npos);
  EXPECT_EQ(md.find("INTERRUPTED"), std::string::npos);
  ctx.interrupted = true;
  md = markdownReport(ctx, rs);
  EXPECT_NE(md.find("INTERRUPTED"), std::string::npos);
  EXPECT_NE(md.find("3 of 10 points"), std::string::npos);
}

TEST(BenchSuites, ReferenceSuiteMeasuresTheOpenScanAgainstTheWindingNumberEverywhere) {
  BenchOptions o;
  o.suite = BenchSuite::Reference;
  o.resolutions = {24};
  o.repeats = 1;
  const std::string md = runBenchSuite(o);
  const std::size_t open = md.find("Open mesh: the bunny split in four 3 times with 12 holes cut (230415 triangles");
  ASSERT_NE(open, std::string::npos) << md;
  // Two rows (3 voxels and the band fraction), each with no sign differing from the winding number everywhere.
  std::size_t rows = 0;
  for (std::size_t at = md.find("\n| 24 |", open); at != std::string::npos; at = md.find("\n| 24 |", at + 1)) {
    ++rows;
    const std::string row = md.substr(at + 1, md.find('\n', at + 1) - at - 1);
    EXPECT_NE(row.find("| 0.0000% |"), std::string::npos) << row;
  }
  EXPECT_EQ(rows, 2u) << md;
}
