"""Python tests of vtkMultiscaleOctreeCutter and vtkMultiscalePatchGenerator: a pipeline from
a source to triangles, cuts made with numpy, closed output for a closed input."""
import unittest

import numpy as np
from vtkmodules.util.numpy_support import numpy_to_vtk, vtk_to_numpy
from vtkmodules.vtkCommonDataModel import vtkPolyData
from vtkmodules.vtkFiltersCore import vtkFeatureEdges
from vtkmodules.vtkFiltersSources import vtkSphereSource

from perceptual_lod import (vtkMultiscaleOctree, vtkMultiscaleOctreeBuilder,
                            vtkMultiscaleOctreeCutter, vtkMultiscalePatchGenerator)


def open_edges(polydata):
    edges = vtkFeatureEdges()
    edges.SetInputData(polydata)
    edges.BoundaryEdgesOn()
    edges.NonManifoldEdgesOn()
    edges.FeatureEdgesOff()
    edges.ManifoldEdgesOff()
    edges.Update()
    return edges.GetOutput().GetNumberOfCells()


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
        for level in range(1, 7):
            cutter.SetLevel(level)
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
        patches.Update()
        self.assertTrue(cutter.GetOutput().HasValidCut())
        out = patches.GetOutput()
        self.assertEqual(open_edges(out), 0, 'two levels meet without a crack')
        nodes = vtk_to_numpy(out.GetPointData().GetArray('OctreeNode'))
        self.assertEqual(set(np.unique(level[nodes])), {3, 6})

    def test_without_cut_draws_finest(self):
        patches = vtkMultiscalePatchGenerator()
        patches.SetInputConnection(self.builder.GetOutputPort())
        patches.Update()
        self.assertGreater(patches.GetOutput().GetNumberOfPolys(), 10000)
        self.assertEqual(open_edges(patches.GetOutput()), 0)


if __name__ == '__main__':
    unittest.main()
