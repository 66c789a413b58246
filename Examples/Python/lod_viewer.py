"""A VTK pipeline that adapts itself every frame: the perceptual LOD bound to a renderer.

    PYTHONPATH=build/lib/python3/dist-packages /usr/bin/python3 Examples/Python/lod_viewer.py \
        [model.ply] [--offscreen]

Interactive: rotate with the mouse; keys 1 SRCC, 2 SRCC+TMM, 3 SCVC, 4 PSEC, 0 full resolution.
With --offscreen (run it under `xvfb-run -a`), it orbits for 60 frames and prints the figures.
"""
import sys

import vtkmodules.vtkInteractionStyle  # noqa: F401
import vtkmodules.vtkRenderingOpenGL2  # noqa: F401
from vtkmodules.vtkFiltersSources import vtkSphereSource
from vtkmodules.vtkIOPLY import vtkPLYReader
from vtkmodules.vtkRenderingCore import (vtkActor, vtkPolyDataMapper, vtkRenderer,
                                         vtkRenderWindow, vtkRenderWindowInteractor)

from perceptual_lod import (vtkMultiscaleOctreeBuilder, vtkMultiscalePatchGenerator,
                            vtkPerceptualLODRenderBinding, vtkPerceptualLODSelector)

from model_files import checked  # beside this script

args = [checked(a) for a in sys.argv[1:] if not a.startswith('--')]
offscreen = '--offscreen' in sys.argv
if args:
    source = vtkPLYReader()
    source.SetFileName(args[0])
else:
    source = vtkSphereSource()
    source.SetThetaResolution(400)
    source.SetPhiResolution(400)

# the pipeline: built once, selected and patched every frame
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
window.AddRenderer(renderer)
window.SetSize(800, 600)

# the binding feeds the camera, lights, material and motion to the selector on every render
binding = vtkPerceptualLODRenderBinding()
binding.SetRenderer(renderer)
binding.SetSelector(selector)
binding.SetProp3D(actor)


def report(frame):
    print(f'frame {frame:3d}: {patches.GetNumberOfTriangles():7d} triangles, '
          f'select {selector.GetSelectTime() * 1e3:5.2f} ms, '
          f'patch {patches.GetGenerateTime() * 1e3:5.2f} ms')


# Reset the camera with the model's bounds: the LOD output only holds what the current view
# draws, so its bounds change with the view.
source.Update()
renderer.ResetCamera(source.GetOutput().GetBounds())
if offscreen:
    window.SetOffScreenRendering(1)
    for frame in range(60):
        renderer.GetActiveCamera().Azimuth(3)
        renderer.ResetCameraClippingRange(source.GetOutput().GetBounds())
        window.Render()
        if frame % 10 == 0:
            report(frame)
else:
    modes = {'1': ('SRCC', 'None'), '2': ('SRCC', 'MicroMotion'), '3': ('SCVC', 'None'),
             '4': ('PSEC', 'None')}

    def on_key(interactor, event):
        key = interactor.GetKeySym()
        if key in modes:
            getattr(selector, 'SetErrorModelTo' + modes[key][0])()
            getattr(selector, 'SetMotionModelTo' + modes[key][1])()
            mapper.SetInputConnection(patches.GetOutputPort())
        elif key == '0':
            mapper.SetInputConnection(source.GetOutputPort())
        window.Render()
        report(0)

    interactor = vtkRenderWindowInteractor()
    interactor.SetRenderWindow(window)
    interactor.GetInteractorStyle().SetCurrentStyleToTrackballCamera()
    interactor.AddObserver('KeyPressEvent', on_key)
    window.Render()
    interactor.Start()
