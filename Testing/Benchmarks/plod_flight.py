"""A flight over a saved octree as a viewer flies it, with what the disk costs: the first frame
with the file's pages out of the page cache, then an orbit and a zoom down to the finest level,
vtkPerceptualLODSelector (SRCC, default tolerances, a headlight, 1920 x 1080, the camera's
frustum; the zoom ends four finest cells from a surface point) and vtkMultiscalePatchGenerator (every core) each frame, no rendering (the frame's CPU
work and its waits on the disk).

    PYTHONPATH=build/lib/python3/dist-packages /usr/bin/python3 \\
        Testing/Benchmarks/plod_flight.py model.plod [--frames 300] [--budget 0] \\
        [--cache-limit MiB] [--background-loading] [--render] [--csv out.csv]

Per frame: milliseconds (select + patches), the major page faults taken during it (a fault the
page cache could not serve: the frame waited on the disk), the process's resident memory and
how much of it is the mapped octree (counted page by page after the frame, outside its time;
the reader's CacheLimit bounds it, less the filters' own arrays, which count against it:
--cache-limit, 0 for none, the reader's default if not given), and how many times the limit
dropped the mapped pages. With --background-loading
(the reader's BackgroundLoading), the pages of refinements are read by the octree's own thread:
a frame's waits are then the process's major faults less that thread's, and the flight also
prints the cells drawn coarser while their pages were read and the frames until the view was
whole again after the last request. With --render, each frame is a whole frame as a user
sees it: vtkPerceptualLODActor in an offscreen 1920 x 1080 window with the same camera (VTK's
default headlight), timed over vtkRenderWindow::Render() and WaitForCompletion() (the
selection, the patches, their upload and the draw, with the GL finished). The
file's pages are dropped from the page cache first (posix_fadvise DONTNEED, which needs no
privilege), so the first frame reads from the disk; the octree file is mapped (version 1), so
its pages come and go as the kernel decides. Prints the first frame, the medians and maxima of
the rest, the frames that waited on the disk after the first, and resident memory over the
flight. Scan-like models of any size come from plodGenerateScan and PerceptualLODMain --save
(docs/benchmarks.md).
"""
import argparse
import csv
import math
import os
import resource
import statistics
import time

from plod_views import HEIGHT, WIDTH, look, place_camera, selection_pipeline

from perceptual_lod import vtkMultiscaleOctreeReader, vtkPerceptualLODActor

PAGE = os.sysconf('SC_PAGE_SIZE')


def resident_mib():
    with open('/proc/self/statm') as f:
        return int(f.read().split()[1]) * PAGE / 2 ** 20


def held_mib(octree):
    """The filters' arrays counted against the reader's CacheLimit (vtkMultiscaleOctree::
    GetHeldBytes), or 'not counted' with a library from before they were."""
    if not hasattr(octree, 'GetHeldBytes'):
        return 'not counted'
    return f'{octree.GetHeldBytes() / 2 ** 20:.0f} MiB'


def resident_kinds_mib():
    """(file-backed, anonymous) resident MiB of this process (/proc/self/status): the mapped
    octree's pages against the arrays the filters allocate (and the interpreter's own)."""
    kinds = {}
    with open('/proc/self/status') as f:
        for line in f:
            if line.startswith(('RssFile:', 'RssAnon:')):
                kinds[line.split(':')[0]] = int(line.split()[1]) / 1024
    return kinds.get('RssFile', 0.0), kinds.get('RssAnon', 0.0)


def major_faults():
    return resource.getrusage(resource.RUSAGE_SELF).ru_majflt


def drop_from_page_cache(path):
    """Asks the kernel to drop the file's clean pages from the page cache; False if it cannot."""
    try:
        fd = os.open(path, os.O_RDONLY)
        try:
            os.fsync(fd)
            os.posix_fadvise(fd, 0, 0, os.POSIX_FADV_DONTNEED)
        finally:
            os.close(fd)
        return True
    except OSError:
        return False


