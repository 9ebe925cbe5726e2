# The labels of the tests GoogleTest finds in the test programs. CTest includes this file
# (TEST_INCLUDE_FILES, set in tests/CMakeLists.txt) after the lists of discovered tests, because
# their names are known only once the programs are built; tests/CMakeLists.txt defines
# SURFTRACE_TEST_PROGRAMS and, for each program, SURFTRACE_LABELS_<program> (its own labels).
#
# Every test gets exactly one of
#   fast    2 s at most: `ctest --preset ci -L fast` is the developer's quick check;
#   slow    the rest: the tests listed below, which took more than 2 s on a 2-core machine
#           (the smaller of two full runs, ctest -j2, other builds beside them);
# and, where it applies,
#   gl      draws through EGL/OpenGL (llvmpipe where there is no GPU);
#   oracle  compared with an independent program: MDAnalysis (Python), FreeSASA, CGAL;
#   cli     runs the surftrace program;
#   script  a shell or CMake script (add_test in tests/CMakeLists.txt, labelled there);
#   release_only  left out of the AddressSanitizer stage of scripts/test.sh (release_only_tests
#           below says why for each, and which tests run the same code under ASan instead).
# A new test is `fast` until it is listed here; tests/check_labels.cmake fails a test run in
# which some test has neither `fast` nor `slow`, or a label not named above.

# The COST (tests/CMakeLists.txt gives it to its own slow tests too) that starts them first.
set(surftrace_slow_test_cost 10)

