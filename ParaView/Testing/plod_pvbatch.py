"""pvbatch tests of the PerceptualLOD plugin (run by CTest; see ParaView/Testing/CMakeLists.txt).

    pvbatch plod_pvbatch.py one-rank <out dir>
    pvbatch plod_pvbatch.py octree <out dir>
    mpiexec -np 2 pvbatch --symmetric plod_pvbatch.py two-ranks <out dir>
    mpiexec -np 2 pvbatch --symmetric plod_pvbatch.py two-ranks-frame-time <out dir>
    pvbatch plod_pvbatch.py screenshot <png> [model.ply]

The scene is generated (no data files): ParaView's Wavelet source contoured at one value, a
closed, curved surface of about 100k triangles. Under MPI each rank's contour is its own piece
of the wavelet's extent, so the pieces meet along planes with the border points duplicated:
exactly where independent octrees would crack.

one-rank (pvbatch, builtin session):
- the representation loads from PV_PLUGIN_PATH and appears as "Perceptual LOD";
- triangles fall as the camera moves away (4 distances, strictly);
- a second render of an unchanged view re-executes nothing (no selection, patch or build);
- Reset Camera fits the whole model (the camera equals ResetCamera on the model's bounds);
- the image against ParaView's Surface representation of the full contour, same view: PSNR
  above PSNR_MIN_SURFACE and no hole pixels (background where the surface is, inside its
  silhouette eroded by 3 pixels);
- the image is saved for the two-rank test.

two-ranks (mpiexec -np 2 pvbatch --symmetric: the script runs on every rank):
- every rank holds a piece and triangles of its own, and its selector's eye is the camera
  ParaView rendered with, at two camera positions;
- the composited image has no hole pixels against the one-rank image (its silhouette eroded by
  1 pixel): nothing opens along the piece borders;
- the composited image equals the one-rank image within PSNR_MIN_RANKS;
- with Redistribute off (each rank builds its own piece as ParaView delivers it, ghost layer
  included) the image is further than PSNR_MIN_RANKS from the one-rank image, and turning it on
  again restores the same image.
"""
import os
import sys
import time

import numpy as np

# the image metrics of the measurements (numpy only), one home for PSNR and erosion
sys.path.insert(0, os.path.join(os.path.dirname(os.path.abspath(__file__)), "..", "..", "Testing",
                                "Quality"))
import plod_metrics as metrics  # noqa: E402

from paraview import servermanager
from paraview.simple import (Contour, GetActiveCamera, Render, ResetCamera, Show,
                             Wavelet, CreateView, SaveScreenshot)
from paraview.vtk.util.numpy_support import vtk_to_numpy

SIZE = (480, 480)
PSNR_MIN_SURFACE = 30.0  # dB, LOD (default tolerances) against the full mesh, same view
PSNR_MIN_RANKS = 60.0    # dB, two ranks against one rank, same view (measured: 84 dB)


def controller():
    from vtkmodules.vtkParallelCore import vtkMultiProcessController
    return vtkMultiProcessController.GetGlobalController()


def rank_and_size():
    c = controller()
    return (c.GetLocalProcessId(), c.GetNumberOfProcesses()) if c else (0, 1)


def two_rank_scene():
    """This rank, the number of ranks (at least 2, else the test fails) and the scene."""
    rank, size = rank_and_size()
    if size < 2:
        fail("run with mpiexec -np 2 pvbatch --symmetric")
    return (rank, size) + tuple(scene())


def say(*args):
    rank, size = rank_and_size()
    print("[rank %d/%d]" % (rank, size), *args, flush=True)


def fail(message):
    say("FAIL:", message)
    sys.stdout.flush()
    os._exit(1)


def check(condition, message):
    if not condition:
        fail(message)
    say("ok:", message)


def render_view(size, background):
    """A new render view of `size` pixels, no axes, a plain `background`."""
    view = CreateView("RenderView")
    view.ViewSize = list(size)
    view.OrientationAxesVisibility = 0
    try:
        view.UseColorPaletteForBackground = 0
    except AttributeError:
        pass
    view.Background = background
    return view


