// What the Jets' dual width costs a stage: `jetshell bench elements --term stage-jets` times the derivatives of
// the shell's Jet-differentiated stages of 3 inputs (unit normal, Kelvin inversion, bending and membrane
// densities; energies/shell/shell_stages.h) at orders 1 and 2, with the framework's width (kJetWidth,
// core/jet_arithmetic.h: 3 inputs carried as 4 duals) against Ceres' plain width (3), interleaved, on the
// inputs of a wavy grid's faces and edges. Checks that both widths give the same derivatives (throws when not).
//
// Inputs: grid squares per side n (faces = 2 n²), timed repeats per figure. Output: one row per stage and order
// (ns per call at each width, their ratio, the largest difference), printed and returned.
#pragma once

#include <string>
#include <vector>

namespace jetshell {

struct StageJetWidthRow {
  std::string stage;
  int order = 0;
  double nsPlain = 0.0;   // Ceres' width: N duals
  double nsFramework = 0.0;  // kJetWidth<N> duals
  double largestDifference = 0.0;  // between the widths, relative (relativeDifference, core/stage.h), every input
};

std::vector<StageJetWidthRow> benchStageJetWidth(int n, int repeats);

}  // namespace jetshell
