#include "validation/reference_table.h"

#include "core/mesh.h"

#include <cmath>
#include <fstream>
#include <sstream>

namespace jetshell::validation {

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
    std::vector<double> row;
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
    }
    if (row.size() != columns)
      throw InputError(path + ":" + std::to_string(lineNumber) + ": expected " + std::to_string(columns) +
                       " columns (lambda and " + std::to_string(columns - 1) + " quantities), found " +
                       std::to_string(row.size()));
    if (!t.lambda.empty() && !(row[0] > t.lambda.back()))
      throw InputError(path + ":" + std::to_string(lineNumber) + ": lambda must increase strictly");
    t.lambda.push_back(row[0]);
    t.value.emplace_back(row.begin() + 1, row.end());
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

ReferenceTable scaled(ReferenceTable table, double factor) {
  for (auto& row : table.value)
    for (double& v : row) v *= factor;
  return table;
}

}  // namespace jetshell::validation
