// The one way a test runs a Python oracle script (tests/oracles/*.py, MDAnalysis): under the
// interpreter that tests/CMakeLists.txt chose at configure time (SURFTRACE_PYTHON, checked
// there to import numpy and MDAnalysis), never whichever `python3` comes first on PATH.
#pragma once

#include <sys/wait.h>

#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <iterator>
#include <string>
#include <vector>

namespace surftrace::test {

// The interpreter chosen at configure time; "" when none there could import the oracles'
// modules (configure said so).
inline std::string oraclePython() { return SURFTRACE_PYTHON; }

// What to tell a user whose build found no interpreter with MDAnalysis.
inline std::string oraclePythonMissing() {
  return "no Python with numpy and MDAnalysis was found when this build was configured; "
         "install them (apt-get install python3-mdanalysis python3-numpy) and re-run cmake, "
         "or configure with -DSURFTRACE_PYTHON=/path/to/python3";
}

inline std::string shellQuoted(const std::string& s) {
  std::string out = "'";
  for (char c : s) {
    if (c == '\'')
      out += "'\\''";
    else
      out += c;
  }
  return out + "'";
}

struct OracleRun {
  int exitCode = -1;     // the script's exit status; -1 when it could not run
  std::string command;   // what ran, for failure messages
  std::string out, err;  // its standard output and error
  bool ok() const { return exitCode == 0; }
  // A failure message: the command, its status and its standard error.
  std::string describe() const {
    if (command.empty()) return oraclePythonMissing();
    return command + " exited " + std::to_string(exitCode) + ":\n" + err;
  }
};

// Runs the Python script at `path` (an oracle, or a script of examples/) with `args` under
// oraclePython(). `scratch` is a folder for the captured output (the caller's temporary folder).
inline OracleRun runPythonScript(const std::filesystem::path& path, const std::vector<std::string>& args,
                                 const std::filesystem::path& scratch) {
  OracleRun run;
  if (oraclePython().empty()) return run;
  const std::string script = path.filename().string();
  const std::filesystem::path outFile = scratch / (script + ".stdout");
  const std::filesystem::path errFile = scratch / (script + ".stderr");
  run.command = shellQuoted(oraclePython());
  run.command.append(" ").append(shellQuoted(path.string()));
  for (const std::string& a : args) run.command.append(" ").append(shellQuoted(a));
  const std::string full = run.command + " > " + shellQuoted(outFile.string()) + " 2> " +
                           shellQuoted(errFile.string());
  const int status = std::system(full.c_str());
  run.exitCode = (status != -1 && WIFEXITED(status)) ? WEXITSTATUS(status) : -1;
  auto slurp = [](const std::filesystem::path& p) {
    std::ifstream in(p, std::ios::binary);
    return std::string((std::istreambuf_iterator<char>(in)), std::istreambuf_iterator<char>());
  };
  run.out = slurp(outFile);
  run.err = slurp(errFile);
  return run;
}

// Runs tests/oracles/`script` with `args` under oraclePython().
inline OracleRun runOracleScript(const std::string& script, const std::vector<std::string>& args,
                                 const std::filesystem::path& scratch) {
  return runPythonScript(std::filesystem::path(SURFTRACE_SOURCE_DIR) / "tests" / "oracles" / script, args, scratch);
}

}  // namespace surftrace::test
