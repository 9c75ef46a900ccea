// Example: a new energy term written without hand derivatives. A seam spring pulls vertex pairs (i, j) towards
// their rest distance L: E = Σ k/2 (‖x_i − x_j‖ − L)². Only the energy is written, once, for any scalar type T;
// ElementEnergyTerm evaluates it with doubles and with Ceres Jets for gradient and Hessian; assembly, PSD
// projection and the derivative checks come for free. One line in energies/registry.cpp enrols it in
// `jetshell check-derivatives` and the conformance suite. Plain double constants and Eigen vector algebra work
// for every scalar type T the framework uses (core/jet_arithmetic.h; vec3 views 3 coordinates, core/scalar.h).
#pragma once

#include "core/mesh.h"
#include "energies/element_energy_term.h"

#include <array>
#include <vector>

namespace jetshell {

struct SeamSpringEnergy {
  static constexpr int kVertices = 2;  // one element = one vertex pair
  // A function of x_j − x_i alone: the Jets need only vertex j's 3 coordinates, not the pair's 6.
  static constexpr bool kTranslationInvariant = true;
  // The stiffness k is a differentiable parameter: ∂E/∂k and ∂²E/∂x∂k come from duals seeded on it.
  static constexpr int kParameters = 1;
  static constexpr std::array<const char*, 1> kParameterNames{{"stiffness"}};
  std::array<double, 1> parameters{{1.0}};  // k
  std::vector<double> restLength;           // L per pair

  template <typename T>
  T operator()(const T* x, const T* p, int pair) const {  // x: the pair's 6 coordinates; p[0] = k
    const T stretch = (vec3(x + 3) - vec3(x)).norm() - restLength[pair];
    return 0.5 * p[0] * stretch * stretch;
  }
};

/// Springs between vertex pairs, with rest lengths taken from the mesh's rest positions.
inline EnergyTermPtr makeSeamSpringTerm(const TriMesh& mesh, const std::vector<std::array<int, 2>>& pairs,
                                        double stiffness) {
  StencilTable table{2, {}};
  SeamSpringEnergy energy{{{stiffness}}, {}};
  for (const auto& [i, j] : pairs) {
    if (i < 0 || j < 0 || i >= mesh.numVertices() || j >= mesh.numVertices() || i == j)
      throw InputError("seam spring (" + std::to_string(i) + ", " + std::to_string(j) + "): bad vertex pair");
    table.ids.insert(table.ids.end(), {i, j});
    energy.restLength.push_back((mesh.V.row(i) - mesh.V.row(j)).norm());
  }
  return std::make_shared<ElementEnergyTerm<SeamSpringEnergy>>("seam_spring", std::move(table),
                                                               mesh.numVertices(), std::move(energy));
}

}  // namespace jetshell
