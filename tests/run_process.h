// Runs one of the project's command-line tools and captures what it prints.
#pragma once
#include <cstdio>
#include <string>
#include <sys/wait.h>

// Returns the exit code (128 + signal when the tool crashed); stdout and stderr land in `output`.
inline int runProcess(const std::string& binary, const std::string& args, std::string& output) {
  std::string cmd = binary + " " + args + " 2>&1";
  FILE* pipe = popen(cmd.c_str(), "r");
  if (!pipe) return -1;
  char buffer[512];
  output.clear();
  while (fgets(buffer, sizeof(buffer), pipe)) output += buffer;
  int status = pclose(pipe);
  return WIFEXITED(status) ? WEXITSTATUS(status) : 128 + WTERMSIG(status);
}
