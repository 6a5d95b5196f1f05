// Where the test process ran out of allocations or was killed: the stack on
// stderr, so that a failure nobody can reproduce leaves more than its name in
// the CI log (issue 30: a std::bad_alloc with gigabytes free in a soak, and
// glibc's heap checks aborting ("malloc_consolidate(): unaligned fastbin
// chunk") in a different test each time; neither seen outside CI). Installed
// before main by a static object; gpu_tests links it.
//   - operator new that finds no memory calls the new handler, which writes the
//     stack and throws std::bad_alloc, as operator new would have without it;
//   - SIGABRT (glibc's heap checks, std::terminate), SIGSEGV, SIGBUS and SIGFPE
//     write the stack, then the default action runs (the process still dies of
//     its signal, which scripts/test's rerun of crashed tests looks for); a
//     handler installed before (a sanitizer's) is kept.
// The stack comes from glibc's backtrace(): function names of the test binary
// (its symbols are exported) and shared objects with their offsets
// (addr2line -e LIB OFFSET names those where the same package is installed).
#include <execinfo.h>
#include <unistd.h>

#include <csignal>
#include <cstring>
#include <initializer_list>
#include <new>

namespace {

void writeStack(const char* what) {
  void* frames[64];
  const int count = backtrace(frames, 64);
  if (write(STDERR_FILENO, what, std::strlen(what)) < 0) return;
  backtrace_symbols_fd(frames, count, STDERR_FILENO);  // writes without allocating
}

void onFailedAllocation() {
  writeStack("crash_report: operator new found no memory (std::bad_alloc follows) at:\n");
  throw std::bad_alloc();
}

void onFatalSignal(int signal) {
  writeStack(signal == SIGABRT   ? "crash_report: SIGABRT (an abort: glibc's heap checks, std::terminate) at:\n"
             : signal == SIGSEGV ? "crash_report: SIGSEGV at:\n"
             : signal == SIGBUS  ? "crash_report: SIGBUS at:\n"
                                 : "crash_report: SIGFPE at:\n");
  std::raise(signal);  // then die of it as before (SA_RESETHAND has already restored the default action)
}

struct CrashReport {
  CrashReport() {
    void* warm[1];
    backtrace(warm, 1);  // loads libgcc's unwinder now: the first call allocates, a handler's must not
    std::set_new_handler(onFailedAllocation);
    struct sigaction action {};
    action.sa_handler = onFatalSignal;
    action.sa_flags = SA_RESETHAND | SA_NODEFER;
    sigemptyset(&action.sa_mask);
    // A handler another tool installed first (AddressSanitizer's for SIGSEGV) is left in place: its report
    // says more than a stack.
    for (int signal : {SIGABRT, SIGSEGV, SIGBUS, SIGFPE}) {
      struct sigaction previous {};
      if (sigaction(signal, nullptr, &previous) == 0 && previous.sa_handler == SIG_DFL &&
          !(previous.sa_flags & SA_SIGINFO))
        sigaction(signal, &action, nullptr);
    }
  }
};
const CrashReport crashReport;

}  // namespace
