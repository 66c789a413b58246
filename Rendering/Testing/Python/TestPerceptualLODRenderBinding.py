"""Python test of vtkPerceptualLODRenderBinding (run under xvfb-run -a): a pipeline bound to a
renderer re-executes while the camera moves and not when it stands still."""
import unittest

import vtkmodules.vtkRenderingOpenGL2  # noqa: F401
from vtkmodules.vtkCommonCore import vtkCommand
from vtkmodules.vtkFiltersSources import vtkSphereSource
from vtkmodules.vtkRenderingCore import vtkActor, vtkPolyDataMapper, vtkRenderer, vtkRenderWindow

from perceptual_lod import (vtkMultiscaleOctreeBuilder, vtkMultiscalePatchGenerator,
                            vtkPerceptualLODRenderBinding, vtkPerceptualLODSelector)


class TestBinding(unittest.TestCase):
    def test_frames(self):
        source = vtkSphereSource()
        source.SetThetaResolution(100)
        source.SetPhiResolution(100)
        builder = vtkMultiscaleOctreeBuilder()
        builder.SetInputConnection(source.GetOutputPort())
        selector = vtkPerceptualLODSelector()
        selector.SetInputConnection(builder.GetOutputPort())
        patches = vtkMultiscalePatchGenerator()
        patches.SetInputConnection(selector.GetOutputPort())
        mapper = vtkPolyDataMapper()
        mapper.SetInputConnection(patches.GetOutputPort())
        actor = vtkActor()
        actor.SetMapper(mapper)
        renderer = vtkRenderer()
        renderer.AddActor(actor)
        window = vtkRenderWindow()
        window.SetOffScreenRendering(1)
        window.SetSize(300, 200)
        window.AddRenderer(renderer)
        binding = vtkPerceptualLODRenderBinding()
        binding.SetRenderer(renderer)
        binding.SetSelector(selector)
        binding.SetProp3D(actor)
        runs = {'builder': 0, 'selector': 0}
        builder.AddObserver(vtkCommand.EndEvent, lambda *a: runs.__setitem__('builder', runs['builder'] + 1))
        selector.AddObserver(vtkCommand.EndEvent, lambda *a: runs.__setitem__('selector', runs['selector'] + 1))
        source.Update()
        renderer.ResetCamera(source.GetOutput().GetBounds())  # the model's, not the LOD's
        for _ in range(10):
            renderer.GetActiveCamera().Azimuth(5)
            window.Render()
        self.assertEqual(runs, {'builder': 1, 'selector': 10})
        self.assertGreater(patches.GetNumberOfTriangles(), 0)
        for _ in range(5):
            window.Render()
        self.assertEqual(runs['selector'], 10)
        self.assertEqual(binding.GetNumberOfUpdates(), 15)
        del binding
        self.assertFalse(renderer.HasObserver(vtkCommand.StartEvent))

    def test_simulated_time(self):
        """A script's own clock: the frame time the motion models read is the simulated one,
        whatever the wall clock did between the pushes; the wall clock comes back after."""
        source = vtkSphereSource()
        builder = vtkMultiscaleOctreeBuilder()
        builder.SetInputConnection(source.GetOutputPort())
        selector = vtkPerceptualLODSelector()
        selector.SetInputConnection(builder.GetOutputPort())
        selector.SetMotionModelToMicroMotion()
        actor = vtkActor()
        renderer = vtkRenderer()
        window = vtkRenderWindow()
        window.SetOffScreenRendering(1)
        window.SetSize(300, 200)
        window.AddRenderer(renderer)
        binding = vtkPerceptualLODRenderBinding()
        binding.EnabledOff()  # pushed by hand below
        binding.SetSelector(selector)
        source.Update()
        renderer.ResetCamera(source.GetOutput().GetBounds())
        for t, seconds in ((0, 10.0), (1, 10.04), (2, 10.065)):
            binding.SetSimulatedTime(seconds)
            actor.SetPosition(0.01 * t, 0, 0)  # the object moves: the frame time is pushed
            binding.UpdateFrom(renderer, actor)
        self.assertAlmostEqual(selector.GetPreviousFrameTime(), 0.025, places=12)
        self.assertAlmostEqual(binding.GetMeasuredFrameTime(), 0.025, places=12)
        binding.UseWallClock()
        actor.SetPosition(0.05, 0, 0)
        binding.UpdateFrom(renderer, actor)
        # from the simulated 10.065 s to the wall clock's seconds since 1970
        self.assertGreater(selector.GetPreviousFrameTime(), 1e9)


if __name__ == '__main__':
    unittest.main()