def scene(kind="wavelet"):
    """A new render view showing `kind` with the Perceptual LOD representation:
    "wavelet", the Wavelet contoured at 157 (open, about 100k triangles; under MPI each rank
    contours its own piece of the extent, with a ghost layer), or "sphere", a closed sphere of
    318k triangles whose pieces meet along meridians whose points agree only to rounding."""
    view = render_view(SIZE, [0.0, 0.0, 0.0])
    if kind == "sphere":
        from paraview.simple import Sphere
        source = Sphere(ThetaResolution=400, PhiResolution=400)
    else:
        wavelet = Wavelet(WholeExtent=[-40, 40, -40, 40, -40, 40])
        source = Contour(Input=wavelet, ContourBy=["POINTS", "RTData"], Isosurfaces=[157.0])
        source.ComputeScalars = 0
    display = Show(source, view)
    display.ColorArrayName = ["POINTS", ""]
    display.SetRepresentationType("Perceptual LOD")
    return view, source, display


class LOD:
    """This rank's vtkPerceptualLODRepresentation, read through the display's information
    properties (the plugin's classes have no Python wrapping in ParaView's Python)."""

    def __init__(self, display):
        self.proxy = display.SMProxy
        if self.proxy.GetProperty("NumberOfTriangles") is None:
            fail("the display has no Perceptual LOD properties: is the plugin loaded "
                 "(PV_PLUGIN_PATH)?")

    def get(self, name):
        self.proxy.UpdatePropertyInformation()
        p = self.proxy.GetProperty(name)
        values = [p.GetElement(i) for i in range(p.GetNumberOfElements())]
        return values[0] if len(values) == 1 else values

    def __getattr__(self, method):
        # lod.GetNumberOfBuilds() reads the property NumberOfBuilds
        if method.startswith("Get"):
            return lambda: self.get(method[3:])
        raise AttributeError(method)


def lod_object(display):
    return LOD(display)


def capture(view):
    image = view.CaptureWindow(1)
    width, height, _ = image.GetDimensions()
    rgb = vtk_to_numpy(image.GetPointData().GetScalars()).reshape(height, width, -1)[:, :, :3]
    return np.asarray(rgb[::-1], dtype=np.float64)


def psnr(a, b):
    """PSNR of the luminance of two RGB images (plod_metrics, the measurements' own)."""
    return metrics.psnr(metrics.luminance(a), metrics.luminance(b))


def covered(rgb):
    return rgb.max(axis=2) > 0


def holes(image, reference, r):
    """Background pixels of `image` inside the reference's object mask eroded by r pixels."""
    return int((metrics.erode(covered(reference), r) & ~covered(image)).sum())


def camera_distance(camera):
    p = np.array(camera.GetPosition())
    f = np.array(camera.GetFocalPoint())
    return float(np.linalg.norm(p - f))


def dolly_to(view, distance):
    camera = GetActiveCamera()
    f = np.array(camera.GetFocalPoint())
    p = np.array(camera.GetPosition())
    d = (p - f) / np.linalg.norm(p - f)
    camera.SetPosition(*(f + distance * d))
    view.CenterOfRotation = list(f)
    Render(view)


