"""The perceptual LOD as one actor: the whole pipeline is vtkPerceptualLODActor.

    PYTHONPATH=build/lib/python3/dist-packages /usr/bin/python3 Examples/Python/lod_actor.py \
        [model.ply | octree.plod] [--offscreen] [--cache-limit MiB] [--background-loading]

Interactive: rotate with the mouse; the actor selects its cut again for every view. With
--offscreen (run it under `xvfb-run -a`), it orbits for 30 frames and prints the triangles drawn.
An octree file is mapped: --cache-limit bounds how much of it stays resident between frames,
and with --background-loading its pages are read by a thread of their own, off the frame: a part
of the model whose pages are not read yet is drawn coarser for a few frames (the actor asks the
interactor for the renders that refine it).
"""
import sys

import vtkmodules.vtkInteractionStyle  # noqa: F401
import vtkmodules.vtkRenderingOpenGL2  # noqa: F401
from vtkmodules.vtkFiltersSources import vtkSphereSource
from vtkmodules.vtkIOPLY import vtkPLYReader
from vtkmodules.vtkRenderingCore import vtkRenderer, vtkRenderWindow, vtkRenderWindowInteractor

from perceptual_lod import vtkMultiscaleOctreeReader, vtkPerceptualLODActor, vtkPLYFileCheck

from model_files import checked  # beside this script

options = sys.argv[1:]
cache_limit = None
if '--cache-limit' in options:
    at = options.index('--cache-limit')
    cache_limit = int(options[at + 1])
    del options[at:at + 2]
background = '--background-loading' in options
args = [checked(a) for a in options if not a.startswith('--')]
if args and vtkMultiscaleOctreeReader.CanReadFile(args[0]):
    source = vtkMultiscaleOctreeReader()  # a saved octree: nothing to build
    source.SetFileName(args[0])
    if cache_limit is not None:
        source.SetCacheLimit(cache_limit)  # MiB of the mapped file kept between frames
    source.SetBackgroundLoading(background)  # pages read off the frame
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
    if isinstance(source, vtkMultiscaleOctreeReader) and source.GetMapped():
        octree = source.GetOutput()
        print(f'mapped octree: cache limit {source.GetCacheLimit()} MiB, '
              f'{octree.GetMappedResidentBytes() / 2 ** 20:.1f} MiB resident, '
              f'dropped {octree.GetNumberOfResidentReleases()} times')
        if source.GetBackgroundLoading():
            print(f'background loading: {octree.GetNumberOfBackgroundLoads()} refinements read '
                  f'by the thread, {octree.GetNumberOfWaitingLoads()} waiting')
else:
    interactor = vtkRenderWindowInteractor()
    interactor.SetRenderWindow(window)
    window.Render()
    interactor.Start()
