// Fill-reducing orderings for sparse Cholesky factors, and what a symbolic analysis reports.
// Inputs: an ordering name (auto | amd | metis | nesdis). Outputs: the enum, and FactorStatistics
// (nnz(L) and the flop count of one numeric factorization: deterministic, so orderings are compared on them).
#pragma once

#include <string>

namespace jetshell {

/// Auto: CHOLMOD's default (AMD, then METIS when AMD's fill is poor: fl/nnz(L) ≥ 500 and nnz(L)/nnz(A) ≥ 5).
/// AMD: approximate minimum degree. METIS: METIS nested dissection. NESDIS: CHOLMOD's nested dissection
/// (METIS bisection with constrained minimum degree on the parts).
enum class FillOrdering { Auto, AMD, METIS, NESDIS };

FillOrdering fillOrderingFromString(const std::string& name);  // auto | amd | metis | nesdis
const char* toString(FillOrdering o);

struct FactorStatistics {
  double nnzA = 0.0;      // nonzeros of the analysed triangle
  double nnzL = 0.0;      // nonzeros of L (without supernodal padding)
  double flops = 0.0;     // floating-point operations of one simplicial LLᵀ factorization
  std::string ordering;   // the ordering used (auto resolves to amd or metis)
  int factors = 1;        // separate factors (the halves of a split one-ring factor, solvers/split_factor.h)
};

}  // namespace jetshell