def flight(frames, closest):
    """(azimuth in degrees, distance in root edges, zoomed) per frame: an orbit about the root
    cube's centre at mid distance over the first half, then a zoom towards a point of the
    surface from mid distance down to `closest` root edges (the same factor every frame)."""
    half = frames // 2
    path = [(360.0 * k / half, 1.9, False) for k in range(half)]
    rest = frames - half
    for k in range(rest):
        f = k / max(1, rest - 1)
        path.append((0.0, 1.9 * (closest / 1.9) ** f, True))
    return path


class RenderedFrames:
    """Whole frames: vtkPerceptualLODActor on the octree at `port`, drawn offscreen; frame()
    places the camera and returns what was timed (Render() and WaitForCompletion())."""

    def __init__(self, port, budget):
        from vtkmodules.vtkRenderingCore import vtkRenderer, vtkRenderWindow
        import vtkmodules.vtkRenderingOpenGL2  # noqa: F401 (the OpenGL window and mappers)
        self.actor = vtkPerceptualLODActor()
        self.actor.SetInputConnection(port)
        self.actor.GetSelector().SetTriangleBudget(budget)
        self.renderer = vtkRenderer()
        self.renderer.AddActor(self.actor)
        self.window = vtkRenderWindow()
        self.window.SetOffScreenRendering(1)
        self.window.SetSize(WIDTH, HEIGHT)
        self.window.AddRenderer(self.renderer)
        self.selector = self.actor.GetSelector()
        self.patches = self.actor.GetPatchGenerator()

    def frame(self, eye, focus, distance):
        place_camera(self.renderer.GetActiveCamera(), eye, focus, distance)
        t = time.perf_counter()
        self.window.Render()
        self.window.WaitForCompletion()
        return (time.perf_counter() - t) * 1e3


