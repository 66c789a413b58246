"""Python tests of vtkMultiscaleOctreeBuilder: import from the package, node arrays as numpy
arrays, pipeline behaviour, and errors on bad input."""
import math
import os
import unittest

import numpy as np
from vtkmodules.util.numpy_support import vtk_to_numpy
from vtkmodules.vtkCommonCore import vtkCommand, vtkPoints
from vtkmodules.vtkCommonDataModel import vtkCellArray, vtkPolyData
from vtkmodules.vtkFiltersSources import vtkSphereSource

from perceptual_lod import vtkMultiscaleOctree, vtkMultiscaleOctreeBuilder


def sphere(resolution=48):
    source = vtkSphereSource()
    source.SetThetaResolution(resolution)
    source.SetPhiResolution(resolution)
    return source


class ErrorCatcher:
    def __init__(self, obj, event=vtkCommand.ErrorEvent):
        self.messages = []
        obj.AddObserver(event, self.on_error)

    def on_error(self, caller, event, data=None):
        self.messages.append(str(data))

    on_error.CallDataType = 'string0'  # VTK passes the message text as the call data


class TestBuilder(unittest.TestCase):
    def test_arrays_are_numpy_and_consistent(self):
        source = sphere()  # a pipeline connection does not keep its producer alive
        builder = vtkMultiscaleOctreeBuilder()
        builder.SetInputConnection(source.GetOutputPort())
        builder.SetFinestLevel(5)
        builder.Update()
        octree = builder.GetOutput()
        self.assertIsInstance(octree, vtkMultiscaleOctree)
        self.assertTrue(octree.IsConsistent())
        data = octree.GetNodeData()
        n = octree.GetNumberOfNodes()
        level = vtk_to_numpy(data.GetArray('Level'))
        parent = vtk_to_numpy(data.GetArray('Parent'))
        vertex = vtk_to_numpy(data.GetArray('Vertex')) + np.array(octree.GetOrigin())
        axis = vtk_to_numpy(data.GetArray('ConeAxis'))
        angle = vtk_to_numpy(data.GetArray('ConeAngle'))
        self.assertEqual(len(level), n)
        self.assertEqual(parent[0], -1)
        np.testing.assert_array_equal(level[1:], level[parent[1:]] + 1)
        np.testing.assert_allclose(np.linalg.norm(axis, axis=1), 1.0, atol=1e-5)
        self.assertTrue(np.all((angle >= 0) & (angle <= math.pi + 1e-6)))
        finest = level == 5
        radius = np.linalg.norm(vertex[finest], axis=1)
        # the UV sphere of radius 0.5 is inscribed: its finest vertices lie within a cell of it
        self.assertLess(np.abs(radius - 0.5).max(), octree.GetCellEdge(5))
        # outward cone axes on the sphere
        dots = np.einsum('ij,ij->i', axis[finest], vertex[finest] / radius[:, None])
        self.assertGreater(dots.min(), 0.8)

    def test_no_reexecution_without_change(self):
        source = sphere()
        builder = vtkMultiscaleOctreeBuilder()
        builder.SetInputConnection(source.GetOutputPort())
        builder.Update()
        t = builder.GetOutput().GetMTime()
        builder.SetFinestLevel(builder.GetFinestLevel())
        builder.Update()
        self.assertEqual(builder.GetOutput().GetMTime(), t)

    def test_nan_points_skip_their_triangles_with_a_warning(self):
        points = vtkPoints()
        for p in [(0, 0, 0), (1, 0, 0), (0, 1, 0), (0, float('nan'), 0)]:
            points.InsertNextPoint(p)
        cells = vtkCellArray()
        cells.InsertNextCell(3, [0, 1, 2])
        cells.InsertNextCell(3, [0, 1, 3])
        mesh = vtkPolyData()
        mesh.SetPoints(points)
        mesh.SetPolys(cells)
        builder = vtkMultiscaleOctreeBuilder()
        warnings = ErrorCatcher(builder, vtkCommand.WarningEvent)
        builder.SetInputData(mesh)
        builder.Update()
        self.assertTrue(any('NaN or infinite' in m for m in warnings.messages), warnings.messages)
        self.assertEqual(builder.GetNumberOfInvalidTriangles(), 1)
        self.assertEqual(builder.GetOutput().GetNumberOfSurfaceTriangles(), 1)
        # nothing usable left: an error, an empty octree
        cells2 = vtkCellArray()
        cells2.InsertNextCell(3, [0, 1, 3])
        mesh.SetPolys(cells2)
        errors = ErrorCatcher(builder)
        builder.Update()
        self.assertTrue(any('no usable triangle' in m for m in errors.messages), errors.messages)
        self.assertEqual(builder.GetOutput().GetNumberOfNodes(), 0)

    def test_surface_is_the_input(self):
        source = sphere(30)
        source.Update()
        builder = vtkMultiscaleOctreeBuilder()
        builder.SetInputConnection(source.GetOutputPort())
        builder.Update()
        octree = builder.GetOutput()
        surface = octree.GetSurfaceData()
        ids = vtk_to_numpy(surface.GetArray('InputPointId'))
        points = vtk_to_numpy(surface.GetArray('Points')) + np.array(octree.GetOrigin())
        triangles = vtk_to_numpy(surface.GetArray('Triangles'))
        original = vtk_to_numpy(source.GetOutput().GetPoints().GetData())
        np.testing.assert_allclose(points, original[ids], atol=1e-6)
        self.assertEqual(len(triangles), source.GetOutput().GetNumberOfPolys())
        self.assertEqual(octree.GetNumberOfBoundaryEdges(), 0)

    def test_modes_and_parameters(self):
        builder = vtkMultiscaleOctreeBuilder()
        self.assertEqual(builder.GetVertexRule(), vtkMultiscaleOctreeBuilder.VERTEX_QEF)
        builder.SetVertexRuleToMean()
        self.assertEqual(builder.GetVertexRule(), vtkMultiscaleOctreeBuilder.VERTEX_MEAN)
        self.assertEqual(vtkMultiscaleOctreeBuilder.GetMaximumFinestLevel(), 21)

    @unittest.skipUnless(os.path.exists(os.path.join(os.environ.get('PLOD_DATA_DIR', '/nonexistent'),
                                                     'bun_zipper.ply')),
                         'Stanford data (PLOD_DATA_DIR) not found')
    def test_bunny(self):
        from vtkmodules.vtkIOPLY import vtkPLYReader
        reader = vtkPLYReader()
        reader.SetFileName(os.path.join(os.environ['PLOD_DATA_DIR'], 'bun_zipper.ply'))
        builder = vtkMultiscaleOctreeBuilder()
        builder.SetInputConnection(reader.GetOutputPort())
        builder.Update()
        self.assertTrue(builder.GetOutput().IsConsistent())
        self.assertGreater(builder.GetOutput().GetNumberOfNodes(), 10000)


if __name__ == '__main__':
    unittest.main()
