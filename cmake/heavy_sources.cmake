# Translation units that each take about 20 s or more of compile CPU (the sanitizer pass's flags, BENCHMARKS.md "CI
# time"). In a unity build (scripts/test.sh) each compiles as a unit of its own instead of joining a batch of 16:
# a batch with two or three of them ran 145-183 s alone at the end of its target while the other core idled.
# Batching saves little for them (a batch's files took 165 s one by one against 172 s together): their cost is
# their own templates, not the shared headers.
set(JETSHELL_HEAVY_SOURCES
  core/psd_projection.cpp
  energies/shell/bending_term.cpp
  energies/shell/bending_graph.cpp
  energies/examples/hinge_bending.cpp
  energies/shell/membrane_term.cpp
  tests/core/stage_graph_test.cpp
  tests/core/psd_projection_test.cpp
  tests/core/jet_arithmetic_test.cpp)
set_source_files_properties(${JETSHELL_HEAVY_SOURCES} PROPERTIES SKIP_UNITY_BUILD_INCLUSION ON)
