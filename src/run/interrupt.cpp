#include "run/interrupt.hpp"

#include <fmt/format.h>

#include <csignal>
#include <unistd.h>

namespace vpc {

namespace {

volatile std::sig_atomic_t g_signal = 0;
volatile std::sig_atomic_t g_at_once = 0;  // SetUpStopsAtOnce
volatile std::sig_atomic_t g_checkpoint = 0;  // note_checkpoint

/// write(2) of a literal: async-signal-safe.
template <std::size_t N>
void say(const char (&msg)[N]) {
  [[maybe_unused]] const auto n = ::write(STDERR_FILENO, msg, N - 1);
}

extern "C" void on_signal(int s) {
  if (g_at_once != 0) {  // set-up: nothing to keep (the text of Interrupted)
    if (s == SIGINT) say("\nvpcontact: interrupted by SIGINT during set-up; nothing was computed\n");
    else say("\nvpcontact: interrupted by SIGTERM during set-up; nothing was computed\n");
    ::_exit(128 + s);
  }
  if (g_signal != 0) {  // the second one: no waiting for the step or factorization under way
    if (g_checkpoint != 0) say("\nvpcontact: second signal: stopping at once (the last checkpoint is kept)\n");
    else say("\nvpcontact: second signal: stopping at once (no checkpoint was written)\n");
    ::_exit(128 + s);
  }
  g_signal = s;
}

}  // namespace

void catch_interrupts() {
  struct sigaction sa {};
  sa.sa_handler = on_signal;
  sigemptyset(&sa.sa_mask);
  sa.sa_flags = SA_RESTART;  // file writes and waits carry on; the loop checks the flag
  sigaction(SIGINT, &sa, nullptr);
  sigaction(SIGTERM, &sa, nullptr);
}

int interrupt_signal() { return g_signal; }

const char* signal_name(int s) { return s == SIGINT ? "SIGINT" : s == SIGTERM ? "SIGTERM" : "a signal"; }

Interrupted::Interrupted(int s)
    : std::runtime_error(fmt::format("interrupted by {} during set-up; nothing was computed", signal_name(s))),
      signal(s) {}

void stop_if_interrupted() {
  if (const int s = interrupt_signal()) throw Interrupted(s);
}

SetUpStopsAtOnce::SetUpStopsAtOnce() {
  g_at_once = 1;
  if (g_signal != 0) {  // arrived before: reported as ever
    g_at_once = 0;
    stop_if_interrupted();
  }
}

SetUpStopsAtOnce::~SetUpStopsAtOnce() { g_at_once = 0; }

void note_checkpoint() { g_checkpoint = 1; }

std::string shell_quote(std::string_view s) {
  const bool safe = !s.empty() && s.find_first_not_of("ABCDEFGHIJKLMNOPQRSTUVWXYZabcdefghijklmnopqrstuvwxyz"
                                                      "0123456789_@%+=:,./-") == std::string_view::npos;
  if (safe) return std::string(s);
  std::string q = "'";
  for (char c : s) q += c == '\'' ? std::string("'\\''") : std::string(1, c);
  return q + "'";
}

std::string resume_command(const std::vector<std::string>& argv, const std::filesystem::path& dir, int mpi_size) {
  std::string cmd = mpi_size > 0 ? fmt::format("mpirun -np {} ", mpi_size) : "";
  for (std::size_t i = 0; i < argv.size(); ++i) {
    const std::string& a = argv[i];
    if (a == "--resume" || a == "-o" || a == "--output") {
      ++i;  // and its value
      continue;
    }
    if (a.starts_with("--resume=") || a.starts_with("--output=") || (a.starts_with("-o") && a.size() > 2)) continue;
    cmd += shell_quote(a) + " ";
  }
  return cmd + "--resume " + shell_quote(dir.string());
}

}  // namespace vpc
