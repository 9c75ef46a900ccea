#include "solvers/objective.h"

#include "core/mesh.h"

#include <omp.h>

#include <algorithm>
#include <chrono>
#include <cmath>
#include <exception>
#include <limits>
#include <sstream>
#include <thread>

namespace jetshell {

Objective::Objective(int numVertices) : numVertices_(numVertices), numFree_(3 * numVertices) {
  if (numVertices <= 0) throw InputError("objective: numVertices must be > 0");
  fixedDof_.assign(3 * static_cast<std::size_t>(numVertices), 0);
}

void Objective::addTerm(EnergyTermPtr term, TermRole role) {
  if (!term) throw InputError("objective: null term");
  if (finalized()) throw InputError("objective: addTerm(" + term->name() + ") after finalize()");
  // Against every earlier name at once: a scene with one contact term per volume actor and thousands of actors
  // made a scan of the earlier names quadratic (20,000 spheres: minutes before the first step).
  const std::string name = term->name();
  if (!termNames_.insert(name).second) throw InputError("objective: duplicate term name '" + name + "'");
  const StencilTable table = term->stencils();
  const int slot = table.width > 0 ? assembler_.addStencils(table) : -1;
  const std::uint64_t version = term->stencilVersion();
  terms_.push_back({std::move(term), role, slot, 3 * table.width, version});
  termEnergies_.push_back(0.0);
  termSeconds_.push_back(0.0);
  termRequests_.emplace_back();
}

void Objective::setPrescribed(PrescribedPositions prescribed) {
  if (finalized()) throw InputError("objective: setPrescribed after finalize()");
  fixedDof_ = prescribed.dofMask(numVertices_);
  prescribed_ = std::move(prescribed);
  numFree_ = 0;
  for (char f : fixedDof_) numFree_ += f ? 0 : 1;
}

void Objective::finalize() {
  if (!finalized()) assembler_.finalize(numVertices_, fixedDof_);
}

double Objective::evaluate(const Eigen::VectorXd& x, Eigen::VectorXd* gradient, bool hessian,
                           const EvalOptions& options, TermSelection selection,
                           const NarrowAssembledHook& narrowAssembled) {
  if (x.size() != numDofs()) throw InputError("objective: x has the wrong size");
  using Clock = std::chrono::steady_clock;
  const auto stencilStart = Clock::now();
  bool changed = false;
  for (Entry& e : terms_) {
    e.term->updateStencils(x);
    changed = changed || e.term->stencilVersion() != e.stencilVersion;
  }
  // Only a Hessian needs the pattern: value and gradient evaluations (line-search trials, iterate tests) leave it
  // stale, and the next Hessian evaluation, which compares the versions again, rebuilds it once.
  // A pattern finalized here starts with zero values (HessianAssembler::finalize): only a kept one is cleared.
  const bool zeroed = (changed && hessian) || !finalized();
  if (changed && hessian) {
    const auto patternStart = Clock::now();
    rebuildPattern();
    patternSeconds_ += std::chrono::duration<double>(Clock::now() - patternStart).count();
  }
  stencilSeconds_ += std::chrono::duration<double>(Clock::now() - stencilStart).count();
  finalize();
  if (gradient != nullptr) gradient->setZero(numDofs());
  if (hessian && !zeroed) assembler_.setZero();
  // The Potential terms' partial sum is kept when they all come first (lastPotentialGradient()).
  bool potentialsFirst = gradient != nullptr;
  if (gradient != nullptr) potentialGradientValid_ = false;
  auto keepPotentialGradient = [&]() {
    potentialGradient_ = *gradient;
    zeroFixed(potentialGradient_);
    potentialGradientX_ = x;
    potentialGradientPath_ = options.path;
    potentialGradientValid_ = true;
    potentialsFirst = false;
  };
  double total = 0.0;
  auto evaluateTerm = [&](std::size_t i) {
    Entry& e = terms_[i];
    if (e.role != TermRole::Potential && potentialsFirst) keepPotentialGradient();
    if (selection == TermSelection::PotentialOnly && e.role != TermRole::Potential) {
      termEnergies_[i] = 0.0;
      return;
    }
    if (e.role == TermRole::Potential && gradient != nullptr) potentialGradientValid_ = false;  // interleaved
    EvalRequest request{gradient, hessian && e.slot >= 0 ? &assembler_ : nullptr, e.slot};
    const auto termStart = Clock::now();
    EvalOptions termOptions = options;
    if (options.projectionMaxBlockDofs > 0 && e.blockDofs > options.projectionMaxBlockDofs)
      termOptions.projection = PsdProjection::None;
    termEnergies_[i] = e.term->evaluate(x, request, termOptions);
    const double seconds = std::chrono::duration<double>(Clock::now() - termStart).count();
    termSeconds_[i] += seconds;
    const RequestKind kind = request.hessian == nullptr ? (gradient != nullptr ? RequestKind::Gradient : RequestKind::Value)
                             : termOptions.projection != PsdProjection::None ? RequestKind::ProjectedHessian
                                                                             : RequestKind::Hessian;
    TermRequests& r = termRequests_[i];
    ++r.calls[static_cast<std::size_t>(kind)];
    r.seconds[static_cast<std::size_t>(kind)] += seconds;
    total += termEnergies_[i];
  };
  if (!hessian || !narrowAssembled) {
    for (std::size_t i = 0; i < terms_.size(); ++i) evaluateTerm(i);
  } else {
    auto narrow = [&](std::size_t i) { return terms_[i].slot < 0 || terms_[i].blockDofs <= kNarrowBlockDofs; };
    for (std::size_t i = 0; i < terms_.size(); ++i)
      if (narrow(i)) evaluateTerm(i);
    const std::function<void()> task = narrowAssembled(assembler_);
    auto evaluateWide = [&] {
      for (std::size_t i = 0; i < terms_.size(); ++i)
        if (!narrow(i)) evaluateTerm(i);
    };
    const int threads = omp_get_max_threads();
    if (!task) {
      evaluateWide();
    } else if (threads < 2) {
      task();
      evaluateWide();
    } else {
      // The task takes one core, the wide terms the rest.
      std::exception_ptr taskError;
      std::thread worker([&task, &taskError] {
        try {
          task();
        } catch (...) {
          taskError = std::current_exception();
        }
      });
      omp_set_num_threads(threads - 1);
      std::exception_ptr wideError;
      try {
        evaluateWide();
      } catch (...) {
        wideError = std::current_exception();
      }
      omp_set_num_threads(threads);
      worker.join();
      if (wideError) std::rethrow_exception(wideError);
      if (taskError) std::rethrow_exception(taskError);
    }
  }
  if (potentialsFirst) keepPotentialGradient();
  if (gradient != nullptr) zeroFixed(*gradient);
  return total;
}

const Eigen::VectorXd* Objective::lastPotentialGradient(const Eigen::VectorXd& x, DerivativePath path) const {
  if (!potentialGradientValid_ || path != potentialGradientPath_ || x.size() != potentialGradientX_.size())
    return nullptr;
  // Exactly the same positions (a NaN never matches).
  for (Eigen::Index i = 0; i < x.size(); ++i)
    if (!(x[i] == potentialGradientX_[i])) return nullptr;
  return &potentialGradient_;
}

void Objective::rebuildPattern() {
  // Only the terms whose stencils moved are declared again (the assembler keeps or translates the others'
  // scatter tables), unless a term's stencil width changed: then every slot anew.
  bool sameSlots = assembler_.numSlots() > 0;
  for (const Entry& e : terms_) {
    if (!sameSlots) break;
    if (e.term->stencilVersion() == e.stencilVersion) continue;
    const int width = e.term->stencils().width;
    sameSlots = e.slot >= 0 ? width == assembler_.stencils(e.slot).width : width == 0;
  }
  if (!sameSlots) assembler_.clearStencils();
  for (Entry& e : terms_) {
    if (sameSlots && e.term->stencilVersion() == e.stencilVersion) continue;
    const StencilTable table = e.term->stencils();
    if (sameSlots) {
      if (e.slot >= 0) assembler_.replaceStencils(e.slot, table);
    } else {
      e.slot = table.width > 0 ? assembler_.addStencils(table) : -1;
    }
    e.blockDofs = 3 * table.width;
    e.stencilVersion = e.term->stencilVersion();
  }
  assembler_.finalize(numVertices_, fixedDof_);
  ++patternRebuilds_;
}

void Objective::beginStep(const Eigen::VectorXd& xStart, double tStart, double timeStep) {
  for (const StepStartHook& h : stepStartHooks_) h(xStart, tStart, timeStep);
}

double Objective::stepBound(const Eigen::VectorXd& x, const Eigen::VectorXd& direction) const {
  double alpha = 1.0;
  for (const StepBound& b : stepBounds_) {
    const double a = b(x, direction);
    if (std::isfinite(a) && a > 0.0) alpha = std::min(alpha, a);
  }
  return alpha;
}

void Objective::zeroFixed(Eigen::VectorXd& v) const {
  for (std::size_t d = 0; d < fixedDof_.size(); ++d)
    if (fixedDof_[d]) v[static_cast<Eigen::Index>(d)] = 0.0;
}

std::vector<std::string> Objective::activeTermNames() const {
  std::vector<std::string> names;
  for (const Entry& e : terms_) names.push_back(e.term->name());
  return names;
}

EnergyTermPtr Objective::term(const std::string& name) const {
  for (const Entry& e : terms_)
    if (e.term->name() == name) return e.term;
  return nullptr;
}

bool Objective::hasMovingStencils() const {
  for (const Entry& e : terms_)
    if (e.term->stencilsFollowConfiguration()) return true;
  return false;
}

double Objective::energyMagnitude() const {
  double m = 0.0;
  for (double e : termEnergies_) m += std::abs(e);
  return m;
}

void Objective::setPrescribedPath(double from, double to, double solidMotion) {
  prescribedPathMotion_ = std::isfinite(solidMotion) ? std::max(0.0, solidMotion) : 0.0;
  if (!std::isfinite(from) || !std::isfinite(to) || scales_.reference.size() != numDofs()) return;
  // Samples of the path: from 0 to 1, an end turned by 720° peaks at λ = 1/4 and 3/4, both samples.
  constexpr int kSamples = 64;
  for (int k = 0; k <= kSamples; ++k) {
    const double t = from + (to - from) * k / kSamples;
    for (const PrescribedPositions::Entry& e : prescribed_.entries()) {
      if (!e.value) continue;  // a constant: the configuration's own displacement has it
      const double moved = std::abs(e.value(t) - scales_.reference[3 * e.vertex + e.component]);
      if (std::isfinite(moved)) prescribedPathMotion_ = std::max(prescribedPathMotion_, moved);
    }
  }
}

ForceScale Objective::forceScale(const Eigen::VectorXd& x, double initialResidual) const {
  ForceScale f;
  if (scales_.force > 0.0) f = {scales_.force, "external_loads"};
  if (scales_.stiffness > 0.0 && scales_.reference.size() == x.size()) {
    // A displacement within the round-off of the coordinates is no motion (an end turned by exactly 360° lands
    // 1e-17 m off its reference: that gave a scale of 1e-13 N, and relaxation ran to its step limit at rest).
    constexpr double kRoundOff = 64.0 * std::numeric_limits<double>::epsilon();
    double moved = prescribedPathMotion_;
    for (Eigen::Index i = 0; i < x.size(); ++i) {
      if (!fixedDof_[static_cast<std::size_t>(i)]) continue;
      const double d = std::abs(x[i] - scales_.reference[i]);
      if (d > kRoundOff * (std::abs(scales_.reference[i]) + scales_.length)) moved = std::max(moved, d);
    }
    const double prescribed = scales_.stiffness * moved;
    if (prescribed > f.value) f = {prescribed, "prescribed_motion"};
  }
  if (!(f.value > 0.0) && scales_.stiffness > 0.0) f = {scales_.stiffness * scales_.length, "material"};
  if (!(f.value > 0.0) || !std::isfinite(f.value)) f = {initialResidual, "initial_residual"};
  return f;
}

}  // namespace jetshell
