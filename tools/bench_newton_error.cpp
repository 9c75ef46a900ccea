#include "tools/bench_newton_error.h"

#include "solvers/step_error_check.h"

#include <algorithm>
#include <cstdio>
#include <sstream>
#include <utility>

namespace jetshell::cli {

std::string traceLine(const SolverSummary& s) {
  std::ostringstream o;
  o.precision(3);
  for (const IterationRecord& r : s.trace)
    o << " [" << r.iteration << ": a " << r.stepLength << " move " << r.largestMove
      << (r.unprojected ? " unprojected" : r.exactHessian ? " exact" : " projected")
      << (r.shift > 0.0 ? " shifted" : "") << "]";
  o << " -> " << s.message;
  return o.str();
}

namespace {

bool passedIterateTest(const SolverSummary& s) {
  return s.converged() && s.convergenceTest == "iterate" && s.iterateThreshold > 0.0;
}

}  // namespace

void NewtonErrorTally::check(const StepReport& rep, DynamicsSolver& run, DynamicsSolver& tight,
                             const DynamicsSolver::Snapshot& before) {
  if (rep.solves.empty() || takenInParts(rep)) return;  // its parts were checked one by one (checkPart)
  const SolverSummary& loose = rep.solves.front();
  const bool movedOn = rep.movedOn > 0;
  if (!passedIterateTest(loose) && !movedOn) return;
  record(loose, movedOn, rep.step, false, checkStepError(rep, run, tight, before));
}

void NewtonErrorTally::checkPart(const SubstepView& part, int step, DynamicsSolver& tight) {
  if (!passedIterateTest(*part.solve) && !part.movedOn) return;
  record(*part.solve, part.movedOn, step, true, checkPartError(part, tight));
}

NewtonErrorWatch::NewtonErrorWatch(DynamicsSolver& run, std::unique_ptr<ShellSystem> tightSystem)
    : run_(run), system_(std::move(tightSystem)), tight_(*system_, tightStepOptions(run.options())) {
  before_ = run_.snapshot();
  const double h = run_.options().timeStep;
  run_.setSubstepObserver([this, h](const SubstepView& part) {
    if (part.timeStep < h) tally_.checkPart(part, run_.stepCount() + 1, tight_);
  });
}

NewtonErrorWatch::~NewtonErrorWatch() { run_.setSubstepObserver({}); }

void NewtonErrorWatch::afterStep(const StepReport& rep) {
  tally_.check(rep, run_, tight_, before_);
  before_ = run_.snapshot();
}

void NewtonErrorTally::record(const SolverSummary& loose, bool movedOn, int step, bool part,
                              const StepErrorCheck& t) {
  if (!t.checked) {
    ++unchecked_[movedOn ? "moved on at the iteration cap" : loose.iterateEstimate];
    if (firstUnchecked_.empty()) {
      std::ostringstream why;
      why << "step " << step << (part ? " (a part of it)" : "") << ": ";
      if (!t.solvedAgain) why << (part ? "a BDF2 solve" : "solved again from x_n, two solves");
      else if (!t.tight.solves.empty()) why << "tight: " << t.tight.solves.size() << " solves, " << t.tight.cuts
                                            << " cuts; first:" << traceLine(t.tight.solves.front());
      firstUnchecked_ = why.str();
    }
    return;
  }
  if (movedOn) {
    ++movedOn_.steps;
    if (part) ++movedOn_.parts;
    movedOn_.worstError = std::max(movedOn_.worstError, t.error);
    const double relative = t.change > 0.0 ? t.error / t.change : 0.0;
    if (relative > movedOn_.worstRelative) {
      movedOn_.worstRelative = relative;
      movedOn_.worstStep = step;
    }
    return;
  }
  const double ratio = t.error / loose.iterateThreshold;
  auto it = std::find_if(checks_.begin(), checks_.end(), [&](const auto& c) { return c.first == loose.iterateEstimate; });
  if (it == checks_.end()) it = checks_.insert(checks_.end(), {loose.iterateEstimate, EstimateCheck{}});
  EstimateCheck& c = it->second;
  ++c.passes;
  if (part) ++c.parts;
  if (ratio > 1.0) {
    ++c.aboveBound;
    if (part) ++c.partsAbove;
  }
  if (ratio > c.worstRatio) {
    c.worstRatio = ratio;
    c.worstStep = step;
    c.worstTrace = std::string(part ? "passed (a part of the step):" : "passed:") + traceLine(loose) +
                   "\n      tight: " + traceLine(t.tight.solves.front());
  }
}

nlohmann::json NewtonErrorTally::toJson() const {
  nlohmann::json j = nlohmann::json::object();
  for (const auto& [name, c] : checks_)
    j[name] = {{"passes", c.passes},         {"parts", c.parts},           {"above_threshold", c.aboveBound},
               {"parts_above", c.partsAbove}, {"worst_ratio", c.worstRatio}, {"worst_step", c.worstStep}};
  j["moved_on_at_cap"] = {{"steps", movedOn_.steps}, {"parts", movedOn_.parts}, {"worst_error_m", movedOn_.worstError},
                          {"worst_error_over_change", movedOn_.worstRelative}, {"worst_step", movedOn_.worstStep}};
  j["unchecked"] = unchecked_;  // by kind
  return j;
}

void NewtonErrorTally::print(const char* indent) const {
  for (const auto& [name, c] : checks_)
    std::printf("%snewton error, %s: %d passes (%d of them parts of steps), %d above their threshold (%d parts), "
                "worst %.3g x at step %d\n%s    %s\n",
                indent, name.c_str(), c.passes, c.parts, c.aboveBound, c.partsAbove, c.worstRatio, c.worstStep, indent,
                c.worstTrace.c_str());
  if (movedOn_.steps > 0)
    std::printf("%snewton error, moved on at the iteration cap: %d solves (%d of them parts of steps), worst %.3g "
                "mm, worst %.3g x the solve's change (step %d)\n",
                indent, movedOn_.steps, movedOn_.parts, 1e3 * movedOn_.worstError, movedOn_.worstRelative,
                movedOn_.worstStep);
  for (const auto& [kind, n] : unchecked_)
    std::printf("%snewton error, %s: %d solves not checked (the tight solve did not converge, or the step was "
                "solved again from x_n)\n",
                indent, kind.c_str(), n);
  if (!unchecked_.empty()) std::printf("%s    the first, %s\n", indent, firstUnchecked_.c_str());
}

}  // namespace jetshell::cli
