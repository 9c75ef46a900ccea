// The hanging cloth of `jetshell bench solver` and `jetshell bench dynamics`, and the clocks benchmarks read.
// An n×n-square, 1 m cloth (the spec's T-shirt material: E 1e5 Pa, ν 0.25, ρ0 1000 kg/m³, h 2 mm) lies flat in
// the z = 0 plane, pinned at the two corners of its y = 1 edge, under gravity −z.
// Inputs: n (squares per side), the Rayleigh damping coefficients. Outputs: the problem; wall and process CPU
// seconds; the machine's 1-minute load average (printed next to every wall-time figure); peak memory.
#pragma once

#include "solvers/shell_system.h"

namespace jetshell::cli {

ShellProblem hangingCloth(int n, double massDamping, double stiffnessDamping);

double wallSeconds();
/// CPU seconds of the whole process (all threads).
double processCpuSeconds();
/// The 1-minute load average, or -1 when it cannot be read.
double loadAverage();
/// The process's peak resident memory, MB.
double peakRssMb();

}  // namespace jetshell::cli
