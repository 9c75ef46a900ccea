// Tabulated reference solutions (validation/reference/*.tsv) and the closed form of the end-moment cantilever.
#pragma once

#include <string>
#include <vector>

namespace jetshell::validation {

/// A load-controlled reference path: per row the load factor λ and one value per quantity.
struct ReferenceTable {
  std::string source;                      // file it came from, or "closed form"
  std::vector<std::string> quantities;     // e.g. {"W_A", "W_B"}
  std::vector<double> lambda;              // per row
  std::vector<std::vector<double>> value;  // per row, one per quantity
  /// Per row and quantity: half a unit of the value's last printed digit (a table printed with three decimals
  /// states 0.026 for anything in [0.0255, 0.0265]); 0 for closed forms, or empty (all 0).
  std::vector<std::vector<double>> halfUnit;
  int rows() const { return static_cast<int>(lambda.size()); }
};

/// Directory of the copied reference tables: $JETSHELL_SOURCE_DIR/validation/reference.
std::string referenceDirectory();

/// Reads a table of whitespace-separated numbers, one row per line, λ first, then quantities.size() values;
/// lines starting with '#' and blank lines are skipped. Each value's printed precision is kept in halfUnit. Throws InputError naming file and line for a missing
/// file, a wrong number of columns, a non-number or λ not strictly increasing.
ReferenceTable loadReferenceTable(const std::string& path, std::vector<std::string> quantities);

/// Sze et al. (2004) §3.2, the closed form (inextensible elastica under a pure end moment: an arc of radius
/// EI/M): θ = 2πλ, −u_tip = L(1 − sin θ/θ), w_tip = L(1 − cos θ)/θ, tabulated at λ = 1/levels, ..., 1.
/// Quantities {"-u_tip", "w_tip"}.
ReferenceTable endMomentClosedForm(double length, int levels);

/// The inextensible elastica of a cantilever (length L, bending stiffness EI, clamped at s = 0) under a tip
/// force of fixed vertical direction λ·Pmax, at the given load factors: EI θ'' = −P cos θ, θ(0) = 0,
/// θ'(L) = 0, solved by shooting on θ'(0) (RK4, 4000 steps, bisection to 1e-13). Quantities
/// {"-u_tip", "w_tip"}: the tip's inward and vertical displacements. A second reference for Sze's §3.1 table,
/// whose three-decimal values are coarse at small loads (λ = 0.05: the table's −u_tip = 0.026, the elastica's
/// 0.0266).
ReferenceTable endShearElastica(double length, double bendingStiffness, double maxForce,
                                const std::vector<double>& lambdas);

/// The same table with every value multiplied by factor (geometrically similar problems).
ReferenceTable scaled(ReferenceTable table, double factor);

}  // namespace jetshell::validation
