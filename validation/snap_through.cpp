// The hinged cylindrical roof (validation/snap_through.h): the case, the two traces and their comparison.
#include "validation/snap_through.h"

#include "core/format.h"
#include "core/mesh.h"
#include "core/mesh_generators.h"
#include "energies/shell/material.h"
#include "solvers/path_following.h"

#include <algorithm>
#include <chrono>
#include <limits>
#include <cmath>
#include <cstdio>
#include <ostream>
#include <sstream>

namespace jetshell::validation {
namespace {

constexpr double kRadius = 2540.0, kLength = 508.0, kArc = 0.2;  // half-length 254, half-angle 0.1 rad
constexpr double kYoungsModulus = 3102.75, kPoissonRatio = 0.3;

struct RoofCase {
  BenchmarkCase c;
  int loadVertex = 0;
};

RoofCase roofCase(const RoofOptions& o) {
  const int n1 = o.resolution.n1, n2 = o.resolution.n2;
  if (n1 < 2 || n2 < 2 || n1 % 2 || n2 % 2)
    throw InputError("hinged-cylindrical-roof: --mesh N1xN2 needs even counts >= 2 (the load sits on the middle node)");
  RoofCase r;
  ShellProblem& p = r.c.problem;
  p.mesh = makeCylinder(kRadius, kLength, kArc, n1, n2);
  p.material = ShellMaterialParamsFrom3dIsotropic(kYoungsModulus, kPoissonRatio, 1.0, o.thickness);
  p.hasGravity = false;
  p.gravity.setZero();
  const int columns = n1 + 1;
  for (int j = 0; j <= n2; ++j)
    for (int i : {0, n1}) p.prescribed.fixVertex(j * columns + i, p.mesh.V.row(j * columns + i).transpose());
  r.loadVertex = (n2 / 2) * columns + n1 / 2;
  p.nodalForces = Eigen::VectorXd::Zero(3 * p.mesh.numVertices());
  p.nodalForces[3 * r.loadVertex + 2] = -o.load;
  r.c.probes = {Probe{{r.loadVertex}, 2, -1.0}};
  return r;
}

/// The parabola through three points, at s.
double quadratic(const double p[3], const double v[3], double s) {
  double sum = 0.0;
  for (int i = 0; i < 3; ++i) {
    double w = 1.0;
    for (int j = 0; j < 3; ++j)
      if (j != i) w *= (s - p[j]) / (p[i] - p[j]);
    sum += w * v[i];
  }
  return sum;
}

RoofTrace trace(const RoofCase& rc, PathControl control, const RoofOptions& o, const std::vector<double>& levels = {}) {
  const auto start = std::chrono::steady_clock::now();
  ShellSystem system(rc.c.problem, AnalysisKind::Statics);
  BenchmarkRunOptions bo;
  bo.freeRule = o.edgeRule;
  addBoundaryRules(system, rc.c, bo);
  LoadSteppingOptions so;
  so.newton = staticNewtonOptions();
  so.newton.residualTolerance = o.residualTolerance;
  so.initialIncrement = std::min(o.increment, o.maxIncrement);
  so.maxIncrement = o.maxIncrement;
  so.levels = levels;
  so.minIncrement = 1e-5;
  so.path.control = control;
  so.path.maxSteps = o.maxSteps;
  so.path.loadScaling = o.loadScaling;
  so.path.controlledDof = 3 * rc.loadVertex + 2;
  so.path.displacement = -o.maxDeflection;
  RoofTrace t;
  t.control = control;
  t.load = {0.0};
  t.deflection = {0.0};
  t.parameter = {0.0};
  const Eigen::VectorXd X = system.restPositions();
  Eigen::VectorXd x = X;
  const StaticsResult r = solveStatics(system, x, so, [&](const LoadStepResult& s) {
    const double w = rc.c.probes[0].read(s.x, X);
    if (o.log != nullptr)
      *o.log << "  " << toString(control) << " step " << s.step << ": P = " << o.load * s.loadFactor << " N, w = " << w
             << " mm, " << s.summary.iterations << " iterations, " << s.negativePivots << " negative pivots"
             << (s.atLevel ? " (level)" : "") << "\n";
    t.maxNegativePivots = std::max(t.maxNegativePivots, s.negativePivots);
    // Arc length's landing on the target is on the path but not one of its points.
    if (control == PathControl::ArcLength && s.atLevel) return true;
    t.load.push_back(o.load * s.loadFactor);
    t.deflection.push_back(w);
    t.parameter.push_back(s.pathParameter);
    return true;
  });
  t.completed = r.completed;
  t.message = r.message;
  t.pathPoints = static_cast<int>(t.load.size()) - 1;
  t.newtonIterations = r.newtonIterations;
  t.cuts = r.totalCuts;
  t.jumps = r.loadJumps;
  for (std::size_t i = 1; i + 1 < t.load.size(); ++i) {
    const double before = t.load[i] - t.load[i - 1], after = t.load[i + 1] - t.load[i];
    if (!(before * after < 0.0)) continue;
    const double p[3] = {t.parameter[i - 1], t.parameter[i], t.parameter[i + 1]};
    const double l[3] = {t.load[i - 1], t.load[i], t.load[i + 1]};
    const double w[3] = {t.deflection[i - 1], t.deflection[i], t.deflection[i + 1]};
    const double s = parabolaVertex(p, l);
    t.limits.push_back({before > 0.0, quadratic(p, l, s), quadratic(p, w, s), static_cast<int>(i)});
  }
  t.wallSeconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
  return t;
}

/// P of the displacement-controlled trace at deflection w: the point that landed there, or NaN.
double loadAt(const RoofTrace& d, double w) {
  for (std::size_t j = 0; j < d.deflection.size(); ++j)
    if (std::abs(d.deflection[j] - w) <= 1e-9 * std::max(1.0, std::abs(w))) return d.load[j];
  return std::nan("");
}

nlohmann::json toJson(const RoofTrace& t) {
  nlohmann::json jumps = nlohmann::json::array();
  for (const LoadJump& j : t.jumps) jumps.push_back(toJson(j));
  nlohmann::json limits = nlohmann::json::array();
  for (const RoofLimit& l : t.limits)
    limits.push_back({{"kind", l.maximum ? "maximum" : "minimum"}, {"load", l.load}, {"deflection", l.deflection},
                      {"path_point", l.step}});
  return {{"control", toString(t.control)}, {"completed", t.completed}, {"message", t.message},
          {"path_points", t.pathPoints}, {"newton_iterations", t.newtonIterations}, {"cuts", t.cuts},
          {"wall_seconds", t.wallSeconds}, {"max_negative_pivots", t.maxNegativePivots}, {"limit_points", limits},
          {"load", t.load}, {"deflection", t.deflection}, {"jumps", jumps}};
}

}  // namespace

RoofResult runHingedRoof(const RoofOptions& o) {
  const RoofCase rc = roofCase(o);
  RoofResult r;
  r.options = o;
  r.vertices = rc.c.problem.mesh.numVertices();
  r.faces = rc.c.problem.mesh.numFaces();
  r.arc = trace(rc, PathControl::ArcLength, o);
  // Displacement control lands on every deflection the arc-length trace reached (as fractions of maxDeflection).
  std::vector<double> levels;
  for (std::size_t i = 1; i < r.arc.deflection.size(); ++i) {
    const double tau = r.arc.deflection[i] / o.maxDeflection;
    if (tau > 1e-12 && tau < 1.0) levels.push_back(tau);
  }
  std::sort(levels.begin(), levels.end());
  levels.erase(std::unique(levels.begin(), levels.end(), [](double a, double b) { return b - a <= 1e-12; }),
               levels.end());
  r.displacement = trace(rc, PathControl::Displacement, o, levels);
  const std::vector<RoofLimit>& a = r.arc.limits;
  const std::vector<RoofLimit>& d = r.displacement.limits;
  r.bothLimitsPassed = r.arc.completed && a.size() >= 2 && a[0].maximum && !a[1].maximum;
  // Displacement control follows w; where the arc-length path turns back in w (a snap-back) the two controls
  // can meet different equilibria at the same w, so the comparison stops at the first such turn.
  std::size_t single = r.arc.deflection.size();
  for (std::size_t i = 1; i < r.arc.deflection.size(); ++i)
    if (r.arc.deflection[i] < r.arc.deflection[i - 1]) {
      single = i - 1;  // and not the point at the turn, where w is stationary (displacement control is singular)
      break;
    }
  r.singleValuedPoints = static_cast<int>(single) - 1;
  const double inf = std::numeric_limits<double>::infinity();
  r.limitLoadDifference = r.limitDeflectionDifference = r.curveDifference = inf;
  if (!d.empty() && d[0].maximum) {
    const double pmax = std::abs(d[0].load);
    r.limitLoadDifference = r.limitDeflectionDifference = 0.0;
    int matched = 0;
    for (std::size_t k = 0; k < a.size() && k < d.size(); ++k) {
      if (static_cast<std::size_t>(a[k].step) + 1 >= single) break;
      r.limitLoadDifference = std::max(r.limitLoadDifference, std::abs(a[k].load - d[k].load) / pmax);
      r.limitDeflectionDifference =
          std::max(r.limitDeflectionDifference, std::abs(a[k].deflection - d[k].deflection) / std::abs(d[k].deflection));
      ++matched;
    }
    r.comparedLimits = matched;
    if (matched == 0) r.limitLoadDifference = r.limitDeflectionDifference = inf;
    int compared = 0;
    r.curveDifference = 0.0;
    for (std::size_t i = 1; i < single; ++i) {
      const double pd = loadAt(r.displacement, r.arc.deflection[i]);
      if (!std::isfinite(pd)) continue;
      r.curveDifference = std::max(r.curveDifference, std::abs(r.arc.load[i] - pd) / pmax);
      ++compared;
    }
    r.comparedPoints = compared;
  }
  return r;
}

std::string formatRoof(const RoofResult& r) {
  std::ostringstream s;
  s << "Hinged cylindrical roof under a central point load (Sze et al. 2004), h = " << r.options.thickness << ", P = "
    << r.options.load << " at lambda = 1\n"
    << "  mesh " << r.options.resolution.n1 << " x " << r.options.resolution.n2 << " (quads across the arc x along), "
    << r.vertices << " vertices, " << r.faces << " faces; edges " << edgeRuleName(r.options.edgeRule) << "\n";
  for (const RoofTrace* t : {&r.arc, &r.displacement}) {
    s << "  " << toString(t->control) << " control: " << (t->completed ? "completed" : "NOT completed") << ", "
      << t->pathPoints << " path points, " << t->newtonIterations << " Newton iterations, " << t->cuts << " cuts, "
      << formatNumber("%.2f", t->wallSeconds) << " s wall, at most " << t->maxNegativePivots
      << " negative pivots; " << t->message << "\n";
    for (const RoofLimit& l : t->limits)
      s << "    limit point (" << (l.maximum ? "maximum: the load turns down" : "minimum: the load turns up")
        << ") P = " << formatNumber("%.2f", l.load) << " N at w = " << formatNumber("%.3f", l.deflection) << " mm (path point "
        << l.step << ")\n";
  }
  s << "  both limit points passed by arc length: " << (r.bothLimitsPassed ? "yes" : "no") << "\n"
    << "  arc length vs displacement control: limit loads " << formatNumber("%.4f", 100.0 * r.limitLoadDifference)
    << "% of P_max, limit deflections " << formatNumber("%.4f", 100.0 * r.limitDeflectionDifference)
    << "% (" << r.comparedLimits << " limit points before the path turns back in w, if it does: "
    << r.singleValuedPoints << " of " << r.arc.pathPoints << " points)"
    << "; load at the same deflection (" << r.comparedPoints << " points) " << formatNumber("%.2e", 100.0 * r.curveDifference)
    << "% of P_max\n";
  return s.str();
}

nlohmann::json toJson(const RoofResult& r) {
  auto finiteOrNull = [](double v) { return std::isfinite(v) ? nlohmann::json(v) : nlohmann::json(nullptr); };
  return {{"name", "hinged-cylindrical-roof"},
          {"thickness", r.options.thickness},
          {"load", r.options.load},
          {"mesh", std::to_string(r.options.resolution.n1) + "x" + std::to_string(r.options.resolution.n2)},
          {"vertices", r.vertices},
          {"faces", r.faces},
          {"both_limits_passed", r.bothLimitsPassed},
          {"limit_load_difference", finiteOrNull(r.limitLoadDifference)},
          {"limit_deflection_difference", finiteOrNull(r.limitDeflectionDifference)},
          {"curve_difference", finiteOrNull(r.curveDifference)},
          {"compared_points", r.comparedPoints},
          {"compared_limits", r.comparedLimits},
          {"single_valued_points", r.singleValuedPoints},
          {"arc_length", toJson(r.arc)},
          {"displacement", toJson(r.displacement)}};
}

}  // namespace jetshell::validation
