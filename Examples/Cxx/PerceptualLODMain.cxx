// SPDX-License-Identifier: BSD-3-Clause
// PerceptualLOD's main program. Today: builds the multiscale octree of a model (or opens one
// saved before), prints what it holds level by level, and the crack-free patches of each
// uniform cut. Usage:
//
//   PerceptualLODMain [model.ply|.stl|.obj|.vtp|.plod] [--level N] [--mean] [--serial]
//                     [--save octree.plod]
//
// Without a file it uses a generated detailed model (a displaced sphere of about 500k
// triangles), so it runs anywhere. --save writes the built octree to a file that this program,
// the viewer and vtkMultiscaleOctreeReader open without building again.
#include "plodTestUtilities.h"

#include "vtkFieldData.h"
#include "vtkFloatArray.h"
#include "vtkMultiscaleOctree.h"
#include "vtkMultiscaleOctreeBuilder.h"
#include "vtkMultiscaleOctreeCutter.h"
#include "vtkMultiscaleOctreeReader.h"
#include "vtkMultiscaleOctreeWriter.h"
#include "vtkMultiscalePatchGenerator.h"
#include "vtkNew.h"
#include "vtkPolyData.h"
#include "vtkSmartPointer.h"
#include "vtkUnsignedCharArray.h"

#include <algorithm>
#include <cstdio>
#include <string>
#include <vector>

