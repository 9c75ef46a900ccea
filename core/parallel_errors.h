// Exceptions thrown inside OpenMP regions: an exception escaping a parallel region terminates the program, so
// element loops catch each one where it is thrown and rethrow the first after the region.
//
//   ParallelErrors errors;
//   #pragma omp parallel for
//   for (int i = 0; i < n; ++i) errors.run([&] { body(i); });
//   errors.rethrow();   // after the region: the first exception caught, if any
#pragma once

#include <exception>

namespace jetshell {

class ParallelErrors {
 public:
  /// Runs f; an exception it throws is kept (the first one only) instead of leaving the region.
  template <typename F>
  void run(F&& f) noexcept {
    try {
      f();
    } catch (...) {
#pragma omp critical(jetshell_parallel_errors)
      {
        if (!error_) error_ = std::current_exception();
      }
    }
  }
  bool failed() const { return static_cast<bool>(error_); }
  /// Rethrows the kept exception (call outside the parallel region).
  void rethrow() const {
    if (error_) std::rethrow_exception(error_);
  }

 private:
  std::exception_ptr error_;
};

}  // namespace jetshell
