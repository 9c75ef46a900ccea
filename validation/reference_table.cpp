#include "validation/reference_table.h"

#include "core/mesh.h"

#include <algorithm>
#include <cmath>
#include <cstdlib>
#include <fstream>
#include <sstream>
#include <string>

namespace jetshell::validation {
namespace {

/// Half a unit of the last digit of a number as printed ("0.026" -> 0.0005, "12" -> 0.5, "1.5e-3" -> 0.00005).
double halfUnitOfLastDigit(const std::string& field) {
  const std::size_t e = field.find_first_of("eE");
  const std::string mantissa = field.substr(0, e);
  // The field already parsed as a finite number; the exponent is clamped so "0e99999999999" cannot overflow.
  const long parsed = e == std::string::npos ? 0 : std::strtol(field.c_str() + e + 1, nullptr, 10);
  const int exponent = static_cast<int>(std::clamp(parsed, -300L, 300L));
  const std::size_t dot = mantissa.find('.');
  const int decimals = dot == std::string::npos ? 0 : static_cast<int>(mantissa.size() - dot - 1);
  return 0.5 * std::pow(10.0, exponent - decimals);
}

}  // namespace

std::string referenceDirectory() { return std::string(JETSHELL_SOURCE_DIR) + "/validation/reference"; }

ReferenceTable loadReferenceTable(const std::string& path, std::vector<std::string> quantities) {
  std::ifstream in(path);
  if (!in) throw InputError(path + ": cannot open reference table");
  ReferenceTable t;
  t.source = path;
  t.quantities = std::move(quantities);
  const std::size_t columns = t.quantities.size() + 1;
  std::string line;
  for (int lineNumber = 1; std::getline(in, line); ++lineNumber) {
    const std::size_t first = line.find_first_not_of(" \t\r");
    if (first == std::string::npos || line[first] == '#') continue;
    std::istringstream fields(line);
    std::vector<double> row, half;
    std::string field;
    while (fields >> field) {
      std::size_t used = 0;
      double v = 0.0;
      try {
        v = std::stod(field, &used);
      } catch (const std::exception&) {
        used = 0;
      }
      if (used != field.size() || !std::isfinite(v))
        throw InputError(path + ":" + std::to_string(lineNumber) + ": '" + field + "' is not a number");
      row.push_back(v);
      half.push_back(halfUnitOfLastDigit(field));
    }
    if (row.size() != columns)
      throw InputError(path + ":" + std::to_string(lineNumber) + ": expected " + std::to_string(columns) +
                       " columns (lambda and " + std::to_string(columns - 1) + " quantities), found " +
                       std::to_string(row.size()));
    if (!t.lambda.empty() && !(row[0] > t.lambda.back()))
      throw InputError(path + ":" + std::to_string(lineNumber) + ": lambda must increase strictly");
    t.lambda.push_back(row[0]);
    t.value.emplace_back(row.begin() + 1, row.end());
    t.halfUnit.emplace_back(half.begin() + 1, half.end());
  }
  if (t.lambda.empty()) throw InputError(path + ": no rows");
  return t;
}

ReferenceTable endMomentClosedForm(double length, int levels) {
  ReferenceTable t;
  t.source = "closed form (Sze et al. 2004 §3.2)";
  t.quantities = {"-u_tip", "w_tip"};
  for (int k = 1; k <= levels; ++k) {
    const double lambda = static_cast<double>(k) / levels;
    const double theta = 2.0 * 3.14159265358979323846 * lambda;
    t.lambda.push_back(lambda);
    t.value.push_back({length * (1.0 - std::sin(theta) / theta), length * (1.0 - std::cos(theta)) / theta});
  }
  return t;
}

namespace {

/// Integrates the elastica from s = 0 with θ'(0) = kappa0; returns θ'(L) and the tip position (x, z).
double shootElastica(double length, double forceOverStiffness, double kappa0, double& x, double& z) {
  constexpr int kSteps = 4000;
  const double h = length / kSteps;
  // State: θ, θ', x, z.
  auto rate = [&](const double* y, double* dy) {
    dy[0] = y[1];
    dy[1] = -forceOverStiffness * std::cos(y[0]);
    dy[2] = std::cos(y[0]);
    dy[3] = std::sin(y[0]);
  };
  double y[4] = {0.0, kappa0, 0.0, 0.0};
  for (int i = 0; i < kSteps; ++i) {
    double k1[4], k2[4], k3[4], k4[4], t[4];
    rate(y, k1);
    for (int c = 0; c < 4; ++c) t[c] = y[c] + 0.5 * h * k1[c];
    rate(t, k2);
    for (int c = 0; c < 4; ++c) t[c] = y[c] + 0.5 * h * k2[c];
    rate(t, k3);
    for (int c = 0; c < 4; ++c) t[c] = y[c] + h * k3[c];
    rate(t, k4);
    for (int c = 0; c < 4; ++c) y[c] += h / 6.0 * (k1[c] + 2.0 * k2[c] + 2.0 * k3[c] + k4[c]);
  }
  x = y[2];
  z = y[3];
  return y[1];
}

}  // namespace

ReferenceTable endShearElastica(double length, double bendingStiffness, double maxForce,
                                const std::vector<double>& lambdas) {
  ReferenceTable t;
  t.source = "inextensible elastica (shooting)";
  t.quantities = {"-u_tip", "w_tip"};
  for (double lambda : lambdas) {
    const double k = lambda * maxForce / bendingStiffness;
    // θ'(0) = P·x_tip/EI lies in (0, P L / EI]; θ'(L) rises with θ'(0) on that bracket.
    double lo = 0.0, hi = k * length, x = length, z = 0.0;
    for (int it = 0; it < 200 && hi - lo > 1e-13 * (1.0 + hi); ++it) {
      const double mid = 0.5 * (lo + hi);
      (shootElastica(length, k, mid, x, z) < 0.0 ? lo : hi) = mid;
    }
    shootElastica(length, k, 0.5 * (lo + hi), x, z);
    t.lambda.push_back(lambda);
    t.value.push_back({length - x, z});
  }
  return t;
}

ReferenceTable scaled(ReferenceTable table, double factor) {
  for (auto& row : table.value)
    for (double& v : row) v *= factor;
  for (auto& row : table.halfUnit)
    for (double& v : row) v *= std::abs(factor);
  return table;
}

}  // namespace jetshell::validation