int main(int argc, char* argv[])
{
  std::string file, save;
  int level = -1;
  bool mean = false, serial = false;
  for (int i = 1; i < argc; ++i)
  {
    const std::string a = argv[i];
    if (a == "--level" && i + 1 < argc)
      level = std::atoi(argv[++i]);
    else if (a == "--mean")
      mean = true;
    else if (a == "--serial")
      serial = true;
    else if (a == "--save" && i + 1 < argc)
      save = argv[++i];
    else if (a == "-h" || a == "--help")
    {
      std::printf("usage: %s [model.ply|.stl|.obj|.vtp|.plod] [--level N] [--mean] [--serial] "
                  "[--save octree.plod]\n",
        argv[0]);
      return 0;
    }
    else
      file = a;
  }
  vtkNew<vtkMultiscaleOctreeBuilder> builder;
  vtkNew<vtkMultiscaleOctreeReader> reader;
  vtkMultiscaleOctree* octree = nullptr;
  if (!file.empty() && vtkMultiscaleOctreeReader::CanReadFile(file.c_str()))
  {
    reader->SetFileName(file.c_str());
    reader->Update();
    octree = reader->GetOutput();
    if (octree->GetNumberOfNodes() == 0)
    {
      std::fprintf(stderr, "%s\ncannot read a model from '%s' (an octree file)\n",
        reader->GetErrorMessage(), file.c_str());
      return 1;
    }
    std::printf("octree file: %s, opened in %.2f ms (%s)\n", file.c_str(),
      reader->GetReadTime() * 1e3, reader->GetMapped() ? "mapped" : "read into memory");
  }
  else
  {
    vtkSmartPointer<vtkPolyData> model;
    if (file.empty())
    {
      std::printf("model: generated displaced sphere\n");
      model = plodtest::MakeBlob(11, 500, 0.2);
    }
    else
    {
      model = plodtest::ReadModel(file);
      if (!model)
      {
        std::fprintf(
          stderr, "cannot read a model from '%s' (PLY, STL, OBJ, VTP or .plod)\n", file.c_str());
        return 1;
      }
      std::printf("model: %s\n", file.c_str());
    }
    std::printf("input: %lld points, %lld polygons\n",
      static_cast<long long>(model->GetNumberOfPoints()),
      static_cast<long long>(model->GetNumberOfPolys() + model->GetNumberOfStrips()));
    builder->SetInputData(model);
    builder->SetFinestLevel(level);
    if (mean)
      builder->SetVertexRuleToMean();
    builder->SetMultiThreaded(!serial);
    builder->Update();
    octree = builder->GetOutput();
    if (octree->GetNumberOfNodes() == 0)
    {
      std::fprintf(stderr, "the octree is empty (see the builder's messages above)\n");
      return 1;
    }
    std::printf("finest level: %s\n", builder->GetFinestLevelReason());
    std::printf("build: %.1f ms (%s), %lld triangles kept, %lld skipped, %lld nodes not "
                "topologically safe\n",
      builder->GetBuildTime() * 1e3, serial ? "1 thread" : "vtkSMPTools",
      static_cast<long long>(octree->GetNumberOfSurfaceTriangles()),
      static_cast<long long>(builder->GetNumberOfSkippedTriangles()),
      static_cast<long long>(builder->GetNumberOfUnsafeNodes()));
  }
  std::printf("octree: %lld nodes, finest level %d, root edge %g at (%g, %g, %g)\n",
    static_cast<long long>(octree->GetNumberOfNodes()), octree->GetFinestLevel(),
    octree->GetRootEdge(), octree->GetOrigin()[0], octree->GetOrigin()[1], octree->GetOrigin()[2]);
  std::printf("memory: %.1f MiB (%.1f bytes per input triangle)\n",
    octree->GetActualMemorySize() / 1024.0,
    octree->GetActualMemorySize() * 1024.0 /
      std::max<vtkIdType>(1, octree->GetNumberOfSurfaceTriangles()));
  if (!save.empty())
  {
    vtkNew<vtkMultiscaleOctreeWriter> writer;
    writer->SetInputData(octree);
    writer->SetFileName(save.c_str());
    if (!writer->Write())
    {
      std::fprintf(stderr, "cannot save the octree: %s\n", writer->GetErrorMessage());
      return 1;
    }
    std::printf("saved: %s (open it with this program, the viewer or vtkMultiscaleOctreeReader)\n",
      save.c_str());
  }

  vtkFieldData* nd = octree->GetNodeData();
  auto* lv = vtkUnsignedCharArray::SafeDownCast(nd->GetArray("Level"));
  auto* angle =
    vtkFloatArray::SafeDownCast(nd->GetArray(vtkMultiscaleOctree::ConeAngleArrayName()));
  auto* shape = vtkFloatArray::SafeDownCast(nd->GetArray("ShapeError"));
  vtkNew<vtkMultiscaleOctreeCutter> cutter;
  cutter->SetInputData(octree);
  vtkNew<vtkMultiscalePatchGenerator> patches;
  patches->SetInputConnection(cutter->GetOutputPort());
  std::printf("\nlevel     nodes   cell edge   cone angle (deg) mean/max   shape error mean/max"
              "   patches: triangles    ms\n");
  for (int l = 0; l <= octree->GetFinestLevel() + 1; ++l)
  {
    if (l > octree->GetFinestLevel())
    {
      cutter->SetLevel(-1);
      patches->Update();
      std::printf(" full %9lld   (every leaf opened: the input)%46lld %6.1f\n",
        static_cast<long long>(octree->GetNumberOfSurfacePoints()),
        static_cast<long long>(patches->GetNumberOfTriangles()), patches->GetGenerateTime() * 1e3);
      break;
    }
    long long count = 0;
    double am = 0, ax = 0, sm = 0, sx = 0;
    for (vtkIdType n = 0; n < octree->GetNumberOfNodes(); ++n)
    {
      if (lv->GetValue(n) != l)
        continue;
      ++count;
      const double a = angle->GetValue(n) * 180.0 / 3.14159265358979;
      am += a;
      ax = std::max(ax, a);
      sm += shape->GetValue(n);
      sx = std::max(sx, double(shape->GetValue(n)));
    }
    cutter->SetLevel(l);
    patches->Update();
    std::printf("%5d %9lld   %9.3g   %8.1f / %6.1f            %9.3g / %9.3g   %18lld %6.1f\n", l,
      count, octree->GetCellEdge(l), am / count, ax, sm / count, sx,
      static_cast<long long>(patches->GetNumberOfTriangles()), patches->GetGenerateTime() * 1e3);
  }
  return 0;
}
