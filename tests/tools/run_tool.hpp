// Runs the `surftrace` program under test and captures what it prints.
#pragma once

#include <array>
#include <cstdio>
#include <string>

#include <sys/wait.h>

namespace surftrace::tools::test {

struct Result {
  int status;
  std::string output;  // stdout and stderr together
};

// Runs a shell command line and captures its standard output.
inline Result runShell(const std::string& cmd) {
  FILE* pipe = popen(cmd.c_str(), "r");
  if (!pipe) return {-1, "popen failed"};
  std::string out;
  std::array<char, 4096> buf;
  while (std::fgets(buf.data(), static_cast<int>(buf.size()), pipe)) out += buf.data();
  const int status = pclose(pipe);
  return {WIFEXITED(status) ? WEXITSTATUS(status) : -1, out};
}

// `cd` into `directory` first when it is not empty (recipes use paths relative to the repository).
inline Result runTool(const std::string& args, const std::string& directory = {}) {
  const std::string cd = directory.empty() ? "" : "cd '" + directory + "' && ";
  return runShell(cd + SURFTRACE_TOOL + " " + args + " 2>&1");
}

}  // namespace surftrace::tools::test
