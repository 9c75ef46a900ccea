// A term defined only by a templated element energy: the framework derives gradient and Hessian with Ceres
// Jets (first order: Jet<double,3K>; second order: Jet<Jet<double,3K>,3K>), assembles in parallel and
// projects. This is how users add energies without hand derivatives (see energies/examples/).
//
// The functor:
//   struct MyEnergy {
//     static constexpr int kVertices = K;           // stencil width
//     template <typename T> T operator()(const T* x, int element) const;  // x: 3K positions of the element
//   };
// Write constants as constant<T>(c) and use the helpers of core/scalar.h instead of Eigen reductions: they
// work for every Jet nesting depth.
#pragma once

#include "core/assembly.h"
#include "core/element_loop.h"
#include "core/scalar.h"
#include "core/term.h"

#include <ceres/jet.h>

#include <string>
#include <utility>

namespace jetshell {

template <typename Functor>
class ElementEnergyTerm : public EnergyTerm {
 public:
  static constexpr int K = Functor::kVertices;
  static constexpr int M = 3 * K;

  ElementEnergyTerm(std::string name, StencilTable stencils, int numVertices, Functor functor,
                    bool zeroAtRest = true, bool rigidInvariant = true)
      : name_(std::move(name)),
        table_(std::move(stencils)),
        schedule_(scheduleElements(table_, numVertices)),
        functor_(std::move(functor)),
        zeroAtRest_(zeroAtRest),
        rigidInvariant_(rigidInvariant) {}

  std::string name() const override { return name_; }
  StencilTable stencils() const override { return table_; }
  bool zeroAtRest() const override { return zeroAtRest_; }
  bool rigidInvariant() const override { return rigidInvariant_; }
  const Functor& functor() const { return functor_; }

  double evaluate(const Eigen::VectorXd& x, const EvalRequest& request, const EvalOptions& options) override {
    return runElementLoop<K>(table_, schedule_, x, request, options.projection, elementEnergy_,
                             [&](int e, const int* ids, bool wantG, bool wantH, Eigen::Matrix<double, M, 1>& g,
                                 Eigen::Matrix<double, M, M>& H) { return element(x, e, ids, wantG, wantH, g, H); });
  }

 private:
  using J1 = ceres::Jet<double, M>;
  using J2 = ceres::Jet<J1, M>;

  double element(const Eigen::VectorXd& x, int e, const int* ids, bool wantG, bool wantH,
                 Eigen::Matrix<double, M, 1>& g, Eigen::Matrix<double, M, M>& H) const {
    double xe[M];
    for (int k = 0; k < K; ++k)
      for (int c = 0; c < 3; ++c) xe[3 * k + c] = ids[k] >= 0 ? x[3 * ids[k] + c] : 0.0;
    if (wantH) {
      J2 xj[M];
      for (int i = 0; i < M; ++i) {
        xj[i] = J2(J1(xe[i], i));
        xj[i].v[i] = J1(1.0);
      }
      const J2 E = functor_(xj, e);
      for (int i = 0; i < M; ++i) {
        g[i] = E.a.v[i];
        for (int j = 0; j < M; ++j) H(i, j) = E.v[i].v[j];
      }
      H = 0.5 * (H + H.transpose()).eval();
      return E.a.a;
    }
    if (wantG) {
      J1 xj[M];
      for (int i = 0; i < M; ++i) xj[i] = J1(xe[i], i);
      const J1 E = functor_(xj, e);
      g = E.v;
      return E.a;
    }
    return functor_(xe, e);
  }

  std::string name_;
  StencilTable table_;
  ElementSchedule schedule_;
  Functor functor_;
  bool zeroAtRest_, rigidInvariant_;
  std::vector<double> elementEnergy_;
};

}  // namespace jetshell
