#include "sinew/core/assert.h"

#include <cstdio>
#include <cstdlib>

namespace sinew::detail {

void assertFailed(const char* condition, const char* message, const char* file, int line) {
  std::fprintf(stderr, "%s:%d: precondition failed: %s (%s)\n", file, line, message, condition);
  std::fflush(stderr);
  std::abort();
}

}  // namespace sinew::detail
