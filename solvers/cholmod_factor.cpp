#include "solvers/cholmod_factor.h"

#include "solvers/supernodal_cholesky.h"

#include <cholmod.h>
#include <omp.h>

#include <sstream>

namespace jetshell {

struct CholmodFactor::Impl {
  cholmod_common common;
  cholmod_factor* factor = nullptr;
  SupernodalCholesky numeric;  // the numeric factorization, on CHOLMOD's analysis
};

namespace {

/// A CHOLMOD view of the Eigen matrix's arrays (no copy). CHOLMOD reads but never writes A.
cholmod_sparse view(const Eigen::SparseMatrix<double>& m) {
  cholmod_sparse A;
  A.nrow = static_cast<std::size_t>(m.rows());
  A.ncol = static_cast<std::size_t>(m.cols());
  A.nzmax = static_cast<std::size_t>(m.nonZeros());
  A.p = const_cast<int*>(m.outerIndexPtr());
  A.i = const_cast<int*>(m.innerIndexPtr());
  A.nz = nullptr;
  A.x = const_cast<double*>(m.valuePtr());
  A.z = nullptr;
  A.stype = 1;  // upper triangle stored
  A.itype = CHOLMOD_INT;
  A.xtype = CHOLMOD_REAL;
  A.dtype = CHOLMOD_DOUBLE;
  A.sorted = 1;
  A.packed = 1;
  return A;
}

std::string statusMessage(const char* what, const cholmod_common& c) {
  std::ostringstream s;
  s << what << " failed (CHOLMOD status " << c.status << ")";
  return s.str();
}

}  // namespace

namespace {

/// Runs the enclosing scope with n OpenMP threads (the BLAS's, for OpenBLAS's OpenMP build); n <= 0 leaves the
/// caller's settings as they are (SplitFactor's parts, each run on one thread of its own parallel region).
/// (It used to make every region inactive for n = 1 as well, against CHOLMOD's own regions in its numeric
/// factorization; solvers/supernodal_cholesky.h replaced that factorization and opens none.)
class ScopedThreads {
 public:
  explicit ScopedThreads(int n) : active_(n > 0 && n != omp_get_max_threads()), saved_(omp_get_max_threads()) {
    if (active_) omp_set_num_threads(n);
  }
  ~ScopedThreads() {
    if (active_) omp_set_num_threads(saved_);
  }
  ScopedThreads(const ScopedThreads&) = delete;
  ScopedThreads& operator=(const ScopedThreads&) = delete;

