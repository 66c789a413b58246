"""What the benchmark scripts share: the selection of a user's view as the benchmarks set it up
(vtkPerceptualLODSelector with SRCC and its default tolerances, one light at the eye, a 1920 x
1080 viewport, the camera's frustum) followed by vtkMultiscalePatchGenerator, and the camera
that looks from an eye at a focus."""
from vtkmodules.vtkRenderingCore import vtkCamera

from perceptual_lod import vtkMultiscalePatchGenerator, vtkPerceptualLODSelector

WIDTH, HEIGHT = 1920, 1080
VIEW_ANGLE = 30.0  # degrees, VTK's default camera


def selection_pipeline(port, budget=0, exact=None):
    """(selector, patches) on the octree at `port`: a triangle budget (0: none) and, when
    `exact` is not None, whether it is counted exactly (else the selector's default)."""
    selector = vtkPerceptualLODSelector()
    selector.SetInputConnection(port)
    selector.SetTriangleBudget(budget)
    if exact is not None:
        selector.SetExactTriangleBudget(exact)
    selector.SetViewportSize(WIDTH, HEIGHT)
    selector.AddLight(False, 0, 0, 1, 1, 0)
    patches = vtkMultiscalePatchGenerator()
    patches.SetInputConnection(selector.GetOutputPort())
    return selector, patches


def place_camera(camera, eye, focus, distance):
    """Puts `camera` at `eye` looking at `focus`, `distance` apart, +y up, with VTK's default
    view angle, clipped at 0.01 and 10 times the distance (the benchmarks' every view)."""
    camera.SetFocalPoint(focus)
    camera.SetPosition(eye)
    camera.SetViewUp(0, 1, 0)
    camera.SetViewAngle(VIEW_ANGLE)
    camera.SetClippingRange(distance * 0.01, distance * 10)


def look(selector, eye, focus, distance):
    """Points `selector` from `eye` at `focus`, `distance` apart: the frustum of place_camera's
    camera, the light at the eye."""
    camera = vtkCamera()
    place_camera(camera, eye, focus, distance)
    planes = [0.0] * 24
    camera.GetFrustumPlanes(WIDTH / HEIGHT, planes)
    selector.SetEyePosition(eye)
    selector.SetFrustumPlanes(planes)
    selector.SetLight(0, False, *eye, 1, 0)