# Regular expressions, each matched against the whole test name.
set(slow_tests
  # tools_tests: FreeSASA's Lee & Richards at 2000 slices, its classifier on three structures
  "AreaPer\\.(ResidueSasMatchesFreesasaLeeRichardsWithItsRadii|PresetRadiiAreFreesasaClassifierRadiiOnEveryAtom)"
  # build_tests
  "Cavities\\.(BoxHoldsSampledSurfacePointsTightly|GroelHasItsCavitiesLocated)"
  "Proteins/CavitiesOnProteins\\.LiningAtomsMatchTheProbeGridOracle/.*"
  "ContourBuildup\\.SealedCavityIsItsOwnComponent"
  "ElementGuess\\.(AgreesWithMDAnalysis|IonsAgreeWithMDAnalysis)"
  "ExactPredicates\\.ProbeErrorBoundHoldsOnHardTriples"
  "MssAreas\\.(MatchesTheAdaptiveReferencePatchByPatch|SameValuesForAnyThreadCount|SignJitteredCubeHasTheExactCubesAreas|SignJitteredLatticeHasTheExactLatticesAreas)"
  "NeighbourGrid\\.MatchesBruteForceOnSampleOf1aon"
  "PatchListValidate\\.RealListsLoadAndRoundTrip"
  "Ses/Cospherical\\..*"
  "SesComponents\\.(CrambinCavityMatchesGridOracle|IsoperimetricOnProteins)"
  "SphericalRegion\\..*"
  "SurfaceBuilder\\.(FlexibleAtomsSkinEqualsFreshBuilds|SesFrameAfterFrameEqualsFreshBuilds|SkinFrameAfterFrameEqualsFreshBuilds)"
  "TriangleCone\\.AgreesWithSampledTriangle"
  # gl_tests
  "GlBallAndStick\\.ModelUnderTheOpaqueSesMeetsTheGlVsEmbreePreset"
  "GlContext\\.OpensWithAnEmptyEnvironment"
  "GlPeelMerge\\..*"
  "GlPeelOpaque\\..*"
  "GlPeelSes\\..*"
  "GlPrimitive\\.EyeInsideAndBesideCylinders"
  "GlSoftLighting\\..*"
  "Surfaces/GlPeel\\..*"
  "Views/GlPrimitiveViews\\..*"
  "Views/GlVsEmbree\\..*"
  # mss_oracle_tests
  "MssOracle\\.(EveryPatchIsSkinInItsOwnMixedCell|VolumeMatchesMonteCarloOfTheSkinFunction)"
  # oracle_tests
  "SesOracle\\.MatchesSampledSasOnRandomClusters"
  # reader_tests
  "Bonds\\.(ConectRecordsOfHeteroGroupsMatchMdanalysisOn1grm|DistanceRuleMatchesMdanalysisGuessOn1crn)"
  "Dcd\\.(FileCutInsideTheHeaderIsAnInputError|TruncatedLastFrameIsLeftOut)"
  # about 50 s each where the shared data set (shared/data) is present, skipped where it is not
  "Dcd\\.SharedDataMatchesMDAnalysis"
  "XtcReader\\.MatchesMdanalysisOnSharedData"
  "TextFramesSharedData\\..*"
  "Files/DcdAgainstMDAnalysis\\..*"
  "Files/GroTopology\\..*"
  "Files/TextFrames\\.EqualMDAnalysis(/.*)?"
  "SelectionAgreesWithMDAnalysisOnInsertionCodes\\..*"
  "TextFramesGro\\.TriclinicBoxMatchesMDAnalysis"
  "Topologies/SelectionAgreesWithMDAnalysis\\..*"
  "XtcReader\\.(HandWrittenFramesMatchMdanalysis|MatchesMdanalysisOnTestData|TruncatedLastFrameIsLeftOutWithNote)"
  # ses_hull_tests
  "SesHull\\..*"
  # ses_oracle_tests
  "ConcaveArea\\..*"
  "Ses/RealMolecule\\.PatchPointsLieOnTheSes(/.*)?"
  "SesVolume\\..*"
  # view_tests
  "ColorMap\\.EveryMapEqualsMatplotlibs"
  # tools_tests
  "BallStickCli\\.(BadOptionsAreRefusedNamingThem|GlMatchesEmbreeAloneAndUnderTheSurface|TrajectoryFramesGetTheModel|UnderATransparentSurfaceTheModelShows)"
  "CameraCli\\..*"
  "ColorsCli\\..*"
  "Cases/Reference\\..*"
  "Cli\\.(CompareDefaultsToTheStrictPresetOfItsEngines|DropCavitiesChangesNoPixel|HelpTeachesTheCommands|HemeProteinWorksOutOfTheBox|LightingPresetsAreRecordedAndGlDrawsSoft|OpacityIsRecordedAndGlPeelsIt|OptionErrorsAreReadable|PatchListRendersAsTheStructureDoes|RenderRejectsImpossibleOptionsClearly|RenderWritesImagesWithTheirCamera|SkinAreaBuildAndShrinkErrors|SkinPatchListRendersAsTheStructureDoes|SliverPatchesDoNotMoveTheSkinsFraming|WideSkinFillsThePicture)"
  "CompareDiff\\..*"
  "CompareExample\\..*"
  "CompareForeign\\..*"
  "CompareHtml\\..*"
  "CompareMasks\\..*"
  "CompareMesh(OneView|Views)\\..*"
  "MeshCli\\.(CrambinSesIsClosedOnTheSurfaceAndWithinItsBound|GroelPieceWithWallsThinnerThanTheGridIsClosedAndWithinItsBound)"
  "MeshCli\\.(GroelKnifeEdgeRidgesMesh|GroelMeetingOfThreeConcaveSheetsMeshes)WithinAHundredthOfAnAngstrom"
  "MeshCli\\.SesMeshHasTheExactSurfacesTopology"
  "MeshCli\\.CrambinSkinAtATenthOfAnAngstromIsClosedOutwardAndWithinItsBound"
  "MeshCli\\.GramicidinSkinIsClosedOnTheSkinAndWithinItsBound"
  "CompareVerdict\\.(ColourIsJudgedBetweenEnginesByDefault|ColourOverCoveredPixelsAndTheBackgroundApart|NanIsCountedAndJudgedAMismatch|NoneComparedFails|OcclusionEdgesAreReportedApart|PerKindTableInTextAndJson)"
  "EngineCli\\.(GlRefusesAnOcclusionDistance|TrajectoryGlFramesPassCompareAgainstEmbreeFrames|TransparentTrajectoryGlFramesPassCompareAgainstEmbreeFrames|TrajectoryGlFramesEqualIndependentGlRenders)"
  "EffectsCli\\.(BadEffectOptionsAreRefused|EffectsAreRecordedAndOffMeansTheImageAsItWas|GlPeelsTheLayersEmbreeComposites|SilhouettesAreExactlyTheDepthJumpsInTheExr|TrajectoryFramesGetTheEffects)"
  "DepthEffectsCli\\..*"
  "InputCli\\.(EveryReadingCommandTakesBeadRadius|MartiniTrajectoryDrawsWithBeadRadius)"
  "Install\\..*"
  "Interrupt\\..*"
  "Messages\\..*"
  "Output\\.(AClosedPipeStopsALongRunEarly|DashIsTheStandardOutput|DevicesAreWrittenInPlace|FilesOnAFullDiskAreErrorsAndLeaveNothing|ImageNamesAreCheckedBeforeTheWork|ParseErrorsExitOne|PathsAreCheckedBeforeTheWork|SymbolicLinksStayLinksAndTheirTargetIsReplaced|TrajectoryFramesAreWholeAndResumeChecksThem)"
  "Reference\\..*"
  "SelectCli\\.(InfoAtomsListsWhatMDAnalysisSelects|RenderOfASelectionIsTheRenderOfAFileOfItsAtoms|SelectionsThatCannotApplyAreErrorsNamingThem|TrajectoryOfASelectionIsTheTrajectoryOfAFileOfItsAtoms)"
  "SrgbCli\\.(BackgroundComesOutAsTheSrgbBytesGiven|EightBitImagesHoldTheSrgbEncodingOfTheExrColour)"
  "Startup\\..*"
  "TrajectoryCli\\..*"
  "Usability\\.(BritishSpellingsAreTheSameOptions|DashCapitalVIsTheVersion|MistypedOptionsAndCommandsGetASuggestion|OutputNamesAreCheckedBeforeTheWork|SppCountsTheSamplesItTakes)"
  # trace_tests
  "LightingSoft\\.FilteredImageIsNearerTheBruteForceOracleThanTheFormerRays"
  "Molecules/RenderOnSkin\\.HitsAreCertifiedAndNoRayCrossesTheBody(/.*)?"
  "Molecules/SesCrossings\\..*"
  "Crossings\\.EveryPixelCrossesTheOuterSesAnEvenNumberOfTimes"
  "MssPatch\\.MatchesBruteForceOracleOnRealPatches"
  "SkinCrossings\\.CountAndPlaceMatchTheSkinOracle"
  "StickPatch\\.MatchesBruteForceOracle"
  "VdwCrossings\\.CountAndPlaceMatchTheUnionOfBalls"
)

