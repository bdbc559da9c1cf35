#!/usr/bin/env bash
# `make sanitize`: the ctest suite built with AddressSanitizer and UBSan (clang-14 -O1 -g1, in
# build-sanitize/, which `make fuzz` shares: scripts/configure-sanitized.sh) and run; a memory
# error, a leak or undefined behaviour ends the test that met it with the sanitizer's report
# (undefined behaviour is not recovered from). CI runs it (the heavy scenarios excluded below).
set -euo pipefail
cd "$(dirname "$0")/.."

JOBS=${JOBS:-2}
BUILD=$(bash scripts/configure-sanitized.sh)
cmake --build "$BUILD" -j"$JOBS" > "$BUILD/sanitize-build.log" 2>&1 ||
  { grep -E "error|Error" "$BUILD/sanitize-build.log" | head -40; exit 1; }

export ASAN_OPTIONS=${ASAN_OPTIONS:-detect_leaks=1:abort_on_error=1:malloc_context_size=20}
export UBSAN_OPTIONS=${UBSAN_OPTIONS:-print_stacktrace=1:halt_on_error=1}
# The suite at small sizes: the end-to-end liver pipelines (4 minutes each under ASan) and the
# three scenarios over a minute under ASan (the beam of every material law, 5 minutes; two
# cylinder estimations) run in the Release suite only; every other test of every room runs here.
heavy='^((Tracked)?LiverPipeline\.|BeamMaterials\.NonlinearModelsAgreeAndLinearIsFarOff$'
heavy+='|Assimilation\.SmallCylinderYoungModulusSameMesh$|Assimilation\.CutLigamentEstimateDropsAfterTheCut$'
# An atlas built and transferred (LDDMM) and 450 real-time frames: minutes in Release terms, far
# more here; their code runs here in the atlas tests and the other RealTimeModel tests.
heavy+='|LiverAtlasMode\.UnannotatedLiverGetsItsSpringsOnTheTransferredAtlasCurve$'
heavy+='|RealTimeModel\.OlderTangentsDriftSlowlyFromTheOwnStep$'
heavy+='|PointCloudForce\.AnOffCentreFootprintIsRecoveredWithTheForce$'
# CI's 90 minutes: the tests over ~25 s under ASan (measured 2026-12-03: 946 s for the suite on
# 2 cores, these 16 half of it) run in the Release suite only. Each room keeps smaller tests
# here that run the same code: the registration's other cases, the resumed ROUKF, ETKF and UKF
# with the mean's tangent, the cylinders' other estimations, the stream's decoder (fuzzed too)
# and server thread (ThreadSanitizer), the atlas' leave-one-out and transfer tests.
heavy+='|SurfaceRegistration\.(RecoversFromTenCentimetresAndTwentyDegreesOff|NoiseAndOutliersKeepTheErrorBounded)$'
heavy+='|SurfaceRegistration\.(RecoversTheTransformFromAPartialViewExactly|ADozenTackersEndAtLeastAsDeepAsIcpFromTheTruth)$'
heavy+='|Filters/ResumeIdentity\.StoppedAndResumedAgainstUninterrupted/ukf_own(_alone)?( |$)'
heavy+='|AtlasCli\.TransferWritesTheRigidTransformAndTheCurveInTheFileUnits$|Stream\.ServeReplayEndToEnd$'
heavy+='|Assimilation\.SmallCylinderSpringsSameMeshImproveValidation$|Assimilation\.ResumedRunWritesWhatAnUninterruptedOneWrites$'
heavy+='|RealTimeModel\.FrozenTangentsBuiltBehindTheLoopStayOnTheOwnStep$'
heavy+='|MestdaghLiver\.StaticNeoHookeanSolvesReproduceTheFenicsPositions$'
heavy+='|SpringCalibration\.EstimatedSpringsReproduceTheMembranesReactionWithinFivePercent$'
heavy+='|BarycentricMap\.MatchesBruteForceOnFineMesh$|VtkReaderEquivalence\.XmlGridsInEveryMode$'
heavy+='|LiverNewPatient\.SpringPriorsComeFromTheCalibratedMembrane$)'
cd "$BUILD" && ctest --output-on-failure -j"$JOBS" --timeout 1500 -E "$heavy"
