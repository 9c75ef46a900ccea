# Scheduling hints for `ctest -j`: CTest starts tests in decreasing COST, and without a hint the longest tests of
# a pass may start last and leave the other core idle (the sanitizer pass ended with the conformance suite
# running alone for about 20 s). CTest's own record of the last run's times (Testing/Temporary/CTestCostData.txt)
# cannot help: it splits each line at spaces, and Catch2's test names contain spaces.
# Each cost is the test's longest measured time in seconds, over the Release and sanitizer passes of CI
# (BENCHMARKS.md, "CI time"). Included after the discovered Catch2 tests are defined; a name that is not a test
# (renamed or removed) is ignored by CTest, so a stale line only loses its hint.
foreach(entry
    "22|conformance: symmetric Hessian, AD equal to analytic, agreement with finite differences"
    "14|time-step policy: a small full Newton correction ends a step with fewer iterations than the residual estimate alone, and the Newton error stays far below the time error"
    "13|newton: every line search and the L-BFGS alternative reach the same equilibrium"
    "13|contact dynamics: two cloths dropped on each other do not interpenetrate"
    "11|run: every example runs its first steps and writes its outputs"
    "10|edge rules: every rule on every boundary edge passes the derivative checks, exact and Gauss-Newton"
    "9|tshirt: falls on the plane, stays above it and out of itself, and comes to rest"
    "8|dynamics: a hanging cloth with damping settles at the equilibrium the static solver finds"
    "7|contact dynamics: a square cloth dropped on a sphere drapes over it"
    "6|dynamic fit: gradients through backward Euler with stiffness damping, gravity and bending scales"
    "6|dynamics: mass damping decays an oscillation at the rate alpha_R predicts")
  string(FIND "${entry}" "|" bar)
  string(SUBSTRING "${entry}" 0 ${bar} cost)
  math(EXPR nameStart "${bar} + 1")
  string(SUBSTRING "${entry}" ${nameStart} -1 name)
  set_tests_properties("${name}" PROPERTIES COST ${cost})
endforeach()
