#include "tools/output/interrupt.h"

#include <csignal>

namespace jetshell {
namespace {

volatile std::sig_atomic_t requested = 0;

extern "C" void onInterrupt(int) {
  requested = 1;
  // A second Ctrl-C should not wait for the frame to finish.
  std::signal(SIGINT, SIG_DFL);
}

}  // namespace

void installInterruptHandler() {
  requested = 0;
  std::signal(SIGINT, onInterrupt);
}

bool interruptRequested() { return requested != 0; }

void requestInterrupt() { requested = 1; }

void removeInterruptHandler() {
  std::signal(SIGINT, SIG_DFL);
  requested = 0;
}

}  // namespace jetshell
