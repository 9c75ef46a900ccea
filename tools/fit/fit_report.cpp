#include "tools/fit/fit_report.h"

#include "core/format.h"
#include "core/mesh.h"
#include "tools/output/atomic_file.h"
#include "tools/render/plot.h"

#include <cmath>
#include <filesystem>
#include <limits>
#include <map>
#include <sstream>

namespace jetshell {
namespace {

nlohmann::json number(double v) { return std::isfinite(v) ? nlohmann::json(v) : nlohmann::json(nullptr); }

std::string format(double v) { return formatNumber("%.9g", v); }

/// Observed and fitted displacements of every observed coordinate.
struct Displacements {
  std::vector<double> observed, fitted;
};

Displacements displacements(const FitReportInputs& in) {
  Displacements d;
  const FitResult& r = *in.result;
  if (r.equilibria.empty()) return d;
  for (const ObservedCoordinate& o : in.problem->observed()) {
    const double rest = in.problem->rest()[o.dof];
    d.observed.push_back(o.target - rest);
    d.fitted.push_back(r.equilibria[static_cast<std::size_t>(o.level)][o.dof] - rest);
  }
  return d;
}

}  // namespace

nlohmann::json fitReportJson(const FitReportInputs& in) {
  const FitResult& r = *in.result;
  nlohmann::json j;
  j["fit_file"] = in.fitFile;
  j["description"] = in.description;
  j["algorithm"] = toString(r.algorithm);
  j["success"] = r.success;
  j["termination"] = r.termination;
  j["message"] = r.message;
  j["iterations"] = r.iterations;
  if (r.q.size() > 0) j["misfit"] = number(r.misfit);  // none when no evaluation succeeded
  j["wall_seconds"] = r.wallSeconds;
  nlohmann::json params = nlohmann::json::array();
  for (std::size_t i = 0; i < r.variables.size(); ++i) {
    const FitVariable& v = r.variables[i];
    nlohmann::json p;
    p["name"] = v.label;
    p["initial"] = v.initial;
    p["lower"] = v.lower;
    p["upper"] = v.upper;
    p["log_scale"] = v.logScale;
    p["value"] = r.q.size() > 0 ? number(r.q[static_cast<Eigen::Index>(i)]) : nlohmann::json(nullptr);
    p["standard_deviation"] = r.uncertainty.available
                                  ? number(r.uncertainty.standardDeviation[static_cast<Eigen::Index>(i)])
                                  : nlohmann::json(nullptr);
    params.push_back(p);
  }
  j["parameters"] = params;
  nlohmann::json u;
  u["available"] = r.uncertainty.available;
  u["method"] = r.uncertainty.message;
  if (r.uncertainty.available) {
    u["residual_variance"] = number(r.uncertainty.residualVariance);
    nlohmann::json c = nlohmann::json::array();
    for (Eigen::Index a = 0; a < r.uncertainty.correlation.rows(); ++a) {
      nlohmann::json row = nlohmann::json::array();
      for (Eigen::Index b = 0; b < r.uncertainty.correlation.cols(); ++b) row.push_back(number(r.uncertainty.correlation(a, b)));
      c.push_back(row);
    }
    u["correlation"] = c;
  }
  j["uncertainty"] = u;
  const FitCounters& k = r.counters;
  j["cost"] = {{"evaluations", k.evaluations},
               {"full_solves", k.fullSolves},
               {"newton_iterations", k.newtonIterations},
               {"newton_factorizations", k.newtonFactorizations},
               {"gradient_evaluations", k.gradientEvaluations},
               {"jacobian_evaluations", k.jacobianEvaluations},
               {"sensitivity_factorizations", k.sensitivityFactorizations},
               {"sensitivity_solves", k.sensitivitySolves},
               {"time_steps", k.timeSteps},
               {"inexact_derivative_solves", k.inexactDerivativeSolves}};
  // Whether the gradients and Jacobians were those of the computed states (FitEvaluation::derivativesExact).
  j["gradient_status"] =
      r.inexactDerivativeEvaluations == 0
          ? "exact"
          : "approximate: " + std::to_string(r.inexactDerivativeEvaluations) +
                " evaluation(s) differentiated through time steps accepted at the Newton iteration cap "
                "(acceptIterationCap); their gradients are not those of the computed trajectory";
  nlohmann::json history = nlohmann::json::array();
  for (const FitRecord& h : r.history) {
    nlohmann::json e;
    e["evaluation"] = h.evaluation;
    e["ok"] = h.ok;
    // A failed evaluation has no misfit, and a gradient not computed no norm: the keys are left out.
    if (h.ok && std::isfinite(h.misfit)) e["misfit"] = number(h.misfit);
    if (h.ok && h.gradientNorm >= 0.0 && std::isfinite(h.gradientNorm)) {
      e["gradient_norm"] = number(h.gradientNorm);
      e["gradient_exact"] = h.exactGradient;
    }
    std::vector<double> q(h.q.data(), h.q.data() + h.q.size());
    e["parameters"] = q;
    history.push_back(e);
  }
  j["history"] = history;
  j["levels"] = in.problem->levels();
  j["level_kind"] = in.problem->levelName();
  nlohmann::json groups = nlohmann::json::array();
  const Displacements d = displacements(in);
  for (std::size_t g = 0; g < in.groupLabels.size(); ++g) {
    nlohmann::json e;
    e["observation"] = in.groupLabels[g];
    double sum = 0.0;
    int count = 0;
    for (std::size_t i = 0; i < in.problem->observed().size(); ++i) {
      if (in.problem->observed()[i].group != static_cast<int>(g) || d.fitted.empty()) continue;
      sum += (d.fitted[i] - d.observed[i]) * (d.fitted[i] - d.observed[i]);
      ++count;
    }
    e["coordinates"] = count;
    e["rms_error"] = count > 0 ? number(std::sqrt(sum / count)) : nlohmann::json(nullptr);
    groups.push_back(e);
  }
  j["observations"] = groups;
  return j;
}

std::vector<std::string> writeFitReport(const FitReportInputs& in, const std::string& directory, bool plots,
                                        std::vector<std::string>& notes) {
  namespace fs = std::filesystem;
  std::error_code ec;
  fs::create_directories(directory, ec);
  if (ec) throw InputError(directory + ": cannot create the output directory (" + ec.message() + ")");
  std::vector<std::string> written;
  const std::string jsonPath = (fs::path(directory) / "fit.json").string();
  writeFileAtomically(jsonPath, fitReportJson(in).dump(2) + "\n");
  written.push_back(jsonPath);
  if (!plots) return written;
  // A plot that cannot be drawn is a note: fit.json, the result, is already written.
  const auto draw = [&](const PlotSpec& spec, const std::string& name) {
    const std::string path = (fs::path(directory) / name).string();
    try {
      plotPng(spec, path);
      written.push_back(path);
    } catch (const InputError& e) {
      notes.push_back(name + " not drawn: " + e.what());
    }
  };
  const FitResult& r = *in.result;
  {
    PlotSpec p;
    p.title = "Misfit history (" + std::string(toString(r.algorithm)) + ")";
    p.xLabel = "evaluation";
    p.yLabel = "misfit";
    p.logY = true;
    PlotSeries all("every evaluation", {}, {}, "points", "#7f7f7f"), best("best so far", {}, {}, "lines", "#1f77b4");
    double bestValue = std::numeric_limits<double>::infinity();
    for (const FitRecord& h : r.history) {
      if (!h.ok || !(h.misfit > 0.0)) continue;  // log scale: exact zeros and failures are not drawn
      all.x.push_back(h.evaluation);
      all.y.push_back(h.misfit);
      bestValue = std::min(bestValue, h.misfit);
      best.x.push_back(h.evaluation);
      best.y.push_back(bestValue);
    }
    p.series = {all, best};
    if (!all.x.empty()) draw(p, "misfit_history.png");
  }
  const Displacements d = displacements(in);
  if (!d.fitted.empty()) {
    PlotSpec p;
    p.title = "Fitted against observed displacements";
    p.xLabel = "observed displacement [m]";
    p.yLabel = "fitted displacement [m]";
    double lo = std::numeric_limits<double>::infinity(), hi = -lo;
    for (double v : d.observed) lo = std::min(lo, v), hi = std::max(hi, v);
    p.series = {PlotSeries("y = x", {lo, hi}, {lo, hi}, "lines", "#7f7f7f", 2),
                PlotSeries("observed coordinates", d.observed, d.fitted, "points", "#d62728")};
    draw(p, "fit_vs_observed.png");
    // Load–displacement curves of the observations that span several levels.
    PlotSpec c;
    c.title = "Load-displacement: observed (points) and fitted (lines)";
    c.xLabel = in.problem->levelName() == "time" ? "time [s]" : in.problem->levelName();
    c.yLabel = "displacement [m]";
    for (std::size_t g = 0; g < in.groupLabels.size(); ++g) {
      std::map<int, std::map<int, std::pair<double, double>>> byDof;  // dof → level → (observed, fitted)
      for (std::size_t i = 0; i < in.problem->observed().size(); ++i) {
        const ObservedCoordinate& o = in.problem->observed()[i];
        if (o.group == static_cast<int>(g)) byDof[o.dof][o.level] = {d.observed[i], d.fitted[i]};
      }
      if (byDof.size() != 1 || byDof.begin()->second.size() < 2) continue;
      PlotSeries obs("observed " + std::to_string(g), {}, {}, "points"), fit("fitted " + std::to_string(g), {}, {}, "lines");
      for (const auto& [level, v] : byDof.begin()->second) {
        const double l = in.problem->levels()[static_cast<std::size_t>(level)];
        obs.x.push_back(l);
        obs.y.push_back(v.first);
        fit.x.push_back(l);
        fit.y.push_back(v.second);
      }
      c.series.push_back(obs);
      c.series.push_back(fit);
    }
    if (!c.series.empty()) draw(c, "curves.png");
  }
  return written;
}

std::string fitSummaryText(const FitReportInputs& in) {
  const FitResult& r = *in.result;
  std::ostringstream s;
  s << toString(r.algorithm) << ": " << (r.success ? "converged" : "not converged") << " (" << r.termination << ")"
    << (r.message.empty() || r.message == "converged" ? "" : ": " + r.message) << "\n";
  s << "  misfit " << (r.q.size() > 0 ? format(r.misfit) : std::string("none (no evaluation succeeded)")) << " after "
    << r.counters.evaluations << " evaluations (" << r.counters.fullSolves
    << " full solves, " << r.counters.newtonIterations << " Newton iterations, " << r.counters.sensitivitySolves
    << " sensitivity solves)\n";
  if (r.inexactDerivativeEvaluations > 0)
    s << "  note: " << r.inexactDerivativeEvaluations << " evaluation(s) differentiated through time steps accepted at "
      << "the iteration cap: their gradients are approximate\n";
  for (std::size_t i = 0; i < r.variables.size() && r.q.size() > 0; ++i) {
    s << "  " << r.variables[i].label << " = " << format(r.q[static_cast<Eigen::Index>(i)]);
    if (r.uncertainty.available) s << " ± " << format(r.uncertainty.standardDeviation[static_cast<Eigen::Index>(i)]);
    s << "  (initial " << format(r.variables[i].initial) << ")\n";
  }
  if (!r.uncertainty.available) s << "  uncertainty: " << r.uncertainty.message << "\n";
  return s.str();
}

}  // namespace jetshell
