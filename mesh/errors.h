// The two kinds of error, kept apart (STYLE.md habit 7):
//  - InputError: bad user input (a file, a line, an option). Caught by the tools, printed as
//    "file:line: error: message", and turned into a non-zero exit. Never an assert.
//  - PB_CHECK: a broken internal invariant. Prints the condition and location and aborts.
#pragma once

#include <cstdio>
#include <cstdlib>
#include <stdexcept>
#include <string>

namespace pb {

class InputError : public std::runtime_error {
 public:
  // line 0 means "the whole file" and is not printed.
  InputError(const std::string& file, int line, const std::string& message)
      : std::runtime_error(Format(file, line, message)), file_(file), line_(line), message_(message) {}
  const std::string& file() const { return file_; }
  int line() const { return line_; }
  const std::string& message() const { return message_; }  // without the "file:line: error: " prefix

 private:
  static std::string Format(const std::string& file, int line, const std::string& message) {
    std::string text = file;
    if (line > 0) text.append(":").append(std::to_string(line));
    return text.append(": error: ").append(message);
  }
  std::string file_;
  int line_;
  std::string message_;
};

[[noreturn]] inline void CheckFailed(const char* condition, const char* file, int line, const char* message) {
  std::fprintf(stderr, "%s:%d: internal error: CHECK(%s) failed: %s\n", file, line, condition, message);
  std::abort();
}

}  // namespace pb

#define PB_CHECK(condition, message) \
  ((condition) ? void(0) : ::pb::CheckFailed(#condition, __FILE__, __LINE__, message))
