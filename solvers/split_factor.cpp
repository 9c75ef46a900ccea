#include "solvers/split_factor.h"

#include "core/parallel_errors.h"

#include <omp.h>

#include <algorithm>
#include <sstream>

namespace jetshell {

SplitFactor::SplitFactor(FillOrdering ordering, int blasThreads) : ordering_(ordering), blasThreads_(blasThreads) {}

void SplitFactor::setPartition(const std::vector<std::int8_t>& vertexPart) {
  vertexPart_ = vertexPart;
  parts_.clear();
  analyzed_ = factorized_ = false;
}

namespace {

/// Sets OpenMP's max-active-levels for the enclosing scope, only from outside any region. (GCC 12's libgomp keeps
/// it per thread, as OpenMP 5.0 does per data environment: a value set on another std::thread does not reach here.)
class ScopedActiveLevels {
 public:
  explicit ScopedActiveLevels(int levels) : saved_(omp_get_max_active_levels()) { omp_set_max_active_levels(levels); }
  ~ScopedActiveLevels() { omp_set_max_active_levels(saved_); }
  ScopedActiveLevels(const ScopedActiveLevels&) = delete;
  ScopedActiveLevels& operator=(const ScopedActiveLevels&) = delete;

 private:
  int saved_;
};

}  // namespace

template <typename F>
void SplitFactor::forEachPart(F&& f) {
  const int n = parts();
  if (n == 1 || omp_in_parallel()) {  // one part sets its own threads; nested in a region, CHOLMOD's stay idle
    for (Part& p : parts_) f(p);
    return;
  }
  if (omp_get_max_threads() < 2) {
    // One after the other. CHOLMOD opens its own regions with a fixed num_threads(4) whatever the thread count:
    // none may become active (on one thread they tripled the halves' factorization time).
    const ScopedActiveLevels none(0);
    for (Part& p : parts_) f(p);
    return;
  }
  // CHOLMOD's and the BLAS's own parallel regions, nested in this one, run on their caller's thread.
  const ScopedActiveLevels one(1);
  ParallelErrors errors;
#pragma omp parallel for num_threads(std::min(n, omp_get_max_threads())) schedule(static, 1)
  for (int p = 0; p < n; ++p) errors.run([&] { f(parts_[static_cast<std::size_t>(p)]); });
  errors.rethrow();
}

SplitFactor::Status SplitFactor::collect(const char* what) {
  Status worst = Status::Ok;
  message_.clear();
  for (std::size_t p = 0; p < parts_.size(); ++p) {
    const Status s = parts_[p].status;
    if (s == Status::Ok) continue;
    if (worst != Status::Failed) worst = s;
    std::ostringstream m;
    if (parts_.size() > 1) m << what << ", part " << p + 1 << " of " << parts_.size() << ": ";
    m << parts_[p].factor->message();
    if (message_.empty() || s == Status::Failed) message_ = m.str();
  }
  return worst;
}

SplitFactor::Status SplitFactor::analyze(const Eigen::SparseMatrix<double>& upper) {
  analyzed_ = factorized_ = false;
  const Eigen::Index n = upper.rows();
  int count = 1;
  for (std::int8_t p : vertexPart_) count = std::max(count, p + 1);
  if (static_cast<Eigen::Index>(3 * vertexPart_.size()) != n) count = 1;  // no partition for this matrix
  parts_.clear();
  parts_.resize(static_cast<std::size_t>(count));
  // One part: the matrix itself, factored with the BLAS threads asked for. Several: each alone, on one thread.
  for (Part& p : parts_) p.factor = std::make_unique<CholmodFactor>(ordering_, count == 1 ? blasThreads_ : 0);
  if (count > 1) {
    auto partOf = [&](Eigen::Index dof) { return static_cast<int>(vertexPart_[static_cast<std::size_t>(dof / 3)]); };
    std::vector<int> local(static_cast<std::size_t>(n));
    for (Eigen::Index d = 0; d < n; ++d) {
      Part& p = parts_[static_cast<std::size_t>(partOf(d))];
      local[static_cast<std::size_t>(d)] = static_cast<int>(p.dofs.size());
      p.dofs.push_back(static_cast<int>(d));
    }
    std::vector<std::vector<int>> outer(parts_.size()), inner(parts_.size());
    for (std::size_t k = 0; k < parts_.size(); ++k) {
      outer[k].reserve(parts_[k].dofs.size() + 1);
      outer[k].push_back(0);
    }
    const int* colStart = upper.outerIndexPtr();
    const int* row = upper.innerIndexPtr();
    for (Eigen::Index j = 0; j < n; ++j) {
      const auto k = static_cast<std::size_t>(partOf(j));
      for (int q = colStart[j]; q < colStart[j + 1]; ++q) {
        if (partOf(row[q]) != static_cast<int>(k)) {
          std::ostringstream m;
          m << "entry (" << row[q] << ", " << j << ") couples parts " << partOf(row[q]) + 1 << " and " << k + 1
            << ": the matrix is not block diagonal over the partition";
          message_ = m.str();
          parts_.clear();
          return Status::Failed;
        }
        inner[k].push_back(local[static_cast<std::size_t>(row[q])]);
        parts_[k].source.push_back(q);
      }
      outer[k].push_back(static_cast<int>(inner[k].size()));
    }
    for (std::size_t k = 0; k < parts_.size(); ++k) {
      Part& p = parts_[k];
      const auto m = static_cast<Eigen::Index>(p.dofs.size());
      p.matrix = Eigen::SparseMatrix<double>(m, m);
      p.matrix.resizeNonZeros(static_cast<Eigen::Index>(inner[k].size()));
      std::copy(outer[k].begin(), outer[k].end(), p.matrix.outerIndexPtr());
      std::copy(inner[k].begin(), inner[k].end(), p.matrix.innerIndexPtr());
      std::fill(p.matrix.valuePtr(), p.matrix.valuePtr() + inner[k].size(), 0.0);
      p.b.resize(m);
    }
  }
  forEachPart([&](Part& p) { p.status = p.factor->analyze(count == 1 ? upper : p.matrix); });
  const Status s = collect("analysis");
  if (s != Status::Ok) return s;
  statistics_ = FactorStatistics{};
  for (const Part& p : parts_) {
    const FactorStatistics& f = p.factor->statistics();
    statistics_.nnzL += f.nnzL;
    statistics_.flops += f.flops;
    statistics_.nnzA += f.nnzA;
  }
  statistics_.ordering = parts_.front().factor->statistics().ordering;
  statistics_.factors = parts();
  analyzed_ = true;
  return Status::Ok;
}

SplitFactor::Status SplitFactor::factorize(const Eigen::SparseMatrix<double>& upper, double shift) {
  factorized_ = false;
  if (!analyzed_) {
    message_ = "factorize before analyze";
    return Status::Failed;
  }
  const bool whole = parts() == 1;
  const double* values = upper.valuePtr();
  forEachPart([&](Part& p) {
    if (!whole) {
      double* v = p.matrix.valuePtr();
      for (std::size_t q = 0; q < p.source.size(); ++q) v[q] = values[p.source[q]];
    }
    p.status = p.factor->factorize(whole ? upper : p.matrix, shift);
  });
  const Status s = collect("factorization");
  factorized_ = s == Status::Ok;
  return s;
}

SplitFactor::Status SplitFactor::solve(const Eigen::VectorXd& b, Eigen::VectorXd& x) {
  if (!factorized_) {
    message_ = "solve without a factor";
    return Status::Failed;
  }
  if (parts() == 1) {
    Part& p = parts_.front();
    p.status = p.factor->solve(b, x);
    return collect("solve");
  }
  x.resize(b.size());
  forEachPart([&](Part& p) {
    for (std::size_t i = 0; i < p.dofs.size(); ++i) p.b[static_cast<Eigen::Index>(i)] = b[p.dofs[i]];
    p.status = p.factor->solve(p.b, p.x);
    if (p.status != Status::Ok) return;
    for (std::size_t i = 0; i < p.dofs.size(); ++i) x[p.dofs[i]] = p.x[static_cast<Eigen::Index>(i)];
  });
  return collect("solve");
}

}  // namespace jetshell
