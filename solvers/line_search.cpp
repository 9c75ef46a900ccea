#include "solvers/line_search.h"

#include "core/mesh.h"

#include <algorithm>
#include <cmath>
#include <sstream>

namespace jetshell {

LineSearchType lineSearchTypeFromString(const std::string& name) {
  if (name == "none") return LineSearchType::None;
  if (name == "armijo") return LineSearchType::BacktrackingArmijo;
  if (name == "residual") return LineSearchType::ResidualNorm;
  if (name == "wolfe") return LineSearchType::StrongWolfe;
  throw InputError("line search '" + name + "': expected none, armijo, residual or wolfe");
}

const char* toString(LineSearchType t) {
  switch (t) {
    case LineSearchType::None: return "none";
    case LineSearchType::BacktrackingArmijo: return "armijo";
    case LineSearchType::ResidualNorm: return "residual";
    case LineSearchType::StrongWolfe: return "wolfe";
  }
  return "?";
}

namespace {

class Search {
 public:
  Search(const LineSearchOptions& o, const LineSearchPoint& start, const LineSearchEvaluator& f)
      : o_(o), start_(start), f_(f) {}

  LineSearchResult run() {
    switch (o_.type) {
      case LineSearchType::None: return none();
      case LineSearchType::BacktrackingArmijo: return armijo();
      case LineSearchType::ResidualNorm: return residualNorm();
      case LineSearchType::StrongWolfe: return strongWolfe();
    }
    return fail("unknown line search");
  }

 private:
  LineSearchPoint eval(double alpha, bool wantGradient) {
    LineSearchPoint p = f_(alpha, wantGradient);
    p.alpha = alpha;
    p.finite = std::isfinite(p.energy) && (!p.hasGradient || (std::isfinite(p.slope) && std::isfinite(p.residual)));
    ++result_.evaluations;
    anyFinite_ = anyFinite_ || p.finite;
    result_.point = p;
    return p;
  }
  bool sufficientDecrease(const LineSearchPoint& p) const {
    return p.finite && p.energy <= start_.energy + o_.c1 * p.alpha * start_.slope + o_.energyNoise;
  }
  LineSearchResult accept(const LineSearchPoint& p) {
    result_.success = true;
    result_.point = p;
    return result_;
  }
  LineSearchResult fail(const std::string& why) {
    result_.success = false;
    result_.allNonFinite = !anyFinite_;
    std::ostringstream s;
    s << why << " after " << result_.evaluations << " evaluations (last alpha " << result_.point.alpha << ")";
    result_.message = s.str();
    return result_;
  }

  LineSearchResult none() {
    const LineSearchPoint p = eval(1.0, false);
    return p.finite ? accept(p) : fail("non-finite energy at the full step");
  }

  LineSearchResult armijo() {
    double alpha = 1.0;
    while (result_.evaluations < o_.maxEvaluations) {
      const LineSearchPoint p = eval(alpha, false);
      if (sufficientDecrease(p)) return accept(p);
      if (!p.finite) {
        alpha *= 0.5;
      } else {
        const double curvature = p.energy - start_.energy - start_.slope * alpha;
        const double q = curvature > 0.0 ? -start_.slope * alpha * alpha / (2.0 * curvature) : 0.5 * alpha;
        alpha = std::clamp(q, 0.1 * alpha, 0.5 * alpha);
      }
    }
    return fail("no sufficient decrease");
  }

  LineSearchResult residualNorm() {
    constexpr double kFallbackAlpha = 1.0 / 16.0;
    double alpha = 1.0;
    bool haveArmijo = false;
    LineSearchPoint armijoPoint;
    while (result_.evaluations < o_.maxEvaluations) {
      const LineSearchPoint p = eval(alpha, true);
      if (p.finite && p.residual <= (1.0 - o_.c1 * alpha) * start_.residual) return accept(p);
      if (!haveArmijo && sufficientDecrease(p)) {
        haveArmijo = true;
        armijoPoint = p;
      }
      if (haveArmijo && alpha < kFallbackAlpha) return accept(armijoPoint);
      alpha *= 0.5;
    }
    if (haveArmijo) return accept(armijoPoint);
    return fail("no residual or energy decrease");
  }