def one_rank(out):
    view, contour, display = scene()
    lod = lod_object(display)
    ResetCamera(view)
    Render(view)
    check(lod.GetNumberOfBuilds() == 1, "the octree is built once (%d)" % lod.GetNumberOfBuilds())
    triangles = lod.GetNumberOfTriangles()
    check(triangles > 1000, "the first render draws triangles (%d)" % triangles)
    say("octree: finest level %d, %d nodes, %d triangles" % (
        lod.GetOctreeFinestLevel(), lod.GetNumberOfOctreeNodes(), lod.GetNumberOfOctreeTriangles()))

    # Reset Camera fits the whole model: the same camera as a VTK ResetCamera on its bounds
    info = contour.GetDataInformation()
    bounds = info.GetBounds()
    camera = GetActiveCamera()
    focal = np.array(camera.GetFocalPoint())
    centre = np.array([(bounds[0] + bounds[1]) / 2, (bounds[2] + bounds[3]) / 2,
                       (bounds[4] + bounds[5]) / 2])
    check(np.allclose(focal, centre, atol=1e-6 * (bounds[1] - bounds[0])),
          "Reset Camera centres the model's bounds (%s vs %s)" % (focal, centre))
    matrix = camera.GetCompositeProjectionTransformMatrix(SIZE[0] / SIZE[1], -1, 1)
    inside = []
    for i in range(8):
        corner = [bounds[i & 1], bounds[2 + ((i >> 1) & 1)], bounds[4 + ((i >> 2) & 1)], 1.0]
        x = [sum(matrix.GetElement(r, c) * corner[c] for c in range(4)) for r in range(4)]
        inside.append(abs(x[0] / x[3]) <= 1 and abs(x[1] / x[3]) <= 1)
    check(all(inside), "Reset Camera shows every corner of the model's bounds")
    image = capture(view)
    np.save(os.path.join(out, "onerank.npy"), image)
    reference_camera = (camera.GetPosition(), camera.GetFocalPoint(), camera.GetViewUp())

    # a still render re-executes nothing
    counts = (lod.GetNumberOfSelections(), lod.GetNumberOfPatchUpdates(), lod.GetNumberOfBuilds())
    Render(view)
    Render(view)
    again = (lod.GetNumberOfSelections(), lod.GetNumberOfPatchUpdates(), lod.GetNumberOfBuilds())
    check(again == counts, "two still renders re-execute nothing (selections, patches, builds: "
          "%s then %s)" % (counts, again))

    # triangles fall as the camera moves away
    start = camera_distance(camera)
    series = []
    for factor in (1.0, 2.0, 4.0, 8.0):
        dolly_to(view, start * factor)
        series.append(lod.GetNumberOfTriangles())
    check(all(a > b for a, b in zip(series, series[1:])),
          "triangles fall as the camera moves away: %s" % series)
    check(lod.GetNumberOfBuilds() == 1, "moving the camera builds nothing again")

    # the triangle budget, as representation properties: estimated (within a few percent), and
    # exact (never over it)
    dolly_to(view, start)
    display.TriangleBudget = 5000
    Render(view)
    binds = series[0] > 5000  # the tolerance cut draws more: the budget decides
    check((0.85 * 5000 if binds else 0) < lod.GetNumberOfTriangles() <= 1.15 * 5000,
          "TriangleBudget 5000 holds within its estimate (%d triangles, tolerance cut %d)"
          % (lod.GetNumberOfTriangles(), series[0]))
    display.ExactTriangleBudget = 1
    Render(view)
    check((0.9 * 5000 if binds else 0) <= lod.GetNumberOfTriangles() <= 5000,
          "TriangleBudget 5000 holds exactly (%d triangles)" % lod.GetNumberOfTriangles())
    display.ExactTriangleBudget = 0
    display.TriangleBudget = 0
    Render(view)
    check(lod.GetNumberOfTriangles() == series[0], "no budget: the tolerance cut again (%d)"
          % lod.GetNumberOfTriangles())

    # against ParaView's Surface representation of the full contour, same view
    camera.SetPosition(*reference_camera[0])
    camera.SetFocalPoint(*reference_camera[1])
    camera.SetViewUp(*reference_camera[2])
    Render(view)
    lod_image = capture(view)
    lod_triangles = lod.GetNumberOfTriangles()
    display.SetRepresentationType("Surface")
    Render(view)
    surface = capture(view)
    full = info.GetNumberOfCells()
    value = psnr(lod_image, surface)
    hole_pixels = holes(lod_image, surface, 3)
    say("LOD %d triangles of %d: PSNR %.2f dB against the Surface representation, %d hole pixels"
        % (lod_triangles, full, value, hole_pixels))
    check(lod_triangles < full, "the LOD draws fewer triangles than the full contour")
    check(value > PSNR_MIN_SURFACE, "PSNR %.2f dB > %.0f dB against Surface" % (value,
                                                                             PSNR_MIN_SURFACE))
    check(hole_pixels == 0, "no hole pixels against Surface (%d)" % hole_pixels)
    np.save(os.path.join(out, "surface.npy"), surface)

    stanford_bunny(out)

    # the closed sphere, for the two-rank test
    view, sphere, display = scene("sphere")
    ResetCamera(view)
    Render(view)
    check(LOD(display).GetNumberOfTriangles() > 0, "the sphere is drawn")
    np.save(os.path.join(out, "onerank-sphere.npy"), capture(view))
    print("one rank: ok", flush=True)


DATA = os.environ.get("PLOD_DATA_DIR", os.path.join(
    os.path.dirname(os.path.abspath(__file__)), "..", "..", "..", "shared", "data"))