 private:
  bool active_;
  int saved_;
};

}  // namespace

CholmodFactor::CholmodFactor(FillOrdering ordering, int blasThreads)
    : impl_(std::make_unique<Impl>()), blasThreads_(blasThreads) {
  cholmod_start(&impl_->common);
  cholmod_common& c = impl_->common;
  switch (ordering) {
    case FillOrdering::Auto: break;  // CHOLMOD's default (nmethods = 0)
    case FillOrdering::AMD:
      c.nmethods = 1;
      c.method[0].ordering = CHOLMOD_AMD;
      break;
    case FillOrdering::METIS:
      c.nmethods = 1;
      c.method[0].ordering = CHOLMOD_METIS;
      break;
    case FillOrdering::NESDIS:
      c.nmethods = 1;
      c.method[0].ordering = CHOLMOD_NESDIS;
      break;
  }
  c.postorder = 1;
  impl_->common.supernodal = CHOLMOD_SUPERNODAL;
  impl_->common.print = 0;
}

CholmodFactor::~CholmodFactor() {
  cholmod_common* c = &impl_->common;
  if (impl_->factor != nullptr) cholmod_free_factor(&impl_->factor, c);
  cholmod_finish(c);
}

bool CholmodFactor::analyzed() const { return impl_->factor != nullptr; }

CholmodFactor::Status CholmodFactor::analyze(const Eigen::SparseMatrix<double>& upper) {
  cholmod_common* c = &impl_->common;
  if (impl_->factor != nullptr) cholmod_free_factor(&impl_->factor, c);
  factorized_ = false;
  cholmod_sparse A = view(upper);
  const ScopedThreads threads(blasThreads_);
  impl_->factor = cholmod_analyze(&A, c);
  if (impl_->factor == nullptr) {
    message_ = statusMessage("cholmod_analyze", *c);
    return Status::Failed;
  }
  statistics_.nnzL = c->lnz;
  statistics_.flops = c->fl;
  statistics_.nnzA = c->anz;
  switch (impl_->factor->ordering) {
    case CHOLMOD_AMD: statistics_.ordering = "amd"; break;
    case CHOLMOD_METIS: statistics_.ordering = "metis"; break;
    case CHOLMOD_NESDIS: statistics_.ordering = "nesdis"; break;
    case CHOLMOD_NATURAL: statistics_.ordering = "natural"; break;
    default: statistics_.ordering = "other"; break;
  }
  if (!impl_->numeric.prepare(*impl_->factor, upper, message_)) {
    cholmod_free_factor(&impl_->factor, c);
    return Status::Failed;
  }
  return Status::Ok;
}

cholmod_factor* CholmodFactor::numericFactor(const Eigen::SparseMatrix<double>& upper) {
  cholmod_common* c = &impl_->common;
  factorized_ = false;
  pivots_.resize(0);
  if (impl_->factor == nullptr) {
    message_ = "factorize before analyze";
    return nullptr;
  }
  if (static_cast<std::size_t>(upper.nonZeros()) != impl_->numeric.entries()) {
    message_ = "factorize: the matrix does not have the analysed pattern";
    return nullptr;
  }
  cholmod_factor* L = impl_->factor;
  if (L->xtype == CHOLMOD_PATTERN && !cholmod_change_factor(CHOLMOD_REAL, 1, 1, 1, 1, L, c)) {
    message_ = statusMessage("cholmod_change_factor", *c);
    return nullptr;
  }
  return L;
}

CholmodFactor::Status CholmodFactor::factorize(const Eigen::SparseMatrix<double>& upper, double shift) {
  ldlt_ = false;
  cholmod_factor* L = numericFactor(upper);
  if (L == nullptr) return Status::Failed;
  const ScopedThreads threads(blasThreads_);
  L->minor = impl_->numeric.factorize(*L, upper, shift);
  if (L->minor < L->n) {
    std::ostringstream s;
    s << "not positive definite at column " << L->minor;
    message_ = s.str();
    return Status::NotPositiveDefinite;
  }
  factorized_ = true;
  return Status::Ok;
}

CholmodFactor::Status CholmodFactor::solve(const Eigen::VectorXd& b, Eigen::VectorXd& x) {
  if (!factorized_) {
    message_ = "solve without a factor";
    return Status::Failed;
  }
  x.resize(b.size());
  if (ldlt_)
    impl_->numeric.solveLdlt(*impl_->factor, b.data(), x.data());
  else
    impl_->numeric.solve(*impl_->factor, b.data(), x.data());
  return Status::Ok;
}

CholmodFactor::Status CholmodFactor::factorizeLdlt(const Eigen::SparseMatrix<double>& upper) {
  ldlt_ = true;
  cholmod_factor* L = numericFactor(upper);
  if (L == nullptr) return Status::Failed;
  const ScopedThreads threads(blasThreads_);
  L->minor = impl_->numeric.factorizeLdlt(*L, upper);
  if (L->minor < L->n) {
    std::ostringstream s;
    s << "LDLT: zero or non-finite pivot at column " << L->minor;
    message_ = s.str();
    return Status::Failed;
  }
  pivots_.resize(static_cast<Eigen::Index>(L->n));
  impl_->numeric.pivots(*L, pivots_.data());
  factorized_ = true;
  return Status::Ok;
}

CholmodFactor::Status CholmodFactor::solveUnitTransposed(const Eigen::VectorXd& u, Eigen::VectorXd& x) {
  if (!factorized_ || !ldlt_ || u.size() != pivots_.size()) {
    message_ = "solveUnitTransposed without an LDLT factor of this size";
    return Status::Failed;
  }
  x.resize(u.size());
  impl_->numeric.solveUnitTransposed(*impl_->factor, u.data(), x.data());
  return Status::Ok;
}

}  // namespace jetshell
