// Invariant checks (docs/design.md §12, tier 1): a failed check is a bug in ssgi, never bad input.
// It prints the expression, the operand values and the source location, then aborts.
#pragma once

#include <cstdio>
#include <cstdlib>
#include <sstream>
#include <string>

namespace ssgi::detail {

[[noreturn]] inline void CheckFailed(const char* file, int line, const char* expr, const std::string& values) {
  std::fprintf(stderr, "ssgi: internal check failed at %s:%d: %s%s\n", file, line, expr, values.c_str());
  std::abort();
}

template <class A, class B>
std::string FormatOperands(const A& a, const B& b) {
  std::ostringstream out;
  out << " (" << a << " vs " << b << ")";
  return out.str();
}

}  // namespace ssgi::detail

#define SSGI_CHECK(cond) \
  ((cond) ? (void)0 : ::ssgi::detail::CheckFailed(__FILE__, __LINE__, #cond, std::string()))

#define SSGI_CHECK_OP(a, op, b)                                                                      \
  do {                                                                                               \
    const auto& ssgiCheckA = (a);                                                                    \
    const auto& ssgiCheckB = (b);                                                                    \
    if (!(ssgiCheckA op ssgiCheckB))                                                                 \
      ::ssgi::detail::CheckFailed(__FILE__, __LINE__, #a " " #op " " #b,                             \
                                  ::ssgi::detail::FormatOperands(ssgiCheckA, ssgiCheckB));           \
  } while (0)

#define SSGI_CHECK_EQ(a, b) SSGI_CHECK_OP(a, ==, b)
#define SSGI_CHECK_NE(a, b) SSGI_CHECK_OP(a, !=, b)
#define SSGI_CHECK_LT(a, b) SSGI_CHECK_OP(a, <, b)
#define SSGI_CHECK_LE(a, b) SSGI_CHECK_OP(a, <=, b)
#define SSGI_CHECK_GT(a, b) SSGI_CHECK_OP(a, >, b)
#define SSGI_CHECK_GE(a, b) SSGI_CHECK_OP(a, >=, b)
