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


if __name__ == '__main__':
    unittest.main()
