"""The perceptual LOD as one actor: the whole pipeline is vtkPerceptualLODActor.

    PYTHONPATH=build/lib/python3/dist-packages /usr/bin/python3 Examples/Python/lod_actor.py \
        [model.ply | octree.plod] [--offscreen]

Interactive: rotate with the mouse; the actor selects its cut again for every view. With
--offscreen (run it under `xvfb-run -a`), it orbits for 30 frames and prints the triangles drawn.
"""
import sys

import vtkmodules.vtkInteractionStyle  # noqa: F401
import vtkmodules.vtkRenderingOpenGL2  # noqa: F401
from vtkmodules.vtkFiltersSources import vtkSphereSource
from vtkmodules.vtkIOPLY import vtkPLYReader
from vtkmodules.vtkRenderingCore import vtkRenderer, vtkRenderWindow, vtkRenderWindowInteractor

from perceptual_lod import vtkMultiscaleOctreeReader, vtkPerceptualLODActor, vtkPLYFileCheck

from model_files import checked  # beside this script

args = [checked(a) for a in sys.argv[1:] if not a.startswith('--')]
if args and vtkMultiscaleOctreeReader.CanReadFile(args[0]):
    source = vtkMultiscaleOctreeReader()  # a saved octree: nothing to build
    source.SetFileName(args[0])
elif args:
    source = vtkPLYReader()
    source.SetFileName(args[0])
else:
    source = vtkSphereSource()
    source.SetThetaResolution(300)
    source.SetPhiResolution(300)

actor = vtkPerceptualLODActor()
actor.SetInputConnection(source.GetOutputPort())
actor.GetProperty().SetSpecular(0.3)
actor.GetProperty().SetSpecularPower(20)
actor.GetSelector().SetContourTolerance(1.0)  # the selector's modes and tolerances

renderer = vtkRenderer()
renderer.AddActor(actor)
renderer.ResetCamera()  # the actor's bounds are the whole model's
window = vtkRenderWindow()
window.AddRenderer(renderer)
window.SetSize(640, 480)

if '--offscreen' in sys.argv:
    window.SetOffScreenRendering(1)
    for frame in range(30):
        renderer.GetActiveCamera().Azimuth(6)
        renderer.ResetCameraClippingRange()
        window.Render()
        print(f'frame {frame:2d}: {actor.GetPatchGenerator().GetNumberOfTriangles()} triangles '
              f'(select {actor.GetSelector().GetSelectTime() * 1e3:.2f} ms)')
else:
    interactor = vtkRenderWindowInteractor()
    interactor.SetRenderWindow(window)
    window.Render()
    interactor.Start()
