// SINEW_ASSERT(condition, "what must hold"): checks a documented precondition (a header's
// "Precondition:"). On in the sanitizer build and in Debug builds (SINEW_ASSERTS defined): a
// broken precondition prints the condition, the message, file and line on stderr and aborts,
// so CI's sanitizer run stops at the caller's mistake instead of at a later symptom. Off in
// Release: the condition is not evaluated (but still compiled, so it stays correct).
// Errors a user can cause (files, settings) are Status values, never asserts.
#pragma once

namespace sinew::detail {
[[noreturn]] void assertFailed(const char* condition, const char* message, const char* file,
                               int line);
}  // namespace sinew::detail

#if defined(SINEW_ASSERTS)
#define SINEW_ASSERT(condition, message) \
  ((condition) ? static_cast<void>(0)    \
               : ::sinew::detail::assertFailed(#condition, message, __FILE__, __LINE__))
#else
#define SINEW_ASSERT(condition, message) static_cast<void>(sizeof((condition) ? 1 : 0))
#endif
