// The hanging cloth of `jetshell bench solver` and `jetshell bench dynamics`, and the clocks benchmarks read.
// An n×n-square, 1 m cloth (the spec's T-shirt material: E 1e5 Pa, ν 0.25, ρ0 1000 kg/m³, h 2 mm) lies flat in
// the z = 0 plane, pinned at the two corners of its y = 1 edge, under gravity −z.
// Inputs: n (squares per side), the Rayleigh damping coefficients. Outputs: the problem; wall and process CPU
// seconds; the machine's 1-minute load average (printed next to every wall-time figure); peak memory.
#pragma once

#include "solvers/shell_system.h"

namespace jetshell::cli {

/// The cloth's material (the spec's T-shirt), or a steel foil's: E 2e11 Pa, ν 0.3, ρ0 7850 kg/m³, h 0.1 mm, a sheet
/// whose membrane is some 10^6 times stiffer than a time step's inertia.
enum class SheetMaterial { Cloth, SteelFoil };

/// youngsModulus > 0 replaces the material's E [Pa], thickness > 0 its thickness [m].
ShellProblem hangingCloth(int n, double massDamping, double stiffnessDamping,
                          SheetMaterial material = SheetMaterial::Cloth, double youngsModulus = 0.0,
                          double thickness = 0.0);

double wallSeconds();
/// CPU seconds of the whole process (all threads).
double processCpuSeconds();
/// The 1-minute load average, or -1 when it cannot be read.
double loadAverage();
/// The process's peak resident memory, MB.
double peakRssMb();

}  // namespace jetshell::cli
