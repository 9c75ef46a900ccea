// Runs a piece of work in a child process with a wall-clock budget, so that whatever it does (crash, hang,
// abort, run out of memory) the caller gets an answer: the work's JSON result, or what went wrong.
//
// The caller must not have started OpenMP threads before (a forked child of a process with a thread pool may
// deadlock in the runtime); `jetshell stress` forks from a parent that never solves anything.
#pragma once

#include <nlohmann/json.hpp>

#include <functional>
#include <string>

namespace jetshell {

struct IsolatedResult {
  enum class Status { Finished, Crashed, TimedOut };
  Status status = Status::Finished;
  nlohmann::json value;  // the work's result when Finished
  std::string what;      // the signal, exit status or exception when it did not finish
  double wallSeconds = 0.0;
};

/// Runs work() in a forked child and waits at most budgetSeconds (then kills it). The child's result travels
/// back as JSON through a pipe; an exception escaping work() counts as Crashed with its message.
IsolatedResult runIsolated(const std::function<nlohmann::json()>& work, double budgetSeconds);

}  // namespace jetshell
