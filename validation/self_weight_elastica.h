// The inextensible elastica of a cantilever under its own weight: the reference for the fabric bending-length
// (cantilever overhang, ASTM D1388 style) fit. A strip of length l, weight w per unit length and flexural
// rigidity G, clamped horizontally at s = 0: G θ'' = −w (l − s) cos θ, θ(0) = 0, θ'(l) = 0 (θ the downward slope
// angle), solved by shooting on θ'(0) (RK4, 4000 steps, bisection to 1e-13). Its shape depends only on
// k = w l³ / G; the tip chord drops by 41.5° at one k, which turns a measured overhang length into G.
// Peirce (1930): G = w c³ with the bending length c = l (cos(θ/2) / (8 tan θ))^(1/3) ≈ l/2 at θ = 41.5°.
#pragma once

namespace jetshell::validation {

struct ElasticaTip {
  double x = 0.0;           // horizontal distance of the tip from the clamp
  double drop = 0.0;        // vertical drop of the tip (> 0 downwards)
  double chordAngle = 0.0;  // atan(drop / x), radians
};

/// The tip of the self-weight elastica.
ElasticaTip selfWeightElastica(double length, double weightPerLength, double rigidity);

/// The rigidity G at which the tip chord drops by chordAngle (radians, in (0, π/2)), by bisection on log G.
double rigidityForChordAngle(double length, double weightPerLength, double chordAngle);

/// Peirce's bending length c = l (cos(θ/2) / (8 tan θ))^(1/3) for the chord angle θ (c ≈ l/2 at 41.5°).
double peirceBendingLength(double length, double chordAngle);

}  // namespace jetshell::validation
