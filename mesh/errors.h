// The two kinds of error, kept apart (STYLE.md habit 7):
//  - InputError: bad user input (a file, a line, an option). Caught by the tools, printed as
//    "file:line: error: message", and turned into a non-zero exit. Never an assert.
//  - PB_CHECK: a broken internal invariant. Prints the condition and location and aborts. PB_CHECK_EQ/NE/LT/LE/
//    GT/GE also print both operands (pbrt-v4's CHECK_GE); PB_DCHECK and PB_DCHECK_* are compiled out of release
//    builds (NDEBUG), so hot loops can carry checks that debug and sanitizer builds run.
#pragma once

#include <cstdio>
#include <cstdlib>
#include <sstream>
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

// A failed comparison check: prints both operands.
template <typename A, typename B>
[[noreturn]] void CheckOpFailed(const char* comparison, const char* file, int line, const A& a, const B& b) {
  std::ostringstream operands;
  operands << "left " << a << ", right " << b;
  CheckFailed(comparison, file, line, operands.str().c_str());
}

}  // namespace pb

#define PB_CHECK(condition, message) \
  ((condition) ? void(0) : ::pb::CheckFailed(#condition, __FILE__, __LINE__, message))

#define PB_CHECK_OP(a, op, b)                                                                   \
  do {                                                                                          \
    const auto& pb_check_a_ = (a);                                                              \
    const auto& pb_check_b_ = (b);                                                              \
    if (!(pb_check_a_ op pb_check_b_))                                                          \
      ::pb::CheckOpFailed(#a " " #op " " #b, __FILE__, __LINE__, pb_check_a_, pb_check_b_);     \
  } while (false)
#define PB_CHECK_EQ(a, b) PB_CHECK_OP(a, ==, b)
#define PB_CHECK_NE(a, b) PB_CHECK_OP(a, !=, b)
#define PB_CHECK_LT(a, b) PB_CHECK_OP(a, <, b)
#define PB_CHECK_LE(a, b) PB_CHECK_OP(a, <=, b)
#define PB_CHECK_GT(a, b) PB_CHECK_OP(a, >, b)
#define PB_CHECK_GE(a, b) PB_CHECK_OP(a, >=, b)

#ifdef NDEBUG
#define PB_DCHECK(condition, message) void(0)
#define PB_DCHECK_OP(a, op, b) void(0)
#else
#define PB_DCHECK(condition, message) PB_CHECK(condition, message)
#define PB_DCHECK_OP(a, op, b) PB_CHECK_OP(a, op, b)
#endif
#define PB_DCHECK_EQ(a, b) PB_DCHECK_OP(a, ==, b)
#define PB_DCHECK_LT(a, b) PB_DCHECK_OP(a, <, b)
#define PB_DCHECK_LE(a, b) PB_DCHECK_OP(a, <=, b)
