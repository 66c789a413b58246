# The VTK-free kernels' sources, the one list of them: the library plod_core
# (Filters/Core/CMakeLists.txt) and the fuzzers' instrumented copy (Testing/Fuzz) both use it.
set(plod_core_sources
  plodBudgetController.cxx
  plodBuildUtil.cxx
  plodCloudSurface.cxx
  plodCut.cxx
  plodOctree.cxx
  plodOctreeBuilder.cxx
  plodOctreeFile.cxx
  plodOctreeSchema.cxx
  plodPatches.cxx
  plodPLYCheck.cxx
  plodSelector.cxx)
set(plod_core_headers
  plodBudgetController.h
  plodBuildUtil.h
  plodCloudSurface.h
  plodCut.h
  plodOctree.h
  plodOctreeBuilder.h
  plodOctreeFile.h
  plodOctreeSchema.h
  plodOctreeStorage.h
  plodPatches.h
  plodPLYCheck.h
  plodSelector.h)