# The tests outside gl_tests that render with --engine gl (found by their code, helpers included).
set(gl_tests
  "BallStickCli\\.Gl.*"
  "Cli\\.(LightingPresetsAreRecordedAndGlDrawsSoft|OpacityIsRecordedAndGlPeelsIt|PatchListRendersAsTheStructureDoes|SkinPatchListRendersAsTheStructureDoes|CompareDefaultsToTheStrictPresetOfItsEngines)"
  "CompareMasks\\.(TheKindCheckCoversMostHitsOf1aonAt256|AReferenceWithoutSeamDistancesFallsBackToTheNeighbourhoodRule)"
  "CompareDiff\\.GlWithinTheLimitsLooksQuiet"
  "CompareVerdict\\.ColourIsJudgedBetweenEnginesByDefault"
  "EffectsCli\\.Gl.*"
  "EngineCli\\.TrajectoryGl.*Frames.*"
  "EngineCli\\.GlRefusesAnOcclusionDistance"
  "Install\\.InstalledProgramsRenderFromTheirPrefix"
  "(Cases/)?Reference\\.Gl.*"
)

# The tests the ASan + UBSan stage of scripts/test.sh leaves out (ctest -LE release_only): the
# Release stage runs them, and under ASan they would add minutes of time that is either
# un-instrumented code or the same instrumented code again, which the tests named here run.
set(release_only_tests
  # Minutes under ASan, as in Release: llvmpipe's shaders (not instrumented) drawing soft and full
  # at 96², opaque and peeled. Under ASan the light maps' host code runs in GlSoftLighting.Soft-
  # ShadowsAndOcclusionAreSmoothOnAFlatFloor (soft and full) and Cli.LightingPresetsAreRecorded-
  # AndGlDrawsSoft (1CRN's SES, both engines), Embree's soft and full in LightingSoft.*.
  "GlSoftLighting\\.SoftAndFullMeetTheEffectsPreset"
  # 85 s under ASan: 98 independent `render --frame` processes, one code path 98 times. Under
  # ASan the trajectory pipeline runs consecutive SES frames in ShardsTogetherAreTheSingleRun-
  # EachFrameOnce (frames 3-39, whole and in 4 shards) and slurm_job_array (1:98:3), and
  # SkinFramesEqualIndependentRenders checks frames against independent renders (--frame).
  "TrajectoryCli\\.EveryFrameOfAdkEqualsAnIndependentRender"
  # 35 s under ASan: a coverage ratio of compare's exact masks on 1AON at 256², a property of
  # the algorithm. Under ASan compare's exact masks run in CompareMasks.AReferenceWithout-
  # SeamDistancesFallsBackToTheNeighbourhoodRule and CompareDiff.*, 1AON's renders in Cases/Reference.*.
  "CompareMasks\\.TheKindCheckCoversMostHitsOf1aonAt256"
)

