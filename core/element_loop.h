// The parallel, deterministic element loop every term uses.
//
// For each colour of the schedule (blocks of elements sharing no vertex), blocks run in parallel with OpenMP
// and the elements of a block in order; colours run one after another. Gradient and Hessian entries are
// therefore summed in a fixed order whatever the thread count, and the energy is summed serially from
// per-element values: the same input gives the same bits. An exception thrown by an element is caught inside
// the parallel region and rethrown after it (core/parallel_errors.h), never terminating the program.
#pragma once

#include "core/assembly.h"
#include "core/parallel_errors.h"
#include "core/psd_projection.h"
#include "core/stencil.h"
#include "core/term.h"

#include <Eigen/Core>

#include <vector>

namespace jetshell {

/// Loops over fewer elements than this run serially: thread start-up costs more than their elements.
inline constexpr int kParallelMinElements = 512;
/// The same for kernels of about 0.1 ms an element (nested-Jet Hessians over 15 or more dofs, ~0.5 M
/// instructions each): a few dozen of them already outweigh a parallel region's start-up and barriers.
inline constexpr int kParallelMinCostlyElements = 32;

/// Adds element e's gradient g (3K, when the request has a gradient) and Hessian H (3K×3K, column-major, when it
/// has a Hessian) into the request: what every element loop does with an element's result.
template <int K>
void addElementResult(const EvalRequest& request, int e, const int* ids, const double* g, const double* H) {
  if (request.gradient != nullptr) {
    double* G = request.gradient->data();
    for (int k = 0; k < K; ++k) {
      if (ids[k] < 0) continue;
      for (int c = 0; c < 3; ++c) G[3 * ids[k] + c] += g[3 * k + c];
    }
  }
  if (request.hessian != nullptr) request.hessian->addElementHessian(request.hessianSlot, e, H);
}

/// Element kernel: kernel(e, ids, wantGradient, wantHessian, g, H) returns the element energy and fills the
/// local gradient g (3K) and Hessian H (3K×3K) when asked. K is the stencil width.
/// parallelMinElements: the element count from which the loop runs in parallel (kParallelMinCostlyElements for
/// costly kernels); the result has the same bits either way.
template <int K, typename Kernel>
double runElementLoop(const StencilTable& table, const ElementSchedule& schedule,
                      const Eigen::VectorXd& /*x*/, const EvalRequest& request, PsdProjection projection,
                      std::vector<double>& elementEnergy, Kernel&& kernel,
                      int parallelMinElements = kParallelMinElements) {
  constexpr int M = 3 * K;
  const int ne = table.size();
  elementEnergy.resize(static_cast<std::size_t>(ne));
  const bool wantG = request.gradient != nullptr;
  const bool wantH = request.hessian != nullptr;
  auto body = [&](int e) {
    Eigen::Matrix<double, M, 1> g;
    Eigen::Matrix<double, M, M> H;
    const int* ids = table.element(e);
    elementEnergy[e] = kernel(e, ids, wantG, wantH, g, H);
    if (wantH) projectPsd<M>(H, projection);
    addElementResult<K>(request, e, ids, g.data(), H.data());
  };
  ParallelErrors errors;
  if (wantG || wantH) {
    // One parallel region for all colours: a colour ends at the worksharing loop's barrier, without a team
    // start-up and join per colour (half the synchronization points, each of which costs a scheduling delay
    // when the other core is busy). Small meshes run serially: thread start-up costs more than their elements.
#pragma omp parallel if (ne >= parallelMinElements)
    for (const std::vector<ElementRange>& color : schedule.colors) {
      const int n = static_cast<int>(color.size());
#pragma omp for schedule(dynamic, 1)
      for (int i = 0; i < n; ++i)
        errors.run([&] {
          for (int e = color[i].begin; e < color[i].end; ++e) body(e);
        });
    }
    // After the region: an exception must never leave an OpenMP region (that terminates the program).
    errors.rethrow();
  } else {
#pragma omp parallel for schedule(static) if (ne >= parallelMinElements)
    for (int e = 0; e < ne; ++e) {
      errors.run([&] {
        Eigen::Matrix<double, M, 1> g;
        Eigen::Matrix<double, M, M> H;
        elementEnergy[e] = kernel(e, table.element(e), false, false, g, H);
      });
    }
    errors.rethrow();
  }
  double total = 0.0;
  for (double v : elementEnergy) total += v;
  return total;
}

}  // namespace jetshell
