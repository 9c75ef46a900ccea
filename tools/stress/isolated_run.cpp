#include "tools/stress/isolated_run.h"

#include <poll.h>
#include <signal.h>
#include <sys/wait.h>
#include <unistd.h>

#include <cerrno>
#include <chrono>
#include <cstring>
#include <stdexcept>
#include <thread>

namespace jetshell {

IsolatedResult runIsolated(const std::function<nlohmann::json()>& work, double budgetSeconds) {
  IsolatedResult out;
  int fds[2];
  if (::pipe(fds) != 0) throw std::runtime_error(std::string("pipe: ") + std::strerror(errno));
  const auto start = std::chrono::steady_clock::now();
  const pid_t pid = ::fork();
  if (pid < 0) throw std::runtime_error(std::string("fork: ") + std::strerror(errno));
  if (pid == 0) {
    ::close(fds[0]);
    std::string text;
    int code = 0;
    try {
      text = work().dump();
    } catch (const std::exception& e) {
      text = nlohmann::json{{"exception", e.what()}}.dump();
      code = 3;
    } catch (...) {
      text = nlohmann::json{{"exception", "unknown exception"}}.dump();
      code = 3;
    }
    std::size_t done = 0;
    while (done < text.size()) {
      const ssize_t n = ::write(fds[1], text.data() + done, text.size() - done);
      if (n <= 0) break;
      done += static_cast<std::size_t>(n);
    }
    ::_exit(code);
  }
  ::close(fds[1]);
  std::string received;
  int status = 0;
  bool exited = false;
  char buffer[4096];
  for (;;) {
    const double elapsed = std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
    if (elapsed > budgetSeconds) break;
    pollfd p{fds[0], POLLIN, 0};
    const int ready = ::poll(&p, 1, 50);
    if (ready > 0) {
      const ssize_t n = ::read(fds[0], buffer, sizeof buffer);
      if (n > 0) {
        received.append(buffer, static_cast<std::size_t>(n));
        continue;
      }
      // End of the pipe: the child is done (or died); collect it.
      if (::waitpid(pid, &status, 0) == pid) exited = true;
      break;
    }
  }
  if (!exited) {
    ::kill(pid, SIGKILL);
    ::waitpid(pid, &status, 0);
    ::close(fds[0]);
    out.status = IsolatedResult::Status::TimedOut;
    out.what = "no answer within the budget of " + std::to_string(budgetSeconds) + " s (killed)";
    out.wallSeconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
    return out;
  }
  ::close(fds[0]);
  out.wallSeconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
  if (WIFSIGNALED(status)) {
    out.status = IsolatedResult::Status::Crashed;
    out.what = std::string("killed by signal ") + std::to_string(WTERMSIG(status)) + " (" + ::strsignal(WTERMSIG(status)) + ")";
    return out;
  }
  const nlohmann::json value = nlohmann::json::parse(received, nullptr, false);
  if (value.is_discarded() || (WIFEXITED(status) && WEXITSTATUS(status) != 0)) {
    out.status = IsolatedResult::Status::Crashed;
    out.what = !value.is_discarded() && value.contains("exception")
                   ? "exception: " + value["exception"].get<std::string>()
                   : "exit status " + std::to_string(WIFEXITED(status) ? WEXITSTATUS(status) : -1) + " without a result";
    return out;
  }
  out.value = value;
  return out;
}

}  // namespace jetshell
