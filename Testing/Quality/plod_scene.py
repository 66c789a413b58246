"""The measurement harness's one scene: a model, its octree and LOD pipeline bound to a
renderer as in a user's pipeline, its smooth-shaded full-resolution reference, and an offscreen
window; with the models and the static baselines the harness's scripts share.

Used by plod_faithful.py, plod_measure.py, plod_budget.py, plod_srcc.py and plod_tmm.py (each
script's docstring gives its protocol). The facts they share live here once:
- the material: colour 0.8 grey, diffuse 0.9, specular 0.3, power 20 (GREY);
- the light: one headlight (a vtkLight of type headlight, as the renderer would make itself);
- the reference shading: smooth point normals from vtkPolyDataNormals without splitting, like
  the LOD's cone normals (smooth);
- the LOD pipeline: builder -> selector -> patch generator -> vtkPolyDataMapper, the selector
  fed by vtkPerceptualLODRenderBinding from the renderer (camera, frustum, viewport, the
  headlight, the actor's matrix and material), on a simulated clock that only the moving
  protocols advance (Scene.at);
- the static baseline: vtkQuadricDecimation of the full mesh, once, to a triangle count
  (decimated).
"""
import math
import time

import numpy as np
import vtkmodules.vtkRenderingOpenGL2  # noqa: F401
from vtkmodules.util.numpy_support import vtk_to_numpy
from vtkmodules.vtkCommonDataModel import vtkPolyData
from vtkmodules.vtkFiltersCore import vtkPolyDataNormals, vtkQuadricDecimation, vtkTriangleFilter
from vtkmodules.vtkFiltersSources import vtkSphereSource
from vtkmodules.vtkIOPLY import vtkPLYReader
from vtkmodules.vtkRenderingCore import (vtkActor, vtkLight, vtkPolyDataMapper, vtkRenderer,
                                         vtkRenderWindow, vtkRenderWindowInteractor,
                                         vtkWindowToImageFilter)

import plod_metrics as metrics
from perceptual_lod import (vtkMultiscaleOctreeBuilder, vtkMultiscaleOctreeCutter,
                            vtkMultiscalePatchGenerator, vtkPerceptualLODMapper,
                            vtkPerceptualLODRenderBinding, vtkPerceptualLODSelector,
                            vtkPLYFileCheck)

GREY = dict(color=(0.8, 0.8, 0.8), diffuse=0.9, specular=0.3, power=20)
BLUE = (0.0, 0.0, 1.0)  # a background no lit grey pixel can have (plod_faithful's holes)
VIEW_ANGLE = 30.0


# ---- models -----------------------------------------------------------------------------------

def output_copy(algorithm):
    """Runs `algorithm` and returns a deep copy of its polydata output (which the next run
    would overwrite)."""
    algorithm.Update()
    pd = vtkPolyData()
    pd.DeepCopy(algorithm.GetOutput())
    return pd


def read_ply(path, triangles=False):
    """The PLY file as vtkPolyData (as triangles with `triangles`). vtkPLYFileCheck reads it
    first: a corrupt file (cut short, counts that lie, indices out of range, ...) raises
    ValueError saying what is wrong and where, instead of crashing vtkPLYReader; so does a file
    without points."""
    check = vtkPLYFileCheck()
    check.SetFileName(path)
    if not check.Check():
        raise ValueError(f'{path}: {check.GetErrorMessage()}')
    reader = vtkPLYReader()
    reader.SetFileName(path)
    reader.Update()
    if reader.GetOutput().GetNumberOfPoints() == 0:
        raise ValueError(f'{path}: no points')
    if not triangles:
        return output_copy(reader)
    tri = vtkTriangleFilter()
    tri.SetInputConnection(reader.GetOutputPort())
    return output_copy(tri)


def generated_model(resolution, noise=0.25, seed=11):
    """A closed detailed model: a UV sphere displaced by random waves (as plodtest::MakeBlob)."""
    sphere = vtkSphereSource()
    sphere.SetThetaResolution(resolution)
    sphere.SetPhiResolution(resolution)
    pd = output_copy(sphere)
    rng = np.random.default_rng(seed)
    waves = rng.uniform(-1, 1, size=(8, 4))
    pts = vtk_to_numpy(pd.GetPoints().GetData())
    x = pts / np.linalg.norm(pts, axis=1)[:, None]
    r = np.ones(len(x))
    for k, w in enumerate(waves):
        r += noise / 8 * np.sin((1 + 2 * k) * (x @ w[:3]) + 3 * w[3])
    pts[:] = x * r[:, None]
    pd.GetPoints().Modified()
    pd.GetPointData().SetNormals(None)  # the source's normals are the undisplaced sphere's
    return pd


