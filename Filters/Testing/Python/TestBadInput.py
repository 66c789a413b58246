"""The bad-input suite from Python (issue 10): one case per class of failure, through the whole
pipeline (builder -> selector -> patch generator), as a numpy user would meet them. Each asserts a
clear error or warning, a valid (possibly empty) output, and no crash or hang."""
import math
import unittest

import numpy as np
from vtkmodules.util.numpy_support import numpy_to_vtk, vtk_to_numpy
from vtkmodules.vtkCommonCore import vtkCommand, vtkFloatArray, vtkPoints
from vtkmodules.vtkCommonDataModel import vtkCellArray, vtkPolyData
from vtkmodules.vtkFiltersSources import vtkSphereSource

from perceptual_lod import (vtkMultiscaleOctreeBuilder, vtkMultiscalePatchGenerator,
                            vtkPerceptualLODSelector)


class Messages:
    def __init__(self, *objects):
        self.errors, self.warnings = [], []
        for o in objects:
            o.AddObserver(vtkCommand.ErrorEvent, self.on_error)
            o.AddObserver(vtkCommand.WarningEvent, self.on_warning)

    def on_error(self, caller, event, data=None):
        self.errors.append(str(data))

    def on_warning(self, caller, event, data=None):
        self.warnings.append(str(data))

    on_error.CallDataType = 'string0'
    on_warning.CallDataType = 'string0'

    def said(self, part):
        return any(part in m for m in self.errors + self.warnings)


def sphere(resolution=24):
    s = vtkSphereSource()
    s.SetThetaResolution(resolution)
    s.SetPhiResolution(resolution)
    s.Update()
    pd = vtkPolyData()
    pd.DeepCopy(s.GetOutput())
    pd.GetPointData().SetNormals(None)
    return pd


def mesh(points, triangles):
    pd = vtkPolyData()
    pts = vtkPoints()
    pts.SetDataTypeToDouble()
    for p in points:
        pts.InsertNextPoint(p)
    cells = vtkCellArray()
    for t in triangles:
        cells.InsertNextCell(3, t)
    pd.SetPoints(pts)
    pd.SetPolys(cells)
    return pd


class Pipeline:
    def __init__(self, data, distance=3.0):
        self.data = data  # a pipeline does not keep its input alive from Python
        self.builder = vtkMultiscaleOctreeBuilder()
        self.builder.SetInputData(data)
        self.selector = vtkPerceptualLODSelector()
        self.selector.SetInputConnection(self.builder.GetOutputPort())
        self.patches = vtkMultiscalePatchGenerator()
        self.patches.SetInputConnection(self.selector.GetOutputPort())
        self.messages = Messages(self.builder, self.selector, self.patches)
        b = data.GetBounds()
        size = max(b[1] - b[0], b[3] - b[2], b[5] - b[4], 1e-300)
        if math.isfinite(size):
            self.selector.SetEyePosition((b[0] + b[1]) / 2, (b[2] + b[3]) / 2,
                                         (b[4] + b[5]) / 2 + distance * size)
        self.selector.SetViewportSize(640, 480)

    def run(self):
        self.patches.Update()
        return self.patches.GetOutput()


