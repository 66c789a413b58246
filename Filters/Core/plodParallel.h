// SPDX-License-Identifier: BSD-3-Clause
/**
 * @file plodParallel.h
 * @brief How the VTK-free kernels run in parallel without depending on a thread library: a
 * kernel takes a ParallelFor and hands it ranges; the VTK layer passes one that runs them with
 * vtkSMPTools, tests pass SerialFor (or one that runs the ranges in another order). A kernel's
 * result never depends on how the ranges were run.
 */
#ifndef plodParallel_h
#define plodParallel_h

#include <algorithm>
#include <cstdint>
#include <functional>

namespace plod
{

/// Runs `body(begin, end)` over [0, n) split in ranges of at most `grain`, possibly in parallel.
using ParallelFor =
  std::function<void(int64_t n, int64_t grain, const std::function<void(int64_t, int64_t)>& body)>;

/// Sequential ParallelFor, for tests and for single-threaded runs.
inline void SerialFor(int64_t n, int64_t grain, const std::function<void(int64_t, int64_t)>& body)
{
  grain = std::max<int64_t>(1, grain);
  for (int64_t b = 0; b < n; b += grain)
  {
    body(b, std::min(n, b + grain));
  }
}

} // namespace plod

#endif