def smooth(data):
    """A copy of `data` with smooth point normals (no splitting), like the LOD's cone normals."""
    normals = vtkPolyDataNormals()
    normals.SetInputData(data)
    normals.SplittingOff()
    return output_copy(normals)


def decimated(full, target):
    """vtkQuadricDecimation of `full` to about `target` triangles, done once (the static LOD a
    VTK user would make instead), smooth-shaded: (mesh, its triangles, milliseconds taken)."""
    dec = vtkQuadricDecimation()
    dec.SetInputData(full)
    dec.SetTargetReduction(max(0.0, min(0.9999, 1.0 - target / full.GetNumberOfPolys())))
    t0 = time.perf_counter()
    dec.Update()
    ms = (time.perf_counter() - t0) * 1e3
    return smooth(dec.GetOutput()), dec.GetOutput().GetNumberOfPolys(), ms


# ---- the scene --------------------------------------------------------------------------------

def set_material(actor, diffuse=GREY['diffuse'], specular=GREY['specular'], power=GREY['power'],
                 color=GREY['color']):
    prop = actor.GetProperty()
    prop.SetColor(*color)
    prop.SetDiffuse(diffuse)
    prop.SetSpecular(specular)
    prop.SetSpecularPower(power)


def grey_actor(mapper):
    """An actor of `mapper` with the harness's material (GREY)."""
    actor = vtkActor()
    actor.SetMapper(mapper)
    set_material(actor)
    return actor


