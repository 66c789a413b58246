"""Python tests of vtkMultiscaleOctreeCutter and vtkMultiscalePatchGenerator: a pipeline from
a source to triangles, cuts made with numpy, closed output for a closed input."""
import unittest

import numpy as np
from vtkmodules.util.numpy_support import numpy_to_vtk, vtk_to_numpy
from vtkmodules.vtkCommonDataModel import vtkPolyData
from vtkmodules.vtkFiltersSources import vtkSphereSource

from perceptual_lod import (vtkMultiscaleOctree, vtkMultiscaleOctreeBuilder,
                            vtkMultiscaleOctreeCutter, vtkMultiscalePatchGenerator)


def open_edges(polydata):
    """Edges not used as often in both directions (cracks or orientation errors)."""
    tris = vtk_to_numpy(polydata.GetPolys().GetConnectivityArray()).reshape(-1, 3)
    e = np.concatenate([tris[:, [0, 1]], tris[:, [1, 2]], tris[:, [2, 0]]])
    sign = np.where(e[:, 0] < e[:, 1], 1, -1)
    key = np.sort(e, axis=1)
    uniq, inverse = np.unique(key, axis=0, return_inverse=True)
    return int(np.count_nonzero(np.bincount(inverse.ravel(), weights=sign, minlength=len(uniq))))


class TestPatches(unittest.TestCase):
    def setUp(self):
        self.source = vtkSphereSource()
        self.source.SetThetaResolution(80)
        self.source.SetPhiResolution(80)
        self.builder = vtkMultiscaleOctreeBuilder()
        self.builder.SetInputConnection(self.source.GetOutputPort())
        self.builder.SetFinestLevel(6)

    def test_uniform_levels_are_closed(self):
        cutter = vtkMultiscaleOctreeCutter()
        cutter.SetInputConnection(self.builder.GetOutputPort())
        patches = vtkMultiscalePatchGenerator()
        patches.SetInputConnection(cutter.GetOutputPort())
        counts = []
        for level in list(range(1, 7)) + [-1]:
            cutter.SetLevel(level)
            patches.SetFoldHandlingToKeep()  # every triangle of the cut: closed
            patches.Update()
            out = patches.GetOutput()
            self.assertEqual(open_edges(out), 0, f'level {level}')
            self.assertIsNotNone(out.GetPointData().GetNormals())
            counts.append(out.GetNumberOfPolys())
        self.assertEqual(counts, sorted(counts))  # finer levels, more triangles
        self.assertEqual(patches.GetNumberOfTriangles(), counts[-1])

    def test_cut_from_numpy_refine_array(self):
        self.builder.Update()
        octree = vtkMultiscaleOctree()
        octree.ShallowCopy(self.builder.GetOutput())
        data = octree.GetNodeData()
        level = vtk_to_numpy(data.GetArray('Level'))
        vertex = vtk_to_numpy(data.GetArray('Vertex')) + np.array(octree.GetOrigin())
        # fine where x > 0, coarse elsewhere
        refine = ((level < 3) | (vertex[:, 0] > 0)).astype(np.uint8)
        array = numpy_to_vtk(refine, deep=1)
        array.SetName('Refine')
        data.AddArray(array)
        cutter = vtkMultiscaleOctreeCutter()
        cutter.SetInputData(octree)
        cutter.SetModeToRefineArray()
        patches = vtkMultiscalePatchGenerator()
        patches.SetInputConnection(cutter.GetOutputPort())
        patches.GenerateNodeIdsOn()
        patches.SetFoldHandlingToKeep()
        patches.Update()
        self.assertTrue(cutter.GetOutput().HasValidCut())
        out = patches.GetOutput()
        self.assertEqual(open_edges(out), 0, 'levels meet without a crack')
        nodes = vtk_to_numpy(out.GetPointData().GetArray('OctreeNode'))
        levels = set(np.unique(level[nodes]))
        # coarse (3) where x < 0, the input (opened leaves, 6) where x > 0, between near x = 0
        self.assertTrue({3, 6} <= levels <= {3, 4, 5, 6}, levels)

    def test_without_cut_draws_the_input(self):
        patches = vtkMultiscalePatchGenerator()
        patches.SetInputConnection(self.builder.GetOutputPort())
        patches.Update()
        self.source.Update()
        self.assertEqual(patches.GetOutput().GetNumberOfPolys(),
                         self.source.GetOutput().GetNumberOfPolys())
        self.assertEqual(open_edges(patches.GetOutput()), 0)


if __name__ == '__main__':
    unittest.main()
