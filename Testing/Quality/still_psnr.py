"""Still-image quality at equal triangle counts (SRCC Fig. 9): PSNR of the LOD image against the
full-resolution image, same view, for SRCC, SCVC and PSEC, at three viewing distances.

    PYTHONPATH=build/lib/python3/dist-packages xvfb-run -a /usr/bin/python3 \
        Testing/Quality/still_psnr.py [--model ../shared/data/bun_zipper.ply] [--size 800 600]

For each distance, SRCC runs at the default tolerances (T_s = 1 px, T_b = 4). SCVC's and PSEC's
contour tolerance is then tuned by bisection so that their triangle count is within 2% of
SRCC's. All images are rendered offscreen in the same window: grey material, one headlight,
800x600 pixels; the full-resolution reference is smooth-shaded (vtkPolyDataNormals, no
splitting) like the LOD. PSNR is computed on 8-bit luminance over the whole image.
"""
import argparse
import math
import sys

import numpy as np
import vtkmodules.vtkRenderingOpenGL2  # noqa: F401
from vtkmodules.util.numpy_support import vtk_to_numpy
from vtkmodules.vtkFiltersCore import vtkPolyDataNormals
from vtkmodules.vtkIOPLY import vtkPLYReader
from vtkmodules.vtkRenderingCore import (vtkActor, vtkLight, vtkPolyDataMapper, vtkRenderer,
                                         vtkRenderWindow, vtkWindowToImageFilter)

from perceptual_lod import (vtkMultiscaleOctreeBuilder, vtkMultiscalePatchGenerator,
                            vtkPerceptualLODSelector)


def psnr(a, b):
    mse = np.mean((a.astype(np.float64) - b.astype(np.float64)) ** 2)
    return float('inf') if mse == 0 else 10 * math.log10(255.0 ** 2 / mse)


class Scene:
    def __init__(self, model, size):
        reader = vtkPLYReader()
        reader.SetFileName(model)
        reader.Update()
        self.reader = reader
        # the reference is smooth-shaded, like the LOD (whose point normals are cone axes)
        normals = vtkPolyDataNormals()
        normals.SetInputConnection(reader.GetOutputPort())
        normals.SplittingOff()
        normals.Update()
        self.full = normals.GetOutput()
        self.builder = vtkMultiscaleOctreeBuilder()
        self.builder.SetInputConnection(reader.GetOutputPort())
        self.builder.SetFinestLevel(8)
        self.selector = vtkPerceptualLODSelector()
        self.selector.SetInputConnection(self.builder.GetOutputPort())
        self.patches = vtkMultiscalePatchGenerator()
        self.patches.SetInputConnection(self.selector.GetOutputPort())
        self.mapper = vtkPolyDataMapper()
        self.actor = vtkActor()
        self.actor.SetMapper(self.mapper)
        prop = self.actor.GetProperty()
        prop.SetColor(0.8, 0.8, 0.8)
        prop.SetDiffuse(0.9)
        prop.SetSpecular(0.3)
        prop.SetSpecularPower(20)
        self.renderer = vtkRenderer()
        self.renderer.AddActor(self.actor)
        self.renderer.SetBackground(0, 0, 0)
        light = vtkLight()
        light.SetLightTypeToHeadlight()
        self.renderer.AddLight(light)
        self.window = vtkRenderWindow()
        self.window.SetOffScreenRendering(1)
        self.window.SetSize(*size)
        self.window.AddRenderer(self.renderer)
        self.size = size
        self.selector.SetViewportSize(*size)
        self.selector.SetDiffuseReflectance(0.9)
        self.selector.SetSpecularReflectance(0.3)
        self.selector.SetSpecularPower(20)

    def look(self, distance):
        b = self.full.GetBounds()
        centre = [(b[0] + b[1]) / 2, (b[2] + b[3]) / 2, (b[4] + b[5]) / 2]
        camera = self.renderer.GetActiveCamera()
        camera.SetFocalPoint(centre)
        camera.SetPosition(centre[0], centre[1], centre[2] + distance)
        camera.SetViewUp(0, 1, 0)
        camera.SetViewAngle(30)
        self.renderer.ResetCameraClippingRange()
        planes = [0.0] * 24
        camera.GetFrustumPlanes(self.size[0] / self.size[1], planes)
        self.selector.SetEyePosition(camera.GetPosition())
        self.selector.SetViewAngle(30)
        self.selector.SetFrustumPlanes(planes)
        # the headlight, as the selector sees it: a directional light from the eye
        d = np.array(camera.GetPosition()) - np.array(centre)
        d /= np.linalg.norm(d)
        self.selector.SetNumberOfLights(1)
        self.selector.SetLight(0, False, *d, 1.0, 1.0)

    def image(self, data):
        self.mapper.SetInputData(data)
        self.window.Render()
        grab = vtkWindowToImageFilter()
        grab.SetInput(self.window)
        grab.Update()
        rgb = vtk_to_numpy(grab.GetOutput().GetPointData().GetScalars()).astype(np.float64)
        return 0.2126 * rgb[:, 0] + 0.7152 * rgb[:, 1] + 0.0722 * rgb[:, 2]

    def lod(self, model, scale):
        getattr(self.selector, 'SetErrorModelTo' + model)()
        self.selector.SetContourTolerance(scale)
        self.selector.SetBrightnessTolerance(4 * scale)
        self.patches.Update()
        out = vtkMultiscalePatchGenerator()  # detach a copy for the mapper
        copy = self.patches.GetOutput().NewInstance()
        copy.DeepCopy(self.patches.GetOutput())
        return copy, self.patches.GetNumberOfTriangles()

    def matched(self, model, target):
        """Contour tolerance giving about `target` triangles (bisection in log scale)."""
        lo, hi = 1e-3, 1e3
        best = None
        for _ in range(40):
            mid = math.sqrt(lo * hi)
            data, count = self.lod(model, mid)
            if best is None or abs(count - target) < abs(best[1] - target):
                best = (data, count, mid)
            if abs(count - target) <= 0.02 * target:
                break
            if count > target:
                lo = mid
            else:
                hi = mid
        return best


def main():
    parser = argparse.ArgumentParser(description=__doc__.split('\n')[0])
    parser.add_argument('--model', default='../shared/data/bun_zipper.ply')
    parser.add_argument('--size', type=int, nargs=2, default=[800, 600])
    parser.add_argument('--distances', type=float, nargs=3, default=[0.25, 0.5, 1.0])
    args = parser.parse_args()
    scene = Scene(args.model, args.size)
    print('| distance | full triangles | method | triangles | tolerance T_s | PSNR (dB) |')
    print('| ---: | ---: | --- | ---: | ---: | ---: |')
    for distance in args.distances:
        scene.look(distance)
        reference = scene.image(scene.full)
        data, target = scene.lod('SRCC', 1.0)
        rows = [('SRCC', data, target, 1.0)]
        for model in ('SCVC', 'PSEC'):
            d, count, tol = scene.matched(model, target)
            rows.append((model, d, count, tol))
        for model, d, count, tol in rows:
            value = psnr(reference, scene.image(d))
            print(f'| {distance} | {scene.full.GetNumberOfPolys()} | {model} | {count} | '
                  f'{tol:.3g} | {value:.2f} |')
        sys.stdout.flush()


if __name__ == '__main__':
    main()