class Scene:
    """One model: its octree, the LOD pipeline bound to a renderer, the full-resolution
    reference, an offscreen window of `size` with one headlight.

    `level`: the octree's finest level (-1: automatic); `rule`: the vertex rule ('mean', 'qef'
    or None for the builder's default); `cloud`: the model is a point cloud with a
    'ScannerPosition' array (its reference is then the finest cut of its own octree);
    `background`: the renderer's background colour (None: VTK's black).

    Four actors: `lod_actor` draws the live pipeline's patches (render_cut, render_lod: the CPU
    path), `gpu_actor` the same selection through vtkPerceptualLODMapper (render_lod_gpu: the GPU
    path, made on first use), `ref_actor` the reference, and `actor` whatever polydata render()
    is given (the moving protocols place it with set_view's offset and angle, and the binding
    reads its matrix).
    """

    def __init__(self, model, name='', size=(640, 480), level=-1, rule=None, cloud=False,
                 background=None):
        self.name = name
        self.model = model
        self.size = size
        self.builder = vtkMultiscaleOctreeBuilder()
        self.builder.SetInputData(model)
        self.builder.SetFinestLevel(level)
        if rule == 'mean':
            self.builder.SetVertexRuleToMean()
        elif rule == 'qef':
            self.builder.SetVertexRuleToQEF()
        if cloud:
            self.builder.SetViewpointArrayName('ScannerPosition')
        t0 = time.perf_counter()
        self.builder.Update()
        self.build_s = time.perf_counter() - t0
        self.octree = self.builder.GetOutput()
        self.selector = vtkPerceptualLODSelector()
        self.selector.SetInputConnection(self.builder.GetOutputPort())
        if cloud:
            self.selector.HideBackFacesOff()
        self.patches = vtkMultiscalePatchGenerator()
        self.patches.SetInputConnection(self.selector.GetOutputPort())
        self.full = self._reference(model, cloud)
        b = self.full.GetBounds()
        self.bounds = b
        self.centre = np.array([(b[0] + b[1]) / 2, (b[2] + b[3]) / 2, (b[4] + b[5]) / 2])
        self.radius = 0.5 * math.sqrt((b[1] - b[0]) ** 2 + (b[3] - b[2]) ** 2 + (b[5] - b[4]) ** 2)

        self.lod_mapper = vtkPolyDataMapper()
        self.lod_mapper.SetInputConnection(self.patches.GetOutputPort())
        self.lod_actor = grey_actor(self.lod_mapper)
        self.ref_mapper = vtkPolyDataMapper()
        self.ref_mapper.SetInputData(self.full)
        self.ref_actor = grey_actor(self.ref_mapper)
        self.mapper = vtkPolyDataMapper()
        self.actor = grey_actor(self.mapper)
        self.gpu_mapper = None
        self.gpu_actor = None

        self.renderer = vtkRenderer()
        if background is not None:
            self.renderer.SetBackground(*background)
        self.renderer.AddActor(self.actor)
        light = vtkLight()
        light.SetLightTypeToHeadlight()
        self.renderer.AddLight(light)
        self.window = vtkRenderWindow()
        self.window.SetOffScreenRendering(1)
        self.window.SetSize(*size)
        self.window.AddRenderer(self.renderer)
        # VTK 9.1's vtkQuadricLODActor dereferences the window's interactor without a check and
        # crashes offscreen without one: attach one, never started
        self.interactor = vtkRenderWindowInteractor()
        self.interactor.SetRenderWindow(self.window)
        self.view_angle = VIEW_ANGLE

        # view, lights and material reach the selector through the render binding, as in a
        # user's pipeline; its clock is simulated (see at())
        self.binding = vtkPerceptualLODRenderBinding()
        self.binding.SetRenderer(self.renderer)
        self.binding.SetSelector(self.selector)
        self.binding.SetProp3D(self.lod_actor)
        self.binding.EnabledOff()
        self.clock_last = 0.0
        self.clock_zero = 0.0
        self.binding.SetSimulatedTime(0.0)

    def _reference(self, model, cloud):
        if not cloud:
            return smooth(model)
        # a point cloud has no mesh: its reference is the finest cut of its own octree
        cutter = vtkMultiscaleOctreeCutter()
        cutter.SetInputConnection(self.builder.GetOutputPort())
        finest = vtkMultiscalePatchGenerator()
        finest.SetInputConnection(cutter.GetOutputPort())
        return output_copy(finest)

    # ---- views: the camera reset to the bounds (still protocols), or the eye on +z (moving) ----

    def reset_view(self, azimuth, dolly):
        """The camera reset to the model's bounds (vtkRenderer::ResetCamera), turned by
        `azimuth` degrees and dollied by `dolly` (0.25: four times as far, 3: a third)."""
        camera = self.renderer.GetActiveCamera()
        camera.SetPosition(0, 0, 1)
        camera.SetFocalPoint(0, 0, 0)
        camera.SetViewUp(0, 1, 0)
        camera.SetViewAngle(self.view_angle)
        self.renderer.ResetCamera(self.bounds)
        camera.Azimuth(azimuth)
        camera.Dolly(dolly)
        self.renderer.ResetCameraClippingRange(self.bounds)

    def set_view(self, distance, offset=(0, 0, 0), angle=0.0):
        """The eye on +z of the centre at `distance`, `actor` moved by `offset` and turned by
        `angle` degrees about the vertical axis (the object's motion, in world coordinates); the
        binding reads the view and `actor`'s matrix and material at once."""
        self.actor.SetOrigin(*self.centre)
        self.actor.SetOrientation(0, angle, 0)
        self.actor.SetPosition(*offset)
        camera = self.renderer.GetActiveCamera()
        camera.SetFocalPoint(*self.centre)
        camera.SetPosition(self.centre[0], self.centre[1], self.centre[2] + distance)
        camera.SetViewUp(0, 1, 0)
        camera.SetViewAngle(self.view_angle)
        self.renderer.ResetCameraClippingRange(self.bounds_moved(offset))
        self.binding.UpdateFrom(self.renderer, self.actor)

    def bounds_moved(self, offset):
        r = self.radius
        c = self.centre + np.array(offset)
        return [c[0] - r, c[0] + r, c[1] - r, c[1] + r, c[2] - r, c[2] + r]

    # The binding's clock is simulated (SetSimulatedTime): the moving protocols set the time of
    # each frame, so that the binding measures the motion and the frame times on their schedule.
    # Between them it stands still (the still protocols have no motion model).
    def start_clock(self):
        """A new schedule: at() counts from a second after the last time set (the binding must
        never see time run back: a negative frame time is an error)."""
        self.clock_zero = self.clock_last + 1.0

    def at(self, seconds):
        """The time of the next frame: `seconds` after start_clock()."""
        t = self.clock_zero + seconds
        self.clock_last = max(self.clock_last, t)
        self.binding.SetSimulatedTime(t)

    # ---- images ---------------------------------------------------------------------------------

    def read_image(self):
        """The window's RGB image as last rendered (rows bottom to top, as VTK reads them)."""
        grab = vtkWindowToImageFilter()
        grab.SetInput(self.window)
        grab.ReadFrontBufferOff()
        grab.Update()
        img = vtk_to_numpy(grab.GetOutput().GetPointData().GetScalars())
        return img.reshape(self.size[1], self.size[0], -1)[..., :3].copy()

    def grab(self):
        """Renders the window; its RGB image."""
        self.window.Render()
        return self.read_image()

    def render_actor(self, actor):
        """The RGB image of `actor` alone."""
        self.renderer.RemoveAllViewProps()
        self.renderer.AddActor(actor)
        return self.grab()

    def render_data(self, data):
        """The RGB image of polydata `data` alone, in the harness's material."""
        mapper = vtkPolyDataMapper()
        mapper.SetInputData(data)
        return self.render_actor(grey_actor(mapper))

    def render_cut(self):
        """The live LOD with the selector as set, the binding feeding it from this view: (RGB
        image, triangles drawn)."""
        self.renderer.RemoveAllViewProps()
        self.renderer.AddActor(self.lod_actor)
        self.binding.EnabledOn()
        img = self.grab()
        self.binding.EnabledOff()
        return img, self.patches.GetNumberOfTriangles()

    def render_lod(self, scale=1.0):
        """render_cut with the tolerances at `scale` times their defaults."""
        self.selector.ScaleTolerances(scale)
        return self.render_cut()

    def render_lod_gpu(self, scale=1.0):
        """render_lod through the GPU path (vtkPerceptualLODMapper fed by the same selector):
        (RGB image, triangles the mapper drew). Raises RuntimeError, naming the missing feature,
        when the context cannot run it."""
        if self.gpu_actor is None:
            self.gpu_mapper = vtkPerceptualLODMapper()
            self.gpu_mapper.SetOctreeConnection(self.selector.GetOutputPort())
            self.gpu_actor = vtkActor()
            self.gpu_actor.SetMapper(self.gpu_mapper)
            self.gpu_actor.SetProperty(self.lod_actor.GetProperty())  # one material for both paths
        self.selector.ScaleTolerances(scale)
        self.renderer.RemoveAllViewProps()
        self.renderer.AddActor(self.gpu_actor)
        self.binding.SetProp3D(self.gpu_actor)
        self.binding.EnabledOn()
        img = self.grab()
        self.binding.EnabledOff()
        self.binding.SetProp3D(self.lod_actor)
        if not self.gpu_mapper.IsSupported(self.window):
            raise RuntimeError('the GPU path cannot run here: ' +
                               self.gpu_mapper.GetUnsupportedReason())
        return img, self.gpu_mapper.GetNumberOfDrawnTriangles()

    def lod(self):
        """Select and patch; returns (polydata copy, triangles, select ms, patch ms)."""
        self.patches.Update()
        out = vtkPolyData()
        out.ShallowCopy(self.patches.GetOutput())
        return (out, self.patches.GetNumberOfTriangles(), self.selector.GetSelectTime() * 1e3,
                self.patches.GetGenerateTime() * 1e3)

    def render(self, data, actor=None):
        """Luminance image of `data` drawn by `actor` of this scene's (or of `actor` given),
        and the render time in ms."""
        self.renderer.RemoveAllViewProps()
        if actor is not None:
            self.renderer.AddActor(actor)
        else:
            self.mapper.SetInputData(data)
            self.renderer.AddActor(self.actor)
        t0 = time.perf_counter()
        self.window.Render()
        ms = (time.perf_counter() - t0) * 1e3
        img = metrics.luminance(self.read_image())
        self.renderer.RemoveAllViewProps()
        self.renderer.AddActor(self.actor)
        return img, ms
