#include "tests/run_tool.h"

#include <sys/wait.h>

#include <array>
#include <cstdio>

namespace pb::test {

ToolRun RunTool(const std::string& executable, const std::string& arguments) {
  ToolRun run;
  FILE* pipe = popen((executable + " " + arguments + " 2>&1").c_str(), "r");
  if (!pipe) return run;
  std::array<char, 4096> buffer{};
  for (size_t n; (n = fread(buffer.data(), 1, buffer.size(), pipe)) > 0;) run.output.append(buffer.data(), n);
  const int raw = pclose(pipe);
  run.status = WIFEXITED(raw) ? WEXITSTATUS(raw) : -1;
  return run;
}

}  // namespace pb::test
