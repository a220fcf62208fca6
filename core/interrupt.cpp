#include "core/interrupt.hpp"

#include <signal.h>

#include <atomic>
#include <csignal>
#include <cstring>

namespace granflow::core {

namespace {

volatile std::sig_atomic_t received = 0;
std::atomic<bool> installed{false};

extern "C" void record_signal(int signal) { received = signal; }

}  // namespace

void install_interrupt_handlers() {
  if (installed.exchange(true)) return;
  struct sigaction action;
  std::memset(&action, 0, sizeof action);
  action.sa_handler = record_signal;
  sigemptyset(&action.sa_mask);
  // SA_RESTART: system calls in progress (writes, waitpid) go on; SA_RESETHAND: a second signal
  // takes the default action and ends the process at once.
  action.sa_flags = SA_RESTART | SA_RESETHAND;
  ::sigaction(SIGINT, &action, nullptr);
  ::sigaction(SIGTERM, &action, nullptr);
}

int interrupt_signal() { return received; }

std::string interrupt_name() {
  switch (received) {
    case SIGINT:
      return "SIGINT";
    case SIGTERM:
      return "SIGTERM";
    case 0:
      return "";
    default:
      return "signal " + std::to_string(received);
  }
}

int interrupt_exit_code() { return received ? 128 + received : 0; }

void set_interrupt_for_testing(int signal) { received = signal; }

}  // namespace granflow::core
