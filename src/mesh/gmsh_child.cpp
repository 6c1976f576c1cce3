#include "mesh/gmsh_child.hpp"

#include "core/error.hpp"

#include <dlfcn.h>
#include <poll.h>
#include <sys/prctl.h>
#include <sys/resource.h>
#include <sys/wait.h>
#include <unistd.h>

#include <algorithm>
#include <cerrno>
#include <chrono>
#include <cmath>
#include <csignal>
#include <cstdint>
#include <cstdio>
#include <cstdlib>
#include <cstring>
#include <filesystem>
#include <fstream>

namespace vpc {

namespace {

namespace fs = std::filesystem;
using namespace gmsh_model;

/// Waits for the child `pid` to end; its wait status, and the most memory it held.
int reap(pid_t pid, std::size_t* max_rss_bytes = nullptr) {
  int status = 0;
  rusage usage{};
  while (::wait4(pid, &status, 0, &usage) < 0 && errno == EINTR) {
  }
  if (max_rss_bytes) *max_rss_bytes = static_cast<std::size_t>(usage.ru_maxrss) * 1024;  // KiB on Linux
  return status;
}

/// The child's answer on `fd`, read until it closes. The child is killed (and
/// reaped) when the time limit passes.
std::string read_answer(int fd, pid_t pid, const std::string& file, const GmshOptions& options) {
  const auto start = std::chrono::steady_clock::now();
  auto stop_child = [&] {
    ::kill(pid, SIGKILL);
    reap(pid);
    ::close(fd);
  };
  std::string out;
  char buffer[1 << 16];
  for (;;) {
    const double seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
    if (options.time_limit > 0 && seconds > options.time_limit) {
      stop_child();
      fail("{}: Gmsh did not finish within {:g} s and was stopped (a loop that does not end, or elements far too "
           "small?); {} sets the limit",
           file, options.time_limit, options.time_limit_how);
    }
    pollfd p{fd, POLLIN, 0};
    const int ready = ::poll(&p, 1, 100);  // or a signal (EINTR): then the clock is looked at again
    if (ready <= 0) continue;
    const ssize_t n = ::read(fd, buffer, sizeof buffer);
    if (n < 0 && errno == EINTR) continue;
    if (n <= 0) return out;
    out.append(buffer, static_cast<std::size_t>(n));
  }
}

/// The child's exit status when Gmsh calls exit().
constexpr int kGmshCalledExit = 86;

#if defined(__SANITIZE_ADDRESS__)
#define VPC_ADDRESS_SANITIZER 1
#elif defined(__has_feature)
#if __has_feature(address_sanitizer)
#define VPC_ADDRESS_SANITIZER 1
#endif
#endif

/// The memory Gmsh may take (beyond what the process already maps) to read a
/// mesh file: some malformed .msh files make Gmsh 4.8 ask for gigabytes (a
/// 58-byte $Nodes header: 15 GB and a minute; fuzz/), while reading a real one
/// needs a small multiple of its size. A geometry is meshed within the limit of
/// the options (which may need much more). 0: no limit (also under
/// AddressSanitizer, which reserves terabytes).
std::size_t memory_budget(const std::string& file, const GmshOptions& options) {
#ifdef VPC_ADDRESS_SANITIZER
  (void)file;
  (void)options;
  return 0;
#else
  if (fs::path(file).extension() != ".msh") return options.memory_limit;
  std::error_code ec;
  const std::uintmax_t size = fs::file_size(file, ec);
  if (ec) return 0;
  return std::max<std::uintmax_t>(std::uintmax_t{4} << 30, 100 * size);
#endif
}

/// In the child: caps its address space at what it maps now plus `budget`.
void limit_memory(std::size_t budget) {
  if (budget == 0) return;
  std::ifstream status("/proc/self/status");
  std::size_t mapped_kb = 0;
  for (std::string line; std::getline(status, line);)
    if (line.rfind("VmSize:", 0) == 0) mapped_kb = std::strtoull(line.c_str() + 7, nullptr, 10);
  if (mapped_kb == 0) return;
  rlimit r{};
  if (::getrlimit(RLIMIT_AS, &r) != 0) return;
  const rlim_t cap = static_cast<rlim_t>(mapped_kb) * 1024 + budget;
  if (r.rlim_max != RLIM_INFINITY && cap > r.rlim_max) return;
  r.rlim_cur = cap;
  ::setrlimit(RLIMIT_AS, &r);
}

}  // namespace

gmsh_model::GmshModel read_in_child(const std::string& file, const GmshOptions& options) {
  const std::size_t budget = memory_budget(file, options);
  const bool script = fs::path(file).extension() != ".msh";
  int fds[2];
  require(::pipe(fds) == 0, "{}: cannot create a pipe for Gmsh: {}", file, std::strerror(errno));
  std::fflush(nullptr);  // nothing buffered is written twice
  const pid_t parent = ::getpid();
  const pid_t pid = ::fork();
  if (pid < 0) {
    const int err = errno;
    ::close(fds[0]);
    ::close(fds[1]);
    fail("{}: cannot start a process for Gmsh: {}", file, std::strerror(err));
  }
  if (pid == 0) {  // the child: never returns
    ::close(fds[0]);
    // The child ends with this process (killed, or timed out by a fuzzer).
    ::prctl(PR_SET_PDEATHSIG, SIGKILL);
    if (::getppid() != parent) ::_exit(1);
    // A crash ends the child by its signal, which the parent reports (not the
    // handlers of sanitizers or fuzzers that the parent may have installed).
    for (int sig : {SIGSEGV, SIGBUS, SIGFPE, SIGILL, SIGABRT}) std::signal(sig, SIG_DFL);
    // Gmsh calls exit() for `Exit;` in a .geo file: the exit handlers and static
    // destructors are the parent's, so the child leaves at once, saying so.
    std::atexit([] { ::_exit(kGmshCalledExit); });
    limit_memory(budget);
    // Ctrl-C reaches the whole process group: the parent stops the child (read_answer).
    std::signal(SIGINT, SIG_IGN);
    std::signal(SIGTERM, SIG_IGN);
    // The CPU time, a second bound behind the parent's clock (SIGXCPU ends the child).
    if (options.time_limit > 0) {
      rlimit r{};
      if (::getrlimit(RLIMIT_CPU, &r) == 0) {
        r.rlim_cur = static_cast<rlim_t>(std::ceil(options.time_limit)) + 5;
        if (r.rlim_max != RLIM_INFINITY && r.rlim_cur > r.rlim_max) r.rlim_cur = r.rlim_max;
        ::setrlimit(RLIMIT_CPU, &r);
      }
    }
    // Gmsh's library is loaded here only (gmsh_module.cpp): the parent never pays for it.
    const char* module = std::getenv("VPCONTACT_GMSH_MODULE");
    if (module == nullptr || *module == '\0') module = VPC_GMSH_MODULE;
    void* handle = ::dlopen(module, RTLD_NOW | RTLD_LOCAL);
    void* entry = handle ? ::dlsym(handle, kWriteModelSymbol) : nullptr;
    if (entry == nullptr) {
      Writer w;
      w.value('E');
      w.string(fmt::format("{}: cannot load vpcontact's Gmsh module '{}': {} (set VPCONTACT_GMSH_MODULE to its path)",
                           file, module, ::dlerror()));
      w.send(fds[1]);
      ::_exit(0);
    }
    reinterpret_cast<WriteModelFunction*>(entry)(file.c_str(), options.dim, options.size_factor, budget, fds[1]);
    ::_exit(0);  // no exit handlers: they belong to the parent
  }
  ::close(fds[1]);
  const std::string bytes = read_answer(fds[0], pid, file, options);
  ::close(fds[0]);
  std::size_t max_rss = 0;
  const int status = reap(pid, &max_rss);
  const std::string how = WIFSIGNALED(status) ? fmt::format("crashed ({})", strsignal(WTERMSIG(status)))
                                              : fmt::format("ended with exit status {}", WEXITSTATUS(status));
  const std::string limit = budget > 0 ? fmt::format("{} MiB", budget >> 20) : "no limit";
  // A crash on a mesh file is most likely a malformed file (fuzz/); a script
  // that Gmsh accepts can crash Gmsh itself (issue 26: Gmsh 4.8 on some recombined meshes).
  auto crash = [&]() -> Error {
    if (WIFSIGNALED(status) && WTERMSIG(status) == SIGXCPU)
      return Error(fmt::format("{}: Gmsh used more than {:g} s of CPU time and was stopped; {} sets the limit", file,
                               options.time_limit, options.time_limit_how));
    if (!script)
      return Error(fmt::format("{}: Gmsh {} while reading the file; the file is probably malformed", file, how));
    return Error(fmt::format(
        "{}: Gmsh {} while meshing the file: a failure of Gmsh itself, which a valid script can meet too (e.g. "
        "recombined or quadrilateral meshes, which vpcontact does not take anyway){}; try other mesh options or "
        "element sizes",
        file, how,
        budget > 0 && max_rss > budget / 2  // C code that finds no memory may crash rather than throw
            ? fmt::format(", or memory beyond the limit of {} ({})", limit, options.memory_limit_how)
            : ""));
  };
  if (bytes.empty()) {
    if (WIFEXITED(status) && WEXITSTATUS(status) == kGmshCalledExit)
      fail("{}: Gmsh ended the program while reading the file (does the .geo file call Exit?)", file);
    throw crash();
  }
  try {
    Reader r(bytes);
    const char kind = r.value<char>();
    if (kind == 'E') throw Error(r.string());
    if (kind == 'O') {
      if (!script) fail("{}: Gmsh ran out of memory while reading the file ({}); the file is probably malformed", file,
                        budget > 0 ? "limit " + limit : limit);
      fail("{}: Gmsh ran out of memory while meshing the file ({}); make the elements larger, or raise the limit "
           "with {}", file, budget > 0 ? "limit " + limit : limit, options.memory_limit_how);
    }
    return r.model();
  } catch (const Reader::Truncated&) {
    throw crash();
  }
}

}  // namespace vpc