def stanford_bunny(out):
    """Real data: the Stanford bunny (bun_zipper.ply), the camera reset to its bounds, the LOD
    against ParaView's Surface representation of the full mesh with smooth normals (Generate
    Surface Normals, as the LOD's patches are smooth-shaded). Skipped when the data is absent."""
    path = os.path.join(DATA, "bun_zipper.ply")
    if not os.path.exists(path):
        say("skipped: the Stanford bunny test needs %s (set PLOD_DATA_DIR)" % path)
        return
    from paraview.simple import GenerateSurfaceNormals, PLYReader
    view = render_view(SIZE, [0.0, 0.0, 0.0])
    mesh = GenerateSurfaceNormals(Input=PLYReader(FileNames=[path]))
    mesh.Splitting = 0
    display = Show(mesh, view)
    display.ColorArrayName = ["POINTS", ""]
    display.SetRepresentationType("Perceptual LOD")
    ResetCamera(view)
    Render(view)
    lod = LOD(display)
    lod_image, triangles = capture(view), lod.GetNumberOfTriangles()
    display.SetRepresentationType("Surface")
    Render(view)
    surface = capture(view)
    value, hole_pixels = psnr(lod_image, surface), holes(lod_image, surface, 3)
    full = mesh.GetDataInformation().GetNumberOfCells()
    say("Stanford bunny: LOD %d of %d triangles, PSNR %.2f dB against the smooth Surface, %d hole "
        "pixels" % (triangles, full, value, hole_pixels))
    check(0 < triangles < full and value > PSNR_MIN_SURFACE and hole_pixels == 0,
          "the bunny's LOD is faithful to the full mesh (%.2f dB, %d hole pixels)"
          % (value, hole_pixels))


def octree_filters(out):
    from paraview.simple import Hide, MultiscaleOctreeBuilder, OpenDataFile, SaveData
    view, contour, display = scene()
    ResetCamera(view)
    Render(view)
    direct = LOD(display).GetNumberOfTriangles()
    Hide(contour, view)
    octree = MultiscaleOctreeBuilder(Input=contour)
    built = Show(octree, view)
    check(built.GetXMLName() == "PerceptualLODRepresentation",
          "an octree is shown with Perceptual LOD by default (%s)" % built.GetXMLName())
    Render(view)
    from_builder = LOD(built).GetNumberOfTriangles()
    check(from_builder == direct, "the Builder's octree draws what the representation draws "
          "from the surface (%d, %d)" % (from_builder, direct))
    path = os.path.join(out, "contour.plod")
    if os.path.exists(path):
        os.remove(path)
    SaveData(path, proxy=octree)
    check(os.path.getsize(path) > 0, "the Writer writes %s" % path)
    Hide(octree, view)
    read = OpenDataFile(path)
    check(read.GetXMLName() == "MultiscaleOctreeReader", "the Reader opens .plod files")
    from_file = Show(read, view)
    Render(view)
    count = LOD(from_file).GetNumberOfTriangles()
    check(count == direct, "the octree read back draws the same triangles (%d, %d)"
          % (count, direct))
    # the cache limit on the mapped file: 2048 MiB by default; the smallest draws the same
    check(read.CacheLimit == 2048, "the Reader's CacheLimit is 2048 MiB (%s)" % read.CacheLimit)
    read.CacheLimit = 1
    Render(view)
    count = LOD(from_file).GetNumberOfTriangles()
    check(count == direct, "a CacheLimit of 1 MiB draws the same triangles (%d, %d)"
          % (count, direct))
    # background loading: off by default; the first view is read whole, so the same triangles
    check(read.BackgroundLoading == 0, "the Reader's BackgroundLoading is off by default")
    read.BackgroundLoading = 1
    Render(view)
    count = LOD(from_file).GetNumberOfTriangles()
    check(count == direct, "with BackgroundLoading the first view draws the same triangles "
          "(%d, %d)" % (count, direct))
    # a move closer: what the first view did not read is drawn coarser until the thread has
    # read it, and renders again refine to what the plain reader draws there
    lod = LOD(from_file)
    dolly_to(view, 0.15 * camera_distance(GetActiveCamera()))
    awaited = lod.GetNumberOfAwaitingCells()
    for _ in range(300):  # (a bound for a stuck thread: the reads take milliseconds)
        if lod.GetNumberOfAwaitingCells() == 0:
            break
        time.sleep(0.01)
        Render(view)
    streamed = lod.GetNumberOfTriangles()
    check(awaited > 0 and lod.GetNumberOfAwaitingCells() == 0, "with BackgroundLoading the "
          "move draws cells awaiting their pages (%d), and renders refine until none awaits"
          % awaited)
    read.BackgroundLoading = 0
    Render(view)
    plain = lod.GetNumberOfTriangles()
    check(streamed == plain and plain > 0, "refined, the close view draws what the plain "
          "reader draws (%d, %d)" % (streamed, plain))
    say("background loading in ParaView: %d cells awaited their pages after a move closer"
        % awaited)

    # a PLY file built without loading it: the same surface triangles as the mesh
    from paraview.simple import MultiscaleOctreeFromPLYFile
    ply = os.path.join(out, "contour.ply")
    if os.path.exists(ply):
        os.remove(ply)
    SaveData(ply, proxy=contour)
    Hide(read, view)
    from_ply = MultiscaleOctreeFromPLYFile(FileName=ply)
    shown = Show(from_ply, view)
    Render(view)
    lod = LOD(shown)
    cells = contour.GetDataInformation().GetNumberOfCells()
    check(lod.GetNumberOfOctreeTriangles() == cells and lod.GetNumberOfTriangles() > 0,
          "the octree of the PLY file holds its %d triangles (%d) and draws %d"
          % (cells, lod.GetNumberOfOctreeTriangles(), lod.GetNumberOfTriangles()))

    # the same file built in pieces into an octree file (the way of a scan larger than memory)
    pieces_file = os.path.join(out, "contour-pieces.plod")
    if os.path.exists(pieces_file):
        os.remove(pieces_file)
    from_pieces = MultiscaleOctreeFromPLYFile(FileName=ply, OctreeFileName=pieces_file,
                                              BuildInPieces=1)
    Hide(from_ply, view)
    shown = Show(from_pieces, view)
    Render(view)
    lod = LOD(shown)
    check(os.path.exists(pieces_file) and lod.GetNumberOfOctreeTriangles() == cells
          and lod.GetNumberOfTriangles() > 0,
          "built in pieces into %s: its %d triangles (%d), %d drawn"
          % (pieces_file, cells, lod.GetNumberOfOctreeTriangles(), lod.GetNumberOfTriangles()))
    print("octree filters: ok", flush=True)


