// levelfuse: checks of internal invariants, compiled into the sanitizer and
// Debug builds only.
#pragma once

#include <cstdio>
#include <cstdlib>

/// LEVELFUSE_DEBUG_CHECK(condition, what): where LEVELFUSE_DEBUG_CHECKS is
/// defined (the ASan, TSan and Debug builds, cmake/LevelfuseCompilerSettings.cmake),
/// aborts naming the file, the line and `what` if `condition` is false;
/// elsewhere compiles to nothing and evaluates nothing. For invariants the
/// code's safety rests on, such as what a parallel pass may write in place.
#ifdef LEVELFUSE_DEBUG_CHECKS
#define LEVELFUSE_DEBUG_CHECK(condition, what)                                                        \
  do {                                                                                                \
    if (!(condition)) {                                                                               \
      std::fprintf(stderr, "%s:%d: levelfuse invariant broken: %s (%s)\n", __FILE__, __LINE__, what, \
                   #condition);                                                                       \
      std::abort();                                                                                   \
    }                                                                                                 \
  } while (false)
#else
#define LEVELFUSE_DEBUG_CHECK(condition, what) \
  do {                                         \
  } while (false)
#endif
