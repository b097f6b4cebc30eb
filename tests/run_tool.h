// Runs one of our executables as a user would, capturing its exit status and everything it printed.
#pragma once

#include <string>

namespace pb::test {

struct ToolRun {
  int status = -1;     // exit status; -1 when it did not exit normally (a crash)
  std::string output;  // stdout and stderr together
};

// `arguments` is passed through the shell, so quote paths with spaces.
ToolRun RunTool(const std::string& executable, const std::string& arguments);

#ifdef PB_BAKE_EXE
// The bake command with `arguments`.
inline ToolRun RunBake(const std::string& arguments) { return RunTool(PB_BAKE_EXE, arguments); }
#endif

}  // namespace pb::test
