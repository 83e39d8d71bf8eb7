# The long tests: label `long` (beside their own), and more time before a hang fails them. They measure accuracy or
# quality at scale (a town, a size M grid, a target of docs/results.md) through passes that shorter tests also run
# and check against their references. They run when asked for (`scripts/test.sh --long`, or `--all` for every
# test; `ctest -L long`): the README's test command and CI's two runs leave them out (`-LE long`, scripts/test.sh),
# and CI runs them last where its 45 minutes allow (.ci/run). In the Release build they took 509 s on 2 cores (913
# test-seconds), the other 737 tests 568 s (2026-11-28); under ASan with synchronization validation 1300 of 3100
# test-seconds (2026-11-27; the seconds below are from that run).
# ctest reads this file after the tests are listed (tests/CMakeLists.txt); it passes over a name no test has, so
# Docs.LongTestsAreTestsWithTheLabel (scripts/check_long_tests.py) keeps the list current.
set(long_timeout 900)
# gpu (279, 274, 106, 104, 58, 60, 53, 49, 44, 41, 35, 25 s)
set_tests_properties(
  CascadeSetGpu.AllocatedMemoryStaysWithin5PercentFrom50To1000MetresAndIsTheEstimate
  CascadeRender.TheRoomKeepsItsShadowsInsideATownOfRooms
  PieceUnionGpu.ClosestModeOnMovingBunniesIsTheExactUnionAndItsCpuCopy
  Render.ContactRaysDarkenTheUmbraTheSdfCannotResolve
  CoarseSdfGpu.BunnyEqualsCpuAt128
  AccuracyTargets.IncrementalFramesMatchTheFullRecomputeAtS
  Render.SdfShadowsAreCloserToTheTruthThanShadowMapsOnTheDefaultScene
  Refine.SignErrorsOnTheBunnyAtTheDefaults
  Refine.ClosestModesLargestErrorOnTheRefinedVoxelsIsUnderAVoxel
  OpenWindingGpu.TeapotAtSizeMIsTheExactBakeWithinAVoxel
  Render.AnalyticPenumbraMatchesTheTruth
  AccuracyTargets.DefaultSceneStaticFramePenumbraAndUmbra
  PROPERTIES LABELS "gpu;long" TIMEOUT ${long_timeout})
# unit (60, 31 s)
set_tests_properties(
  OpenScans.SignsAreTheBruteForceWindingNumbers
  BenchSuites.ReferenceSuiteMeasuresTheOpenScanAgainstTheWindingNumberEverywhere
  PROPERTIES LABELS "unit;long" TIMEOUT ${long_timeout})
# cli (74 s; Cli.SweepInterruptedByCtrlCKeepsTheFinishedPoints runs the sweep under the sanitizers)
set_tests_properties(Cli.SweepWritesCsvReportAndPlots PROPERTIES LABELS "cli;long" TIMEOUT ${long_timeout})