def two_ranks(out):
    rank, size, view, contour, display = two_rank_scene()
    lod = lod_object(display)
    ResetCamera(view)
    Render(view)
    say("octree: finest level %d, %d nodes, %d triangles" % (
        lod.GetOctreeFinestLevel(), lod.GetNumberOfOctreeNodes(), lod.GetNumberOfOctreeTriangles()))
    camera = GetActiveCamera()
    for step in range(2):
        eye = lod.GetSelectorEye()
        position = camera.GetPosition()
        check(np.allclose(eye, position, rtol=1e-9, atol=1e-9 * camera_distance(camera)),
              "the selector's eye is the rendered camera (%s vs %s)" % (eye, position))
        check(lod.GetNumberOfTriangles() > 0, "this rank draws triangles of its own (%d)"
              % lod.GetNumberOfTriangles())
        if step == 0:
            image = capture(view)
            camera.Azimuth(30)
            Render(view)
    check(lod.GetRank() == rank, "the properties read are this rank's (%d)" % lod.GetRank())
    check(lod.GetNumberOfOwnedCells() > 0, "this rank owns octree cells (%d)"
          % lod.GetNumberOfOwnedCells())
    # the same view with every rank building its own piece as it is: what the redistribution
    # prevents (reported, and checked to differ, so that the checks below can tell)
    camera.Azimuth(-30)
    display.Redistribute = 0
    Render(view)
    unshared = capture(view)
    display.Redistribute = 1
    Render(view)
    again = capture(view)
    # the closed sphere: its pieces' border points agree only to rounding (merged), and the
    # automatic back-face rule must see the whole closed mesh, not each rank's open piece
    view_s, sphere, display_s = scene("sphere")
    ResetCamera(view_s)
    Render(view_s)
    lod_s = LOD(display_s)
    check(lod_s.GetGlobalBoundaryEdges() == 0, "the sphere shared out is closed (boundary edges "
          "of the whole mesh: %d)" % lod_s.GetGlobalBoundaryEdges())
    sphere_image = capture(view_s)
    if rank != 0:
        print("two ranks: ok", flush=True)
        return
    reference_s = np.load(os.path.join(out, "onerank-sphere.npy"))
    value_s = psnr(sphere_image, reference_s)
    holes_s = holes(sphere_image, reference_s, 1)
    say("sphere, two ranks against one: PSNR %.2f dB, %d hole pixels" % (value_s, holes_s))
    check(holes_s == 0 and value_s > PSNR_MIN_RANKS, "the sphere on two ranks is the one-rank "
          "sphere (%.2f dB > %.0f dB, %d hole pixels)" % (value_s, PSNR_MIN_RANKS, holes_s))
    reference = np.load(os.path.join(out, "onerank.npy"))
    value_off = psnr(unshared, reference)
    say("pieces built as they are (Redistribute off): PSNR %.2f dB against one rank, %d hole "
        "pixels" % (value_off, holes(unshared, reference, 1)))
    check(value_off < PSNR_MIN_RANKS, "without the redistribution the image is not the one-rank "
          "image (%.2f dB): the PSNR check tells them apart" % value_off)
    check(np.array_equal(again, image), "Redistribute on again gives the same image")
    np.save(os.path.join(out, "tworanks.npy"), image)
    hole_pixels = holes(image, reference, 1)
    value = psnr(image, reference)
    say("two ranks against one: PSNR %.2f dB, %d hole pixels" % (value, hole_pixels))
    check(hole_pixels == 0, "no hole pixels along the piece borders (%d)" % hole_pixels)
    check(value > PSNR_MIN_RANKS, "PSNR %.2f dB > %.0f dB against one rank" % (value,
                                                                            PSNR_MIN_RANKS))
    print("two ranks: ok", flush=True)


