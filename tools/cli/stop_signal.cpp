// The one flag a signal handler may touch: a volatile sig_atomic_t (C++17 [support.signal]); the handler does
// nothing else but, on a second signal, restore the default action and raise it again.
#include "tools/cli/stop_signal.h"

#include <csignal>

namespace penumbra::cli {
namespace {

volatile std::sig_atomic_t received = 0;  // the first signal's number, 0 before any

extern "C" void onStopSignal(int sig) {
  if (received != 0) {
    std::signal(sig, SIG_DFL);
    std::raise(sig);
    return;
  }
  received = sig;
}

struct sigaction previousTerm, previousInt;

}  // namespace

StopSignals::StopSignals() {
  received = 0;
  struct sigaction action {};
  action.sa_handler = onStopSignal;
  sigemptyset(&action.sa_mask);
  sigaction(SIGTERM, &action, &previousTerm);
  sigaction(SIGINT, &action, &previousInt);
}

StopSignals::~StopSignals() {
  sigaction(SIGTERM, &previousTerm, nullptr);
  sigaction(SIGINT, &previousInt, nullptr);
}

bool StopSignals::requested() const { return received != 0; }

const char* StopSignals::name() const {
  if (received == SIGTERM) return "SIGTERM";
  if (received == SIGINT) return "SIGINT";
  return "";
}

}  // namespace penumbra::cli