def main():
    ap = argparse.ArgumentParser()
    ap.add_argument('octree')
    ap.add_argument('--frames', type=int, default=300)
    ap.add_argument('--budget', type=int, default=0, help='triangle budget (0: none)')
    ap.add_argument('--cache-limit', type=int, default=None,
                    help="the reader's CacheLimit in MiB (0: none; default: the reader's)")
    ap.add_argument('--background-loading', action='store_true',
                    help="the reader's BackgroundLoading: pages read off the frame")
    ap.add_argument('--render', action='store_true',
                    help='whole frames: vtkPerceptualLODActor drawn offscreen, GL finished')
    ap.add_argument('--csv', help='per-frame figures')
    args = ap.parse_args()

    dropped = drop_from_page_cache(args.octree)
    rss0, faults0 = resident_mib(), major_faults()
    t0 = time.perf_counter()
    reader = vtkMultiscaleOctreeReader()
    reader.SetFileName(args.octree)
    if args.cache_limit is not None:
        reader.SetCacheLimit(args.cache_limit)
    reader.SetBackgroundLoading(args.background_loading)
    reader.Update()
    open_ms = (time.perf_counter() - t0) * 1e3
    bounds = [0.0] * 6
    reader.GetOutput().GetNodeBounds(0, bounds)
    centre = [0.5 * (bounds[2 * a] + bounds[2 * a + 1]) for a in range(3)]
    edge = bounds[1] - bounds[0]
    # the zoom's target: the vertex of the last node, a cell of the finest level (nodes are
    # stored level by level), on the surface; the zoom ends four of its cells away
    octree = reader.GetOutput()
    last = octree.GetNumberOfNodes() - 1
    target = [0.0] * 3
    octree.GetNodeVertex(last, target)
    cell = [0.0] * 6
    octree.GetNodeBounds(last, cell)
    closest = 4 * (cell[1] - cell[0]) / edge

    if args.render:
        rendered = RenderedFrames(reader.GetOutputPort(), args.budget)
        selector, patches = rendered.selector, rendered.patches
    else:
        selector, patches = selection_pipeline(reader.GetOutputPort(), args.budget)

    rows = []
    for k, (azimuth, distance, zoomed) in enumerate(flight(args.frames, closest)):
        a = math.radians(azimuth)
        d = distance * edge
        focus = target if zoomed else centre
        eye = (focus[0] + d * math.sin(a), focus[1], focus[2] + d * math.cos(a))
        before = major_faults() - octree.GetNumberOfBackgroundMajorFaults()
        if args.render:
            ms = rendered.frame(eye, focus, d)
        else:
            look(selector, eye, focus, d)
            t = time.perf_counter()
            patches.Update()
            ms = (time.perf_counter() - t) * 1e3
        frame_faults = major_faults() - octree.GetNumberOfBackgroundMajorFaults() - before
        rows.append(dict(frame=k, azimuth=azimuth, distance=distance, ms=ms,
                         triangles=patches.GetNumberOfTriangles(),
                         major_faults=max(0, frame_faults), awaiting=selector.GetNumberOfAwaitingCells(),
                         waiting_loads=octree.GetNumberOfWaitingLoads(),
                         resident_mib=resident_mib(),
                         mapped_mib=octree.GetMappedResidentBytes() / 2 ** 20,
                         releases=octree.GetNumberOfResidentReleases()))

    file_mib, anonymous_mib = resident_kinds_mib()  # at the last frame
    if args.csv:
        with open(args.csv, 'w', newline='') as f:
            w = csv.DictWriter(f, list(rows[0]))
            w.writeheader()
            w.writerows(rows)
    first, rest = rows[0], rows[1:]
    ms = [r['ms'] for r in rest]
    waited = [r for r in rest if r['major_faults'] > 0]
    median = statistics.median(ms)
    print(f'{args.octree}: {os.path.getsize(args.octree) / 2 ** 20:.0f} MiB, page cache '
          f'{"dropped" if dropped else "NOT dropped (warm)"}; open {open_ms:.1f} ms, '
          f'resident {rss0:.0f} MiB before')
    print(f'frames timed: {"whole (render, GL finished)" if args.render else "select + patches"}')
    print(f'first frame {first["ms"]:.1f} ms ({first["major_faults"]} major faults, '
          f'{first["triangles"]} triangles)')
    print(f'frames 2-{len(rows)}: median {median:.2f} ms, max {max(ms):.2f} ms, '
          f'{sum(m > 2 * median for m in ms)} over twice the median; '
          f'{len(waited)} waited on the disk ({sum(r["major_faults"] for r in waited)} faults); '
          f'triangles median {statistics.median(r["triangles"] for r in rest):.0f}')
    rss = [r['resident_mib'] for r in rows]
    print(f'resident MiB over the flight: {min(rss):.0f} min, {statistics.median(rss):.0f} median, '
          f'{max(rss):.0f} max; major faults in all {major_faults() - faults0}')
    mapped = [r['mapped_mib'] for r in rows]
    print(f'the mapped octree resident (MiB, after each frame; CacheLimit '
          f'{reader.GetCacheLimit()} MiB): {min(mapped):.0f} min, {statistics.median(mapped):.0f} '
          f'median, {max(mapped):.0f} max; dropped {rows[-1]["releases"]} times, in '
          f'{sum(r["releases"] > p for r, p in zip(rows, [0] + [q["releases"] for q in rows]))}'
          f' frames')
    print(f'resident at the last frame: {file_mib:.0f} MiB of files (the mapped octree, the '
          f'libraries), {anonymous_mib:.0f} MiB anonymous (the filters\' arrays, Python, VTK); '
          f'the filters\' arrays counted against the CacheLimit: {held_mib(octree)}')
    if args.background_loading:
        coarser = [r for r in rest if r['awaiting'] > 0]
        print(f'background loading: {len(coarser)} frames drew cells awaiting their pages '
              f'(median {statistics.median([r["awaiting"] for r in coarser]) if coarser else 0:.0f}'
              f' cells, max {max([r["awaiting"] for r in coarser], default=0)}); '
              f'{octree.GetNumberOfBackgroundLoads()} refinements read by the thread, '
              f'{octree.GetNumberOfBackgroundMajorFaults()} major faults there')


if __name__ == '__main__':
    main()