  bool curvatureCondition(const LineSearchPoint& p) const {
    return std::abs(p.slope) <= -o_.c2 * start_.slope;
  }

  LineSearchResult strongWolfe() {
    constexpr double kMaxAlpha = 4.0;
    LineSearchPoint previous = start_;
    double alpha = 1.0;
    bool first = true;
    while (result_.evaluations < o_.maxEvaluations) {
      const LineSearchPoint p = eval(alpha, true);
      if (!p.finite) {
        alpha = 0.5 * (previous.alpha + alpha);  // shrink towards the last good point
        continue;
      }
      if (!sufficientDecrease(p) || (!first && p.energy >= previous.energy)) return zoom(previous, p);
      if (curvatureCondition(p)) return accept(p);
      if (p.slope >= 0.0) return zoom(p, previous);
      if (alpha >= kMaxAlpha) return accept(p);  // sufficient decrease at the largest step allowed
      previous = p;
      alpha = std::min(2.0 * alpha, kMaxAlpha);
      first = false;
    }
    return fail("strong Wolfe conditions not met");
  }

  /// Minimizer of the cubic interpolating φ and φ' at a and b, or NaN when it does not exist.
  static double cubicMinimizer(const LineSearchPoint& a, const LineSearchPoint& b) {
    const double d1 = a.slope + b.slope - 3.0 * (a.energy - b.energy) / (a.alpha - b.alpha);
    const double disc = d1 * d1 - a.slope * b.slope;
    if (!(disc >= 0.0)) return std::nan("");
    const double d2 = std::copysign(std::sqrt(disc), b.alpha - a.alpha);
    const double denom = b.slope - a.slope + 2.0 * d2;
    if (denom == 0.0) return std::nan("");
    return b.alpha - (b.alpha - a.alpha) * (b.slope + d2 - d1) / denom;
  }

  /// Nocedal & Wright Algorithm 3.6. lo satisfies sufficient decrease and has the lower energy; hi may be
  /// non-finite (then bisection).
  LineSearchResult zoom(LineSearchPoint lo, LineSearchPoint hi) {
    while (result_.evaluations < o_.maxEvaluations) {
      const double left = std::min(lo.alpha, hi.alpha), right = std::max(lo.alpha, hi.alpha);
      const double width = right - left;
      if (width <= 1e-12 * right) break;
      double alpha = hi.finite ? cubicMinimizer(lo, hi) : std::nan("");
      if (!(alpha >= left + 0.1 * width && alpha <= right - 0.1 * width)) alpha = 0.5 * (left + right);
      const LineSearchPoint p = eval(alpha, true);
      if (!sufficientDecrease(p) || p.energy >= lo.energy) {
        hi = p;
      } else {
        if (curvatureCondition(p)) return accept(p);
        if (p.slope * (hi.alpha - lo.alpha) >= 0.0) hi = lo;
        lo = p;
      }
    }
    // The bracket collapsed or the budget ran out: a point with sufficient decrease is still progress.
    if (lo.alpha > 0.0 && sufficientDecrease(lo)) return accept(lo);
    return fail("strong Wolfe zoom did not converge");
  }

  const LineSearchOptions& o_;
  const LineSearchPoint& start_;
  const LineSearchEvaluator& f_;
  LineSearchResult result_;
  bool anyFinite_ = false;
};

}  // namespace

LineSearchResult lineSearch(const LineSearchOptions& options, const LineSearchPoint& start,
                            const LineSearchEvaluator& evaluate) {
  return Search(options, start, evaluate).run();
}

}  // namespace jetshell
