// How far a moving solid's surface sweeps past a shell within a time step, judged by the signed distance at the
// shell's sample points rather than by how far the solid's material moves.
//
// A Newton solve sees a solid only where it is at its step's end, so a dynamic step is divided into parts in
// each of which the solid cannot pass through the shell (ShellContact::solidSweep). The bound by material travel
// (VolumeContactState::solidTravel) over-divides where a solid moves along its own surface: a box turning as a
// turntable under a cloth on its top, or sliding under it as a conveyor's tray, moves its material fast while its
// top stays where it is. What matters at a sample point p is the signed distance d(p, t): a part in which it
// changes by at most `allowed` lets no solid of thinnest half-width 2·allowed through p unseen.
//
// Data flow: the sample points the solid may reach within the step (as for solidTravel: their distance at tStart
// at most the solid's move there, their own move and the activation distance) are read from x and v at tStart;
// d(p, ·) is sampled at F + 1 equal sub-times, F a power of two that keeps the surface's largest speed bound
// L_p = |v| + |ω'| (|p − c(tStart)| + |v| h) (ω' the turn that moves the surface, VolumeShape::surfaceTurning;
// across keyframes the largest |v| and |ω'| of the step's pieces, and the centre's path over them for |v| h)
// times h / F within allowed / 4. Between two sub-times d(p, ·) changes by at most L_p h / F, so over a part made
// of whole sub-intervals it changes by at most the spread of its samples plus L_p h / F. The parts are the fewest
// (a power of two dividing F) for which that stays within `allowed` at every sample point; F parts always do.
#pragma once

#include "energies/contact/volume_contact.h"

#include <Eigen/Core>

namespace jetshell {

/// The fewest parts (a power of two) a step of h from tStart must be divided into so that the solid's signed
/// distance changes by at most `allowed` [m] within each, at every sample point it may reach (see the file
/// comment); 1 for a static solid or one that reaches no sample point. +∞ when more than maxSubTimes sub-times
/// would be needed to bound it (the caller keeps the bound by material travel). x, v: positions and velocities
/// (3N) at tStart. Throws InputError when allowed is not positive and finite.
double surfaceSweepParts(const VolumeContactState& state, const Eigen::VectorXd& x, const Eigen::VectorXd& v,
                         double tStart, double h, double allowed, double maxSubTimes);

}  // namespace jetshell
