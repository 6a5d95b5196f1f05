// tests/crash_report.cpp, linked into this binary: a failed allocation and a
// fatal signal leave the stack in the log, and otherwise behave as before.
#include <gtest/gtest.h>

#include <csignal>
#include <cstdlib>
#include <new>
#include <string>

// operator new that finds no memory writes the stack, with the test's own frame named, then throws
// std::bad_alloc as it would have.
TEST(CrashReport, AFailedAllocationWritesTheStackAndStillThrows) {
  volatile size_t huge = size_t(1) << 62;  // more than any machine has: malloc refuses it at once
  testing::internal::CaptureStderr();
  bool thrown = false;
  try {
    void* volatile p = ::operator new(huge);
    ::operator delete(p);
  } catch (const std::bad_alloc&) {
    thrown = true;
  }
  const std::string log = testing::internal::GetCapturedStderr();
  EXPECT_TRUE(thrown);
  EXPECT_NE(log.find("crash_report: operator new found no memory"), std::string::npos) << log;
  EXPECT_NE(log.find("AFailedAllocationWritesTheStackAndStillThrows"), std::string::npos)
      << "the test binary's frames are not named:\n"
      << log;
}

// An abort (what glibc's heap checks do) writes the stack, and the process still dies of SIGABRT.
TEST(CrashReportDeathTest, AnAbortWritesTheStackAndStillKillsTheProcess) {
  GTEST_FLAG_SET(death_test_style, "threadsafe");
  EXPECT_EXIT(std::abort(), testing::KilledBySignal(SIGABRT), "crash_report: SIGABRT .*at:.*libc.so.6\\(abort");
}
