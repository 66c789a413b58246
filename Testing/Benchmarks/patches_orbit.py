"""What the patches cost as the eye orbits a saved octree: vtkPerceptualLODSelector (SRCC,
default tolerances, one light at the eye, 1920 x 1080, the camera's frustum) and
vtkMultiscalePatchGenerator (every core), the eye on a circle around the octree's root cube.

    PYTHONPATH=build/lib/python3/dist-packages /usr/bin/python3 \\
        Testing/Benchmarks/patches_orbit.py model.plod [--view far|mid|close] [--step 2]
        [--frames 22] [--budget 0] [--exact]

Prints the median patch time (vtkMultiscalePatchGenerator::GetGenerateTime) and selection time
over the frames (the first two dropped) and the median triangle count. Scan-like models of any
size come from plodGenerateScan and PerceptualLODMain --save (docs/benchmarks.md).
"""
import argparse
import math
import statistics

from plod_views import look, selection_pipeline

from perceptual_lod import vtkMultiscaleOctreeReader

# the eye's distance from the root cube's centre, in root edges
DISTANCES = {'far': 5.6, 'mid': 1.9, 'close': 0.85}


def main():
    ap = argparse.ArgumentParser()
    ap.add_argument('octree')
    ap.add_argument('--view', choices=sorted(DISTANCES), default='mid')
    ap.add_argument('--step', type=float, default=2.0, help='degrees a frame')
    ap.add_argument('--frames', type=int, default=22)
    ap.add_argument('--budget', type=int, default=0, help='triangle budget (0: none)')
    ap.add_argument('--exact', action='store_true',
                    help='count the budget exactly (SetExactTriangleBudget)')
    args = ap.parse_args()

    reader = vtkMultiscaleOctreeReader()
    reader.SetFileName(args.octree)
    reader.Update()
    bounds = [0.0] * 6
    reader.GetOutput().GetNodeBounds(0, bounds)
    centre = [0.5 * (bounds[2 * a] + bounds[2 * a + 1]) for a in range(3)]
    distance = DISTANCES[args.view] * (bounds[1] - bounds[0])

    selector, patches = selection_pipeline(reader.GetOutputPort(), args.budget, args.exact)

    patch_ms, select_ms, triangles = [], [], []
    for frame in range(args.frames):
        a = math.radians(args.step * frame)
        eye = (centre[0] + distance * math.sin(a), centre[1], centre[2] + distance * math.cos(a))
        look(selector, eye, centre, distance)
        patches.Update()
        if frame >= 2:
            patch_ms.append(patches.GetGenerateTime() * 1e3)
            select_ms.append(selector.GetSelectTime() * 1e3)
            triangles.append(patches.GetNumberOfTriangles())
    print(f'{args.view}, {args.step:g} degrees a frame, budget {args.budget}'
          f'{" (exact)" if args.exact else ""}: patches median '
          f'{statistics.median(patch_ms):.2f} ms, selection {statistics.median(select_ms):.2f} ms, '
          f'{statistics.median(triangles):.0f} triangles')


if __name__ == '__main__':
    main()
