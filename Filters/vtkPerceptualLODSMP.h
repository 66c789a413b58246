// SPDX-License-Identifier: BSD-3-Clause
/**
 * @file vtkPerceptualLODSMP.h
 * @brief The kernels' ranges (plod::ParallelFor) run by vtkSMPTools: how the VTK classes of
 *        this module hand their cores to the VTK-free kernels. Private to the module.
 */
#ifndef vtkPerceptualLODSMP_h
#define vtkPerceptualLODSMP_h

#include "plodParallel.h"
#include "vtkSMPTools.h"

namespace plodvtk
{
/// vtkSMPTools::For over the kernel's ranges; SerialFor when `multiThreaded` is false.
inline plod::ParallelFor SMPRanges(bool multiThreaded = true)
{
  if (!multiThreaded)
  {
    return plod::SerialFor;
  }
  return [](int64_t n, int64_t grain, const std::function<void(int64_t, int64_t)>& body) {
    vtkSMPTools::For(0, static_cast<vtkIdType>(n), static_cast<vtkIdType>(grain),
      [&body](vtkIdType b, vtkIdType e) { body(b, e); });
  };
}
}

#endif
