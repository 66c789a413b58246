"""Python tests of vtkPerceptualLODSelector: the mode names, a camera's numbers, figures of the
last execution, and the cut arrays as numpy arrays."""
import unittest

import numpy as np
from vtkmodules.util.numpy_support import vtk_to_numpy
from vtkmodules.vtkFiltersSources import vtkSphereSource
from vtkmodules.vtkRenderingCore import vtkCamera

from perceptual_lod import (vtkMultiscaleOctreeBuilder, vtkMultiscalePatchGenerator,
                            vtkPerceptualLODSelector)


class TestSelector(unittest.TestCase):
    def setUp(self):
        self.source = vtkSphereSource()
        self.source.SetThetaResolution(120)
        self.source.SetPhiResolution(120)
        self.builder = vtkMultiscaleOctreeBuilder()
        self.builder.SetInputConnection(self.source.GetOutputPort())
        self.builder.SetFinestLevel(7)
        self.selector = vtkPerceptualLODSelector()
        self.selector.SetInputConnection(self.builder.GetOutputPort())
        self.patches = vtkMultiscalePatchGenerator()
        self.patches.SetInputConnection(self.selector.GetOutputPort())

    def look(self, distance, selector=None):
        selector = selector or self.selector
        camera = vtkCamera()
        camera.SetPosition(0, 0, distance)
        camera.SetFocalPoint(0, 0, 0)
        planes = [0.0] * 24
        camera.GetFrustumPlanes(16 / 9, planes)
        selector.SetEyePosition(camera.GetPosition())
        selector.SetViewAngle(camera.GetViewAngle())
        selector.SetFrustumPlanes(planes)

    def test_modes_by_name(self):
        s = self.selector
        for name, value in [('SRCC', s.ERROR_SRCC), ('SCVC', s.ERROR_SCVC),
                            ('PSEC', s.ERROR_PSEC), ('Distance', s.ERROR_DISTANCE)]:
            getattr(s, 'SetErrorModelTo' + name)()
            self.assertEqual(s.GetErrorModel(), value)
        for name, value in [('None', s.MOTION_NONE), ('MicroMotion', s.MOTION_MICRO),
                            ('InverseVelocity', s.MOTION_INVERSE_VELOCITY),
                            ('DirectVelocity', s.MOTION_DIRECT_VELOCITY)]:
            getattr(s, 'SetMotionModelTo' + name)()
            self.assertEqual(s.GetMotionModel(), value)
        s.SetContourTolerance(0.5)
        s.SetBrightnessTolerance(2.0)
        s.SetFrameInterval(1 / 120)
        self.assertAlmostEqual(s.GetFrameInterval(), 1 / 120)

    def test_selection_and_figures(self):
        self.selector.AddLight(False, 0.3, 0.4, 1.0, 0.9, 0.4)
        counts = []
        for distance in (1.5, 3, 6, 12):
            self.look(distance)
            self.patches.Update()
            cut = self.selector.GetOutput()
            self.assertTrue(cut.HasValidCut())
            state = vtk_to_numpy(cut.GetNodeData().GetArray('CutState'))
            reason = vtk_to_numpy(cut.GetNodeData().GetArray('CutReason'))
            self.assertEqual(int((state == 1).sum()), self.selector.GetNumberOfDrawnNodes())
            self.assertEqual(int((state > 0).sum()), self.selector.GetNumberOfCutNodes())
            self.assertTrue(np.all((reason > 0) == (state > 0)))
            self.assertGreater(self.selector.GetNumberOfVisitedNodes(),
                               self.selector.GetNumberOfCutNodes() - 1)
            counts.append(self.patches.GetNumberOfTriangles())
        self.assertEqual(counts, sorted(counts, reverse=True))  # farther, fewer triangles

    def test_triangle_budget(self):
        self.selector.AddLight(False, 0.3, 0.4, 1.0, 0.9, 0.4)
        self.look(3)
        self.patches.Update()
        full = self.selector.GetNumberOfBudgetTriangles()
        self.assertFalse(self.selector.GetBudgetWasBinding())
        self.assertGreater(full, 100)
        self.selector.SetTriangleBudget(-1)  # off
        self.assertEqual(self.selector.GetTriangleBudget(), 0)
        budget = full // 4
        self.selector.SetTriangleBudget(budget)
        self.patches.Update()
        self.assertTrue(self.selector.GetBudgetWasBinding())
        self.assertLessEqual(self.selector.GetNumberOfBudgetTriangles(), budget)
        self.assertLessEqual(self.patches.GetNumberOfTriangles(), budget)
        reason = vtk_to_numpy(self.selector.GetOutput().GetNodeData().GetArray('CutReason'))
        self.assertGreater(int((reason == 8).sum()), 0)  # left unrefined by the budget
        # the stop rule is wrapped: skipping misfits (the default) fills at least as much
        self.assertEqual(self.selector.GetBudgetStopRule(), self.selector.BUDGET_SKIP_MISFITS)
        skip = self.selector.GetNumberOfBudgetTriangles()
        self.selector.SetBudgetStopRuleToStopAtFirstMisfit()
        self.patches.Update()
        self.assertEqual(self.selector.GetBudgetStopRule(), self.selector.BUDGET_STOP_AT_FIRST_MISFIT)
        self.assertLessEqual(self.selector.GetNumberOfBudgetTriangles(), skip)
        self.assertLessEqual(self.selector.GetNumberOfBudgetTriangles(), budget)
        self.assertLessEqual(self.patches.GetNumberOfTriangles(), budget)

    def test_budget_walk_figures(self):
        # a budget the tolerance cut fits keeps that cut; one that binds runs the queue walk,
        # and the next binding frame judges cells ahead on every core (MultiThreaded, the
        # default): the same cut as one thread gives
        self.selector.AddLight(False, 0.3, 0.4, 1.0, 0.9, 0.4)
        self.look(3)
        self.selector.SetTriangleBudget(10 ** 9)
        self.selector.Update()
        self.assertTrue(self.selector.GetBudgetKeptToleranceCut())
        self.assertEqual(self.selector.GetNumberOfCellsJudgedAhead(), 0)
        budget = self.selector.GetNumberOfBudgetTriangles() // 4
        self.selector.SetTriangleBudget(budget)
        self.selector.Update()
        self.assertTrue(self.selector.GetBudgetWasBinding())
        self.assertFalse(self.selector.GetBudgetKeptToleranceCut())
        self.assertEqual(self.selector.GetNumberOfCellsJudgedAhead(), 0)
        self.look(3.1)
        self.selector.Update()
        self.assertGreater(self.selector.GetNumberOfCellsJudgedAhead(), 0)
        self.assertLessEqual(self.selector.GetNumberOfCellsJudgedAhead(),
                             self.selector.GetNumberOfVisitedNodes())
        state = vtk_to_numpy(self.selector.GetOutput().GetNodeData().GetArray('CutState')).copy()
        serial = vtkPerceptualLODSelector()
        serial.SetInputConnection(self.builder.GetOutputPort())
        serial.MultiThreadedOff()
        serial.AddLight(False, 0.3, 0.4, 1.0, 0.9, 0.4)
        self.look(3.1, serial)
        serial.SetTriangleBudget(budget)
        serial.Update()
        self.assertEqual(serial.GetNumberOfCellsJudgedAhead(), 0)
        self.assertTrue(np.array_equal(
            state, vtk_to_numpy(serial.GetOutput().GetNodeData().GetArray('CutState'))))

    def test_foveation_factors(self):
        # screen foveation bounds its factor from a table: few cells compute it, and none
        # without foveation; a budget that does not bind keeps the tolerance walk's cut, table
        # and all (the queue walk, which computes every factor, gives the same cut: the C++
        # test ScreenFoveationTableGivesTheExactCut)
        self.selector.AddLight(False, 0.3, 0.4, 1.0, 0.9, 0.4)
        self.look(3)
        self.selector.SetGazeDirection(0.1, 0, -1)
        self.patches.Update()
        self.assertEqual(self.selector.GetNumberOfFoveationFactors(), 0)
        self.selector.SetFoveationModeToScreen()
        self.selector.SetFoveationRate(3)
        self.patches.Update()
        visited = self.selector.GetNumberOfVisitedNodes()
        fast = self.selector.GetNumberOfFoveationFactors()
        self.assertLess(fast * 20, visited)
        cut = self.selector.GetOutput()
        state = vtk_to_numpy(cut.GetNodeData().GetArray('CutState')).copy()
        self.selector.SetTriangleBudget(10 ** 9)  # a budget that does not bind
        self.patches.Update()
        self.assertFalse(self.selector.GetBudgetWasBinding())
        self.assertEqual(self.selector.GetNumberOfVisitedNodes(), visited)
        self.assertEqual(self.selector.GetNumberOfFoveationFactors(), fast)
        exact = vtk_to_numpy(self.selector.GetOutput().GetNodeData().GetArray('CutState'))
        self.assertTrue(np.array_equal(state, exact))


if __name__ == '__main__':
    unittest.main()