# The tests outside the oracle programs that run MDAnalysis, FreeSASA or a Python oracle script.
set(oracle_tests
  "AtomCulling\\.ContainedAtomsMatchFreesasa"
  "ElementGuess\\.(AgreesWithMDAnalysis|IonsAgreeWithMDAnalysis)"
  "MoleculePdb\\.AltLocsNeverDropAnAtomWithoutAlternative3al1"
  "SelectCli\\.InfoAtomsListsWhatMDAnalysisSelects"
  "MssBuilder\\.ApproachesTheVanDerWaalsAreaAsShrinkTendsToOne"
  "EffectsCli\\.SilhouettesAreExactlyTheDepthJumpsInTheExr"
  "CompareExample\\..*"
)

# Whether `name` matches one of the patterns whole (one at a time: CMake's regular expressions
# hold at most 9 groups).
function(surftrace_matches_one out name)
  foreach(pattern IN LISTS ARGN)
    if(name MATCHES "^(${pattern})$")
      set(${out} TRUE PARENT_SCOPE)
      return()
    endif()
  endforeach()
  set(${out} FALSE PARENT_SCOPE)
endfunction()

foreach(program IN LISTS SURFTRACE_TEST_PROGRAMS)
  foreach(name IN LISTS ${program}_TESTS)
    set(labels ${SURFTRACE_LABELS_${program}})
    surftrace_matches_one(slow "${name}" ${slow_tests})
    if(slow)
      list(APPEND labels slow)
    else()
      list(APPEND labels fast)
    endif()
    surftrace_matches_one(gl "${name}" ${gl_tests})
    if(gl)
      list(APPEND labels gl)
    endif()
    surftrace_matches_one(oracle "${name}" ${oracle_tests})
    if(oracle)
      list(APPEND labels oracle)
    endif()
    surftrace_matches_one(release_only "${name}" ${release_only_tests})
    if(release_only)
      list(APPEND labels release_only)
    endif()
    list(REMOVE_DUPLICATES labels)
    set_tests_properties("${name}" PROPERTIES LABELS "${labels}")
    if(slow)
      # ctest -j starts the costliest tests first; without a CTestCostData.txt (a fresh build
      # folder, as in CI) every test costs 0 and they start in file order, which left a 138 s
      # GL test for the end with the other core idle. The slow ones first packs both cores.
      set_tests_properties("${name}" PROPERTIES COST ${surftrace_slow_test_cost})
    endif()
  endforeach()
endforeach()
