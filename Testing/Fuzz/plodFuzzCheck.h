// SPDX-License-Identifier: BSD-3-Clause
/**
 * @file plodFuzzCheck.h
 * @brief The fuzz targets' failed check: what failed is printed, then the target aborts, so
 *        that libFuzzer keeps the input (FuzzOctreeFile, FuzzPLYPieces).
 */
#ifndef plodFuzzCheck_h
#define plodFuzzCheck_h

#include <cstdio>
#include <cstdlib>
#include <string>

/// Aborts with "<target>: check failed: <condition> (<what>)" when `cond` is false.
#define PLOD_FUZZ_CHECK(target, cond, what)                                                        \
  do                                                                                               \
  {                                                                                                \
    if (!(cond))                                                                                   \
    {                                                                                              \
      std::fprintf(                                                                                \
        stderr, "%s: check failed: %s (%s)\n", target, #cond, std::string(what).c_str());          \
      std::abort();                                                                                \
    }                                                                                              \
  } while (0)

#endif
