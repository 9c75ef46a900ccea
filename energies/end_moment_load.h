// The end moment as a load description: what a scene or a benchmark asks for, before any term is built
// (energies/end_moment_term.h builds the term; solvers/shell_system.h carries this in ShellProblem::endMoments).
// Plain data, so that the scene layer and the parsers can hold it without the element machinery.
#pragma once

#include <Eigen/Core>

#include <string>
#include <vector>

namespace jetshell {

/// A moment applied along a boundary edge of the shell (energies/end_moment_term.h): `moment` N·m at load factor
/// 1, about the edge's current direction oriented the way `axis` points at rest (right-hand rule), shared among
/// the edge's segments by length. Statics only: the term unwraps its rotation between load steps.
struct EndMomentLoad {
  std::vector<int> chain;  // the loaded edge's vertices in order (consecutive pairs are boundary edges)
  Eigen::Vector3d axis = Eigen::Vector3d::Zero();
  double moment = 0.0;     // N·m at λ = 1
  std::string where;       // for messages, e.g. "/actors/0/loads/1"
};

}  // namespace jetshell