class TestBadInput(unittest.TestCase):
    def test_long_sliver_does_not_hang(self):
        rng = np.random.default_rng(3)
        points, triangles = [], []
        for _ in range(2000):
            c = rng.uniform(0, 1, 3)
            triangles.append([len(points), len(points) + 1, len(points) + 2])
            points += [c + 1e-4 * rng.uniform(0, 1, 3) for _ in range(3)]
        n = len(points)
        points += [(0, 0, 0), (1, 1, 1), (1, 1, 1.0001)]
        triangles.append([n, n + 1, n + 2])
        for level in (-1, 17, 21):
            p = Pipeline(mesh(points, triangles))
            p.builder.SetFinestLevel(level)
            self.assertGreater(p.run().GetNumberOfPolys(), 0)
            self.assertEqual(p.builder.GetOutput().GetNumberOfSurfaceTriangles(), 2001)

    def test_short_arrays_are_errors_naming_them(self):
        data = sphere()
        short = numpy_to_vtk(np.full(data.GetNumberOfPoints() - 3, 0.5, dtype=np.float32), deep=1)
        short.SetName('Kd')
        data.GetPointData().AddArray(short)
        p = Pipeline(data)
        p.builder.SetDiffuseArrayName('Kd')
        self.assertEqual(p.run().GetNumberOfPolys(), 0)
        self.assertTrue(p.messages.said("array 'Kd'"), p.messages.errors)
        self.assertEqual(p.builder.GetOutput().GetNumberOfNodes(), 0)

    def test_octree_edited_from_numpy(self):
        p = Pipeline(sphere(30))
        self.assertGreater(p.run().GetNumberOfPolys(), 0)
        octree = p.builder.GetOutput()
        for name, index, value in (('FirstChild', 0, 1 << 30), ('Parent', -1, -2),
                                   ('PointCluster', 7, 1 << 30), ('Triangles', 4, -9)):
            data = octree.GetNodeData().GetArray(name) or octree.GetSurfaceData().GetArray(name)
            array = vtk_to_numpy(data).reshape(-1)
            index = index % len(array)
            old = array[index]
            array[index] = value if value >= -1 else (len(array) - 1 if name == 'Parent' else value)
            # numpy writes the VTK array in place; without telling VTK, the filters must still
            # neither crash nor loop (the output is then whatever the bad data gives)
            p.selector.Modified()
            p.run()
            # told, as VTK asks of in-place edits, they refuse the octree with an error
            data.Modified()
            p.selector.Modified()
            p.messages.errors.clear()
            self.assertEqual(p.run().GetNumberOfPolys(), 0, name)
            self.assertTrue(p.messages.said('invalid'), (name, p.messages.errors))
            array[index] = old
            data.Modified()
        p.selector.Modified()
        p.messages.errors.clear()
        self.assertGreater(p.run().GetNumberOfPolys(), 0)
        self.assertEqual(p.messages.errors, [])

    def test_tiny_meshes_draw(self):
        for points, triangles in (([(0, 0, 0), (1, 0, 0), (0, 1, 0)], [[0, 1, 2]]),
                                  ([(1, 1, 1), (1, -1, -1), (-1, 1, -1), (-1, -1, 1)],
                                   [[0, 1, 2], [0, 3, 1], [0, 2, 3], [1, 3, 2]])):
            p = Pipeline(mesh(points, triangles))
            p.selector.HideBackFacesOff()
            self.assertGreater(p.run().GetNumberOfPolys(), 0)
            self.assertGreaterEqual(p.builder.GetOutput().GetFinestLevel(), 1)

    def test_extreme_coordinates(self):
        for scale in (1e-300, 1e300):
            data = sphere(12)
            pts = vtk_to_numpy(data.GetPoints().GetData())
            data.GetPoints().SetData(numpy_to_vtk(pts.astype(np.float64) * scale, deep=1))
            p = Pipeline(data)
            self.assertEqual(p.run().GetNumberOfPolys(), 0)
            self.assertTrue(p.messages.said('single-precision'), p.messages.errors)

    def test_nan_points_skip_their_triangles(self):
        data = sphere()
        pts = vtk_to_numpy(data.GetPoints().GetData())
        pts[5] = np.nan
        data.GetPoints().Modified()
        p = Pipeline(data)
        self.assertGreater(p.run().GetNumberOfPolys(), 0)
        self.assertTrue(p.messages.said('NaN or infinite'), p.messages.warnings)

    def test_root_alone_says_why(self):
        p = Pipeline(sphere())
        p.selector.SetEyePosition(0, 0, 1e300)
        self.assertEqual(p.run().GetNumberOfPolys(), 0)
        self.assertIn('root alone', p.selector.GetEmptyCutReason())

    def test_many_bright_lights(self):
        p = Pipeline(sphere(60))
        p.selector.SetNumberOfLights(1000)
        for i in range(1000):
            p.selector.SetLight(i, False, 0.3, 0.4, 1.0, 1.0, 1.0)
        self.assertGreater(p.run().GetNumberOfPolys(), 0)
        self.assertLess(p.selector.GetSelectTime(), 5.0)

    def test_absurd_parameters(self):
        p = Pipeline(sphere())
        p.selector.SetContourTolerance(float('nan'))
        p.run()
        self.assertTrue(p.messages.said('Invalid input'), p.messages.errors)
        q = Pipeline(sphere())
        q.builder.SetMemoryLimit(-5)
        q.run()
        self.assertEqual(q.builder.GetOutput().GetNumberOfNodes(), 0)


if __name__ == '__main__':
    unittest.main()
