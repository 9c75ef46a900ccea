// The one list of energy terms that `jetshell check-derivatives` and the conformance suite
// (tests/energies/conformance_test.cpp) check: registering a term here enrols it in both.
//
// To register a new term, add one line to the table in energies/registry.cpp:
//   {"my_term", "what it is", [](const TermSetup& s) { return makeMyTerm(s.mesh, ...); }},
// The factory builds the term on the small mesh it is given (a 4-face bending stencil patch and a 12-face grid,
// see tools/checks/check_configurations.h); the term's own zeroAtRest() / rigidInvariant() say which conformance checks
// apply. A term with a model Hessian that is not the derivative of its gradient sets hessianIsExact = false.
#pragma once

#include "core/mesh.h"
#include "energies/shell/reference_state.h"
#include "core/term.h"
#include "core/topology.h"
#include "energies/shell/material.h"

#include <functional>
#include <string>
#include <vector>

namespace jetshell {

/// What a factory builds its term on.
struct TermSetup {
  const TriMesh& mesh;
  const Topology& topology;
  const ShellReference& reference;
  const ShellMaterialParams& material;
};

using TermFactory = std::function<EnergyTermPtr(const TermSetup&)>;

struct RegisteredTerm {
  std::string name;     // unique; the check's name for it (several entries may build the same class)
  std::string summary;  // one line for `check-derivatives --list`
  TermFactory make;
  EvalOptions options = {};     // evaluation options it is checked under (path is chosen by the checker)
  bool hessianIsExact = true;   // false: a model Hessian (Gauss–Newton), checked PSD instead of against FD
  bool singularAtFold = false;  // true: the energy is infinite at a 180° fold by design (tan-based hinges), so
                                // the checks skip the near-fold configurations, where differences cannot resolve it
};

/// Every registered term, in registration order.
const std::vector<RegisteredTerm>& termRegistry();

/// The entry with this name, or null.
const RegisteredTerm* findRegisteredTerm(const std::string& name);

/// The registered names, in registration order.
std::vector<std::string> registeredTermNames();

}  // namespace jetshell
