// The snap-through benchmark: the hinged cylindrical roof under a central point load (Sze, Liu & Lo 2004,
// "hinged cylindrical shell"): R = 2540, half-length 254 (length 508), half-angle 0.1 rad, E = 3102.75, ν = 0.3,
// h = 12.7 (or 6.35); the straight edges hinged (nodes fixed, no moment across the edge), the curved ends free,
// P at λ = 1 down at the apex. Full model.
//
// The path is traced twice on the same mesh, by arc length (through both limit points, up to λ = 1) and by
// displacement control of the load point's deflection (λ unknown) landing on every deflection the arc-length
// trace reached, and the two are compared: the load at the same deflection (the same equilibrium, found by two
// different controls: they agree to the solver's tolerance where the path is single-valued in w), and the limit
// points' loads and deflections (each located by a parabola through its trace's three points around the turn). The reference
// folder has no table for this problem; VALIDATION.md states what the literature gives and from where.
//
// Inputs: RoofOptions. Output: RoofResult (both traces, their limit points, the differences), as text and JSON.
#pragma once

#include "solvers/statics.h"
#include "validation/benchmark.h"

#include <nlohmann/json.hpp>

#include <iosfwd>
#include <string>
#include <vector>

namespace jetshell::validation {

struct RoofOptions {
  Resolution resolution{16, 16};  // quads across the arc (between the hinged edges) x along the axis; both even
  double thickness = 12.7;
  double load = 3000.0;           // P at λ = 1 [N]
  double maxDeflection = 32.0;    // displacement control: the load point's deflection at τ = 1 [mm]
  double increment = 0.05;        // first increment: λ (arc length) or τ (displacement)
  double maxIncrement = 0.25;     // largest increment, in the same units
  double loadScaling = 0.0;       // ψ of the arc length (0: cylindrical)
  int maxSteps = 400;
  double residualTolerance = 1e-6;
  EdgeRule edgeRule = EdgeRule::SecondOrderFree;          // the hinged and free edges: no moment across them
  std::ostream* log = nullptr;    // one line per path point, or null
};

/// A limit point located on a trace: the load and deflection at the vertex of the parabolas through the three
/// path points around the turn.
struct RoofLimit {
  bool maximum = true;
  double load = 0.0;        // P [N]
  double deflection = 0.0;  // w at the load point [mm], positive down
  int step = 0;
};

struct RoofTrace {
  PathControl control = PathControl::ArcLength;
  bool completed = false;
  std::string message;
  int pathPoints = 0, newtonIterations = 0, cuts = 0;
  double wallSeconds = 0.0;
  int maxNegativePivots = 0;        // the most negative eigenvalues of K seen along the path
  std::vector<double> load, deflection, parameter;  // per path point
  std::vector<RoofLimit> limits;
  std::vector<LoadJump> jumps;      // steps whose equilibrium jumped (displacement control at a snap-back)
};

struct RoofResult {
  RoofOptions options;
  int vertices = 0, faces = 0;
  RoofTrace arc, displacement;
  bool bothLimitsPassed = false;    // the arc-length trace found a maximum then a minimum and reached λ = 1
  // Compared where the arc-length path is single-valued in w: its points before w first decreases (a
  // snap-back, where displacement control meets other equilibria at the same w).
  int singleValuedPoints = 0;
  int comparedLimits = 0;                  // limit points of both traces within that part, matched in order
  double limitLoadDifference = 0.0;        // max over them |P_arc − P_disp| / |P_max(disp)|
  double limitDeflectionDifference = 0.0;  // max over them |w_arc − w_disp| / |w of that limit (disp)|
  int comparedPoints = 0;           // arc-length points whose deflection displacement control landed on
  double curveDifference = 0.0;     // max over the arc-length points of |P_arc(w) − P_disp(w)| / |P_max(disp)|
};

RoofResult runHingedRoof(const RoofOptions& options);
std::string formatRoof(const RoofResult& result);
nlohmann::json toJson(const RoofResult& result);

}  // namespace jetshell::validation
