# Run by ctest (tests/CMakeLists.txt adds it after the GoogleTest files, whose tests it names): the
# heaviest GoogleTest cases start first under `ctest -j` (COST, in seconds: the larger of their times in
# the full tier and the sanitized tier, measured 2026-12-07 on a 2-core machine). A fresh build has no
# Testing/Temporary/CTestCostData.txt, and ctest then starts tests in the order they are declared: a
# minute-long test declared late runs alone at the end. A name not found here is ignored (a renamed
# test only loses its place in the queue); the plain tests' costs are set where they are declared.
set_tests_properties([=[SlidingPairs.FrictionFollowsTheSlidingRows]=] PROPERTIES COST 70)
set_tests_properties([=[PrimalDual/EveryShippedCase.PrimalAndDualAgree/hertz_spheres_3d  # GetParam() = "hertz-spheres-3d"]=] PROPERTIES COST 62)
set_tests_properties([=[SlidingPairs.TheContactGoesWithTheSlidingDisc]=] PROPERTIES COST 52)
set_tests_properties([=[PrimalDual/EveryShippedCase.PrimalAndDualAgree/hertz_2d  # GetParam() = "hertz-2d"]=] PROPERTIES COST 42)
set_tests_properties([=[PrimalDual/EveryShippedCase.PrimalAndDualAgree/cattaneo_mindlin_pair_2d  # GetParam() = "cattaneo-mindlin-pair-2d"]=] PROPERTIES COST 42)
set_tests_properties([=[PrimalDual/EveryShippedCase.PrimalAndDualAgree/wear_ironing_3d  # GetParam() = "wear-ironing-3d"]=] PROPERTIES COST 41)
set_tests_properties([=[Adapt.AResumeAcrossAdaptationsIsByteIdentical]=] PROPERTIES COST 41)
set_tests_properties([=[Hertz.SphereOnSphereQuarterModel]=] PROPERTIES COST 35)
set_tests_properties([=[FrictionBenchmarks.CattaneoMindlinBetweenTwoBodiesOfOneMaterial]=] PROPERTIES COST 33)
set_tests_properties([=[FrictionBenchmarks.CattaneoMindlinStickZoneAndTraction]=] PROPERTIES COST 31)
set_tests_properties([=[PrimalDual/EveryShippedCase.PrimalAndDualAgree/hertz_3d  # GetParam() = "hertz-3d"]=] PROPERTIES COST 30)
set_tests_properties([=[PrimalDual/EveryShippedCase.PrimalAndDualAgree/hertz_cylinders_2d  # GetParam() = "hertz-cylinders-2d"]=] PROPERTIES COST 27)
set_tests_properties([=[Indentation.DamageGrowsUnderThePunchAndSoftensTheResponse]=] PROPERTIES COST 27)
set_tests_properties([=[FrictionShear.ShearLimitCapsCoulombsBound3d]=] PROPERTIES COST 26)
set_tests_properties([=[Adapt.ARunRefinesAheadOfTheIndenterAndCoarsensBehindIt]=] PROPERTIES COST 25)
set_tests_properties([=[Adapt.AnAdaptedMeshThatCannotBeSetUpLeavesTheRunOnTheMeshBefore]=] PROPERTIES COST 24)
set_tests_properties([=[SolverPlan.FactorsScaledFromAFewerTimesRefinedMeshMatchTheWholeMeshsAnalysis]=] PROPERTIES COST 23)
set_tests_properties([=[PrimalDual/EveryShippedCase.PrimalAndDualAgree/punch_3d  # GetParam() = "punch-3d"]=] PROPERTIES COST 22)
set_tests_properties([=[PrimalDual/EveryShippedCase.PrimalAndDualAgree/indentation_3d  # GetParam() = "indentation-3d"]=] PROPERTIES COST 21)
set_tests_properties([=[Adapt.AStepThatFailsOnTheAdaptedMeshUndoesTheAdaptation]=] PROPERTIES COST 19)
set_tests_properties([=[Hertz.LineContactOnARigidCylinder]=] PROPERTIES COST 19)
set_tests_properties([=[LawBlocks.EllipticCoulombWithEqualAxesIsCoulombOnTheDual]=] PROPERTIES COST 17)
set_tests_properties([=[PrimalDual/EveryShippedCase.PrimalAndDualAgree/ironing_3d  # GetParam() = "ironing-3d"]=] PROPERTIES COST 16)
set_tests_properties([=[Hertz.LineContactOnAGradedMeshUpToAOverH50]=] PROPERTIES COST 16)
set_tests_properties([=[Hertz.LineContactBetweenTwoElasticBodies]=] PROPERTIES COST 16)
set_tests_properties([=[LawBlocks.EllipticCoulombFullSlipLiesOnTheEllipseAlongItsNormal]=] PROPERTIES COST 15)
