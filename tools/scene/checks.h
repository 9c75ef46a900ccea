// One-line range checks shared by the C++ API validation and the JSON reader, so both word errors alike:
// "<field> = <value>: must be ...". `field` is "where.name" from the API or a JSON pointer from a scene file.
#pragma once

#include "core/mesh.h"

#include <Eigen/Core>

#include <cmath>
#include <cstdint>
#include <sstream>
#include <string>

namespace jetshell::check {

[[noreturn]] inline void fail(const std::string& field, double value, const std::string& rule) {
  std::ostringstream s;
  s << field << " = " << value << ": " << rule;
  throw InputError(s.str());
}

inline void finite(double v, const std::string& field) {
  if (!std::isfinite(v)) fail(field, v, "must be finite");
}
inline void positive(double v, const std::string& field) {
  if (!(std::isfinite(v) && v > 0)) fail(field, v, "must be finite and > 0");
}
inline void nonNegative(double v, const std::string& field) {
  if (!(std::isfinite(v) && v >= 0)) fail(field, v, "must be finite and >= 0");
}
inline void atLeast(int v, int minimum, const std::string& field) {
  if (v < minimum) {
    fail(field, v, "must be >= " + std::to_string(minimum));
  }
}
inline void atMostReal(double v, double maximum, const std::string& field) {
  if (!(v <= maximum)) {
    std::ostringstream s;
    s << field << " = " << v << ": too large (at most " << maximum << ")";
    throw InputError(s.str());
  }
}
/// |v| at most `maximum` (a magnitude bound: "<field> = [..]: too large (norm at most M)").
inline void normAtMost(const Eigen::Vector3d& v, double maximum, const std::string& field) {
  if (!(v.norm() <= maximum)) {
    std::ostringstream s;
    s << field << " = [" << v[0] << ", " << v[1] << ", " << v[2] << "]: too large (norm at most " << maximum << ")";
    throw InputError(s.str());
  }
}
inline void atMost(std::int64_t v, std::int64_t maximum, const std::string& field) {
  if (v > maximum) {
    std::ostringstream s;
    s << field << " = " << v << ": too large (at most " << maximum << ")";
    throw InputError(s.str());
  }
}
/// duration / timeStep steps must be at most maxSteps ("<field> = 1e-300: 1e+300 steps over the duration 1 s, too
/// many (at most 10000000)").
inline void stepCount(double duration, double timeStep, std::int64_t maxSteps, const std::string& field) {
  const double steps = std::ceil(duration / timeStep);
  if (!(steps <= static_cast<double>(maxSteps))) {
    std::ostringstream s;
    s << field << " = " << timeStep << ": " << steps << " steps over the duration " << duration
      << " s, too many (at most " << maxSteps << ")";
    throw InputError(s.str());
  }
}
inline void finite(const Eigen::Vector3d& v, const std::string& field) {
  for (int c = 0; c < 3; ++c)
    if (!std::isfinite(v[c])) fail(field + "[" + std::to_string(c) + "]", v[c], "must be finite");
}
inline void nonZero(const Eigen::Vector3d& v, const std::string& field) {
  finite(v, field);
  if (v.cwiseAbs().maxCoeff() == 0.0) throw InputError(field + " = [0, 0, 0]: must be a non-zero vector");
}
/// A direction given as a vector (finite, non-zero), with unit length. Scaled by its largest component first, so
/// that neither huge components (1e308: the norm overflows) nor tiny ones (1e-200: it underflows) lose it.
inline Eigen::Vector3d unitDirection(const Eigen::Vector3d& v, const std::string& field) {
  nonZero(v, field);
  return (v / v.cwiseAbs().maxCoeff()).normalized();
}

}  // namespace jetshell::check
