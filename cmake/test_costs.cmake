# Scheduling hints for `ctest -j`: CTest starts tests in decreasing COST, and without a hint the longest tests of
# a pass may start last and leave the other core idle (the sanitizer pass ended with the conformance suite
# running alone for about 20 s). CTest's own record of the last run's times (Testing/Temporary/CTestCostData.txt)
# cannot help: it splits each line at spaces, and Catch2's test names contain spaces.
# Each cost is the test's longest measured time in seconds, over the Release and sanitizer passes of CI
# (BENCHMARKS.md, "CI time"). Included after the discovered Catch2 tests are defined; a name that is not a test
# (renamed or removed) is ignored by CTest, so a stale line only loses its hint.
# The memcheck runs (tests/tools/memcheck_test.sh): 37 s each alone on a 2-core host; derivatives 69 s beside a build.
set_tests_properties(memcheck_derivatives PROPERTIES COST 69)
set_tests_properties(memcheck_runs PROPERTIES COST 40)
set_tests_properties("conformance: symmetric Hessian, AD equal to analytic, agreement with finite differences"
  PROPERTIES COST 22)
set_tests_properties("time-step policy: a small full Newton correction ends a step with fewer iterations than the residual estimate alone, and the Newton error stays far below the time error"
  PROPERTIES COST 14)
set_tests_properties("newton: every line search and the L-BFGS alternative reach the same equilibrium"
  PROPERTIES COST 13)
set_tests_properties("contact dynamics: two cloths dropped on each other do not interpenetrate"
  PROPERTIES COST 13)
set_tests_properties("run: every example runs its first steps and writes its outputs"
  PROPERTIES COST 11)
set_tests_properties("edge rules: every rule on every boundary edge passes the derivative checks, exact and Gauss-Newton"
  PROPERTIES COST 10)
set_tests_properties("tshirt: falls on the plane, stays above it and out of itself, and comes to rest"
  PROPERTIES COST 9)
set_tests_properties("dynamics: a hanging cloth with damping settles at the equilibrium the static solver finds"
  PROPERTIES COST 8)
set_tests_properties("contact dynamics: a square cloth dropped on a sphere drapes over it"
  PROPERTIES COST 7)
set_tests_properties("dynamic fit: gradients through backward Euler with stiffness damping, gravity and bending scales"
  PROPERTIES COST 6)
set_tests_properties("dynamics: mass damping decays an oscillation at the rate alpha_R predicts"
  PROPERTIES COST 6)