def gather(values):
    """Every rank's `values` (numbers), in rank order: one AllGather, made by every rank."""
    from vtkmodules.vtkCommonCore import vtkDoubleArray
    send, received = vtkDoubleArray(), vtkDoubleArray()
    send.SetNumberOfTuples(len(values))
    for i, v in enumerate(values):
        send.SetValue(i, float(v))
    controller().AllGather(send, received)
    n = len(values)
    return [[received.GetValue(r * n + i) for i in range(n)] for r in range(rank_and_size()[1])]


FRAME_FIGURES = ("SharedFrameCost", "LocalFrameCost", "TotalTriangleBudget", "RankTriangleBudget",
                 "NumberOfBudgetTriangles", "NumberOfTriangles", "NumberOfFrameReductions",
                 "NumberOfSelections")


def frame_figures(lod):
    """This frame's figures of every rank: a list (one dict per rank)."""
    rows = gather([lod.get(name) for name in FRAME_FIGURES])
    return [dict(zip(FRAME_FIGURES, row)) for row in rows]


def check_shared_frame(rows, what):
    """The checks made on every frame with several ranks: the same steering frame cost and total
    budget on every rank, the ranks' parts and the triangles within the total."""
    costs = {row["SharedFrameCost"] for row in rows}
    totals = {row["TotalTriangleBudget"] for row in rows}
    if len(costs) != 1:
        fail("%s: the ranks steer with different frame costs %s" % (what, sorted(costs)))
    if len(totals) != 1:
        fail("%s: the ranks hold different total budgets %s" % (what, sorted(totals)))
    total = totals.pop()
    parts = sum(row["RankTriangleBudget"] for row in rows)
    counted = sum(row["NumberOfBudgetTriangles"] for row in rows)
    drawn = sum(row["NumberOfTriangles"] for row in rows)
    if total > 0 and not (parts <= total and counted <= total and drawn <= total):
        fail("%s: over the total budget %d: parts %d, counted %d, drawn %d triangles"
             % (what, total, parts, counted, drawn))
    return total, counted, drawn


