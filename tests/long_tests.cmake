# The long tests: label `long` (beside their own), and more time before a hang fails them. They measure accuracy or
# quality at scale (a town, a size M grid, a target of docs/results.md) through passes that shorter tests also run
# and check against their references. The Release run (the README's test command) runs them all; CI's sanitizer
# run leaves them out (`-LE long`, .ci/run): under ASan with synchronization validation they took 1300 of its
# 3100 test-seconds, two of them 275 s each (near the 300 s a test may take), and the run without them took 835 s
# instead of 1556 (2 cores of a CPU machine, 2026-11-27; the seconds below are from that run).
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
