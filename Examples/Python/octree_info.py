"""Build the multiscale octree of a model from Python and look at it with numpy.

    PYTHONPATH=build/lib/python3/dist-packages /usr/bin/python3 Examples/Python/octree_info.py [model.ply]
"""
import sys

import numpy as np
from vtkmodules.util.numpy_support import vtk_to_numpy
from vtkmodules.vtkFiltersSources import vtkSphereSource

from perceptual_lod import vtkMultiscaleOctreeBuilder


builder = vtkMultiscaleOctreeBuilder()
if len(sys.argv) > 1:
    # the builder reads a PLY file itself (no polydata of the model), refusing a damaged file,
    # a FIFO or a model too big for its memory limit with a message
    builder.SetFileName(sys.argv[1])
else:
    source = vtkSphereSource()
    source.SetThetaResolution(200)
    source.SetPhiResolution(200)
    builder.SetInputConnection(source.GetOutputPort())
builder.Update()
octree = builder.GetOutput()
if octree.GetNumberOfNodes() == 0:
    sys.exit(f'{sys.argv[1]}: no octree (see the message above)')

data = octree.GetNodeData()
level = vtk_to_numpy(data.GetArray('Level'))
angle = np.degrees(vtk_to_numpy(data.GetArray('ConeAngle')))
shape = vtk_to_numpy(data.GetArray('ShapeError'))
vertex = vtk_to_numpy(data.GetArray('Vertex')) + np.array(octree.GetOrigin())  # world coordinates

print(f'{octree.GetNumberOfNodes()} nodes, finest level {octree.GetFinestLevel()}, '
      f'built in {builder.GetBuildTime() * 1e3:.1f} ms')
for l in range(octree.GetFinestLevel() + 1):
    at = level == l
    print(f'level {l:2d}: {at.sum():8d} nodes, cone angle max {angle[at].max():6.1f} deg, '
          f'shape error max {shape[at].max():.3g}')
print('finest vertices span', vertex[level == octree.GetFinestLevel()].min(axis=0),
      vertex[level == octree.GetFinestLevel()].max(axis=0))