def two_ranks_frame_time(out):
    """mpiexec -np 2 pvbatch --symmetric: the budget and the frame-time target shared by ranks.
    - TriangleBudget is the view's total: the ranks' parts, the triangles their selectors count
      and those they draw stay within it, the split settles (a still view selects nothing
      again), and 0 gives the tolerance cut again;
    - with TargetFrameTime set, every frame, both ranks steer with the same frame cost (the
      maximum over ranks) and hold the same total budget, and the triangles stay within it;
    - one rank made to look slow (TestingExtraFrameCost on TestingSlowRank 1) lowers both
      ranks' budgets, though rank 0's own frames are far faster than the target;
    - with one rank's actor culled (its piece outside the view), both go on exchanging;
    - the representation's collectives are as many on every rank: one per render."""
    rank, size, view, contour, display = two_rank_scene()
    lod = LOD(display)
    ResetCamera(view)
    renders = 0

    def render(what):
        nonlocal renders
        Render(view)
        renders += 1
        rows = frame_figures(lod)
        return rows, check_shared_frame(rows, what)

    rows, (_, tolerance_counted, tolerance_drawn) = render("tolerance cut")
    # (paraview.simple renders the first render twice, the camera reset between)
    first_reductions, renders = rows[0]["NumberOfFrameReductions"], 0
    say("tolerance cut: %s counted, %s drawn" % ([r["NumberOfBudgetTriangles"] for r in rows],
                                                 [r["NumberOfTriangles"] for r in rows]))
    # the fixed budget: a third of the tolerance cut, in the whole view
    budget = int(tolerance_counted // 3)
    display.TriangleBudget = budget
    selections = []
    for frame in range(5):
        rows, (total, counted, drawn) = render("TriangleBudget %d, frame %d" % (budget, frame))
        check(total == budget, "TriangleBudget %d is the view's total (%d)" % (budget, total))
        selections.append([r["NumberOfSelections"] for r in rows])
    check(selections[-1] == selections[-3], "the split settles: a still view selects nothing "
          "again (selections per rank and frame: %s)" % selections)
    parts = [r["RankTriangleBudget"] for r in rows]
    check(counted > 0.9 * budget and drawn > 0.5 * budget,
          "TriangleBudget %d split %s between the ranks: %d counted, %d drawn in all"
          % (budget, parts, counted, drawn))
    display.TriangleBudget = 0
    rows, (_, counted, drawn) = render("no budget")
    check(drawn == tolerance_drawn, "no budget: the tolerance cut again (%d)" % drawn)

    # a frame-time target far above what frames cost: the budget rises to the tolerance cut
    target = 10.0
    display.TargetFrameTime = target
    first = []
    for frame in range(5):
        rows, (total, counted, drawn) = render("target %g s, frame %d" % (target, frame))
        first.append((rows[0]["SharedFrameCost"], total))
    say("target %g s: (shared frame cost, total budget) per frame %s" % (target, first))
    check(total >= counted and drawn == tolerance_drawn,
          "a target far above the frame costs draws the tolerance cut (%d of budget %d)"
          % (drawn, total))
    local0 = rows[0]["LocalFrameCost"]
    check(0 < local0 < target, "rank 0's own frames cost %.3f s" % local0)

    # rank 1 looks slow: its frames count 2 targets more than they cost (set alike on every
    # rank: a property changed on one rank only makes that rank alone update the view)
    display.TestingSlowRank = 1
    display.TestingExtraFrameCost = 2 * target
    slowed = []
    for frame in range(8):
        rows, (total, counted, drawn) = render("rank 1 slowed, frame %d" % frame)
        slowed.append((rows[0]["SharedFrameCost"], total, rows[0]["RankTriangleBudget"],
                       rows[1]["RankTriangleBudget"], counted, drawn,
                       rows[0]["LocalFrameCost"]))
    for row in slowed:
        say("rank 1 slowed: shared cost %.3f s, total %d, parts %d + %d, counted %d, drawn %d, "
            "rank 0's own frame %.3f s" % row)
    check(all(row[0] >= 2 * target for row in slowed),
          "both ranks steer with rank 1's slow frames (shared cost >= %g s)" % (2 * target))
    check(all(row[6] < target for row in slowed),
          "rank 0's own frames stay below the target (at most %.3f s)"
          % max(row[6] for row in slowed))
    totals = [row[1] for row in slowed]
    # the median of three frames moves one frame after the first slow one, then every frame
    check(all(b < a for a, b in zip(totals, totals[1:])) and totals[-1] < 0.5 * totals[0],
          "the total budget falls with the slowest rank's frames: %s" % totals)
    part0 = [row[2] for row in slowed]
    check(part0[-1] < 0.5 * part0[0],
          "rank 0's part falls too, though its own frames are fast: %s" % part0)

    # a view of one corner of the model from the side, through a narrow angle: a rank whose
    # piece lies outside the frustum has its actor culled by the renderer, so it does not push
    # and could not take part in a collective made while rendering. The exchange at
    # REQUEST_RENDER goes on, the same on both ranks.
    camera = GetActiveCamera()
    saved = (camera.GetPosition(), camera.GetFocalPoint(), camera.GetViewUp(),
             camera.GetViewAngle())
    b = contour.GetDataInformation().GetBounds()
    corner = np.array([b[0], b[2], b[4]])
    side = np.array([-1.0, 1.0, 0.0]) / np.sqrt(2.0)
    camera.SetFocalPoint(*corner)
    camera.SetPosition(*(corner + (b[1] - b[0]) * side))
    camera.SetViewUp(0, 0, 1)
    camera.SetViewAngle(10)
    for frame in range(3):
        rows, _ = render("one rank culled, frame %d" % frame)
        follows = gather([1.0 if np.allclose(lod.GetSelectorEye(), camera.GetPosition()) else 0.0])
    check(sorted(f[0] for f in follows) == [0.0, 1.0],
          "one rank's actor is culled, the other renders (selector eyes following the camera: "
          "%s), and both keep exchanging" % [f[0] for f in follows])
    camera.SetPosition(*saved[0])
    camera.SetFocalPoint(*saved[1])
    camera.SetViewUp(*saved[2])
    camera.SetViewAngle(saved[3])

    # the representation's collectives: as many on every rank, one per render
    reductions = [r["NumberOfFrameReductions"] for r in rows]
    check(len(set(reductions)) == 1 and reductions[0] - first_reductions == renders,
          "one reduction per render on every rank (%s, %d for the %d renders since the first)"
          % (reductions, reductions[0] - first_reductions, renders))
    display.TestingExtraFrameCost = 0
    display.TargetFrameTime = 0
    rows, (_, counted, drawn) = render("target off")
    check(drawn == tolerance_drawn, "the target off: the tolerance cut again (%d)" % drawn)
    print("two ranks frame time: ok", flush=True)


def client(out, port):
    """A client (ParaView's Python) connected to `mpiexec -np 2 pvserver` on localhost:`port`:
    the server ranks render (the representation asks for distributed rendering), the client
    gets the composited image and never the mesh."""
    from paraview.simple import Connect, LoadDistributedPlugin
    connection = Connect("localhost", int(port))
    check(connection is not None, "connected to pvserver on port %s" % port)
    # the plugin is loaded on the server ranks through their PV_PLUGIN_PATH; the client needs
    # the proxy definitions too, from its own PV_PLUGIN_PATH
    ranks = servermanager.ActiveConnection.GetNumberOfDataPartitions()
    check(ranks == 2, "the server has 2 ranks (%d)" % ranks)
    view, contour, display = scene()
    lod = LOD(display)
    ResetCamera(view)
    Render(view)
    image = capture(view)
    # information properties read the client's own object: it must have drawn nothing (the
    # mesh never came to the client; the server ranks rendered the image)
    check(lod.GetNumberOfTriangles() == 0,
          "the client draws no triangle itself (%d)" % lod.GetNumberOfTriangles())
    check(covered(image).sum() > 1000, "the client receives the servers' image (%d pixels)"
          % covered(image).sum())
    reference = np.load(os.path.join(out, "onerank.npy"))
    hole_pixels = holes(image, reference, 1)
    value = psnr(image, reference)
    say("client-server (2 server ranks) against one rank: PSNR %.2f dB, %d hole pixels"
        % (value, hole_pixels))
    check(hole_pixels == 0, "no hole pixels in the image the client receives (%d)" % hole_pixels)
    check(value > PSNR_MIN_RANKS, "PSNR %.2f dB > %.0f dB against one rank" % (value,
                                                                            PSNR_MIN_RANKS))
    print("client-server: ok", flush=True)


def screenshot(path, model=None):
    """The README's picture: `model` (a PLY file; default the generated scene) drawn with the
    Perceptual LOD representation, with its triangle count."""
    if model:
        from paraview.simple import PLYReader, Text
        view = render_view((640, 480), [0.1, 0.1, 0.12])
        source = PLYReader(FileNames=[model])
        display = Show(source, view)
        display.ColorArrayName = ["POINTS", ""]
        display.SetRepresentationType("Perceptual LOD")
    else:
        view, source, display = scene()
    display.DiffuseColor = [0.85, 0.75, 0.55]
    ResetCamera(view)
    Render(view)
    lod = LOD(display)
    full = source.GetDataInformation().GetNumberOfCells()
    if model:
        label = Text(Text="Perceptual LOD in ParaView 5.11 (pvbatch): %d of %d triangles"
                     % (lod.GetNumberOfTriangles(), full))
        label_display = Show(label, view)
        label_display.FontSize = 14
        Render(view)
    SaveScreenshot(path, view, ImageResolution=list(view.ViewSize))
    print("screenshot written: %s (%d of %d triangles)" % (path, lod.GetNumberOfTriangles(), full),
          flush=True)


if __name__ == "__main__":
    mode, target = sys.argv[1], sys.argv[2]
    {"one-rank": one_rank, "two-ranks": two_ranks, "two-ranks-frame-time": two_ranks_frame_time,
     "octree": octree_filters, "client": client, "screenshot": screenshot}[mode](
        target, *sys.argv[3:])
