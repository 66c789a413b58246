"""Build the multiscale octree of a model from Python and look at it with numpy.

    PYTHONPATH=build/lib/python3/dist-packages /usr/bin/python3 Examples/Python/octree_info.py [model.ply]
"""
import os
import sys

import numpy as np
from vtkmodules.util.numpy_support import vtk_to_numpy
from vtkmodules.vtkFiltersSources import vtkSphereSource
from vtkmodules.vtkIOPLY import vtkPLYReader

from perceptual_lod import vtkMultiscaleOctreeBuilder, vtkPLYFileCheck


def checked(path):
    """`path` if a reader may open it: a regular file (a FIFO would make the reader wait forever)
    that, for PLY, vtkPLYFileCheck accepts (VTK's PLY reader crashes on some damaged files)."""
    if not os.path.isfile(path):
        sys.exit(f'{path}: missing, or not a regular file (a directory, a FIFO or a device)')
    if path.lower().endswith('.ply'):
        check = vtkPLYFileCheck()
        check.SetFileName(path)
        if not check.Check():
            sys.exit(f'{path}: {check.GetErrorMessage()}')
    return path


if len(sys.argv) > 1:
    source = vtkPLYReader()
    source.SetFileName(checked(sys.argv[1]))
else:
    source = vtkSphereSource()
    source.SetThetaResolution(200)
    source.SetPhiResolution(200)

builder = vtkMultiscaleOctreeBuilder()
builder.SetInputConnection(source.GetOutputPort())
builder.Update()
octree = builder.GetOutput()

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
