"""The two layouts of an octree file side by side: the mapped one (version 1, the default) and the
compact one (version 2, vtkMultiscaleOctreeWriter::SetCompact). For an octree file given, writes
it again in each layout, alternately, `--repeats` times (median seconds of Write()), then opens
each with the page cache dropped first (cold) and again at once (warm), `--repeats` times
(median milliseconds of the reader's Update()), and prints one Markdown row per layout: bytes
per triangle, write time, open times, resident memory after a cold open.

    PYTHONPATH=build/lib/python3/dist-packages /usr/bin/python3 \\
        Testing/Benchmarks/file_layouts.py model.plod [--repeats 3] [--tmp folder]
"""
import argparse
import os
import statistics
import subprocess
import sys
import tempfile
import time


from perceptual_lod import vtkMultiscaleOctreeReader, vtkMultiscaleOctreeWriter

OPEN = '''
import sys, time, resource
from plod_flight import drop_from_page_cache, resident_mib
from perceptual_lod import vtkMultiscaleOctreeReader
path, cold = sys.argv[1], sys.argv[2] == "cold"
if cold:
    drop_from_page_cache(path)
t = time.perf_counter()
r = vtkMultiscaleOctreeReader()
r.SetFileName(path)
r.Update()
ms = (time.perf_counter() - t) * 1e3
assert r.GetOutput().GetNumberOfNodes() > 0, r.GetErrorMessage()
print(ms, resident_mib())
'''


def open_in_a_new_process(path, cold):
    """(milliseconds, resident MiB) of opening `path` in a fresh process (its own memory)."""
    env = dict(os.environ)
    env['PYTHONPATH'] = os.pathsep.join([os.path.dirname(os.path.abspath(__file__))] +
                                        sys.path)
    out = subprocess.run([sys.executable, '-c', OPEN, path, 'cold' if cold else 'warm'],
                         env=env, check=True, capture_output=True, text=True).stdout.split()
    return float(out[0]), float(out[1])


def main():
    ap = argparse.ArgumentParser()
    ap.add_argument('octree')
    ap.add_argument('--repeats', type=int, default=3)
    ap.add_argument('--tmp', default=None, help='folder for the files written (default: beside)')
    args = ap.parse_args()

    reader = vtkMultiscaleOctreeReader()
    reader.SetFileName(args.octree)
    reader.Update()
    octree = reader.GetOutput()
    if octree.GetNumberOfNodes() == 0:
        sys.exit(f'{args.octree}: {reader.GetErrorMessage()}')
    triangles = octree.GetNumberOfSurfaceTriangles()
    folder = tempfile.mkdtemp(prefix='plod_layouts_',
                              dir=args.tmp or os.path.dirname(os.path.abspath(args.octree)))
    paths = {'mapped': os.path.join(folder, 'mapped.plod'),
             'compact': os.path.join(folder, 'compact.plod')}
    writes = {name: [] for name in paths}
    for _ in range(args.repeats):
        for name, path in paths.items():
            writer = vtkMultiscaleOctreeWriter()
            writer.SetInputData(octree)
            writer.SetFileName(path)
            writer.SetCompact(name == 'compact')
            t = time.perf_counter()
            if not writer.Write():
                sys.exit(writer.GetErrorMessage())
            writes[name].append(time.perf_counter() - t)
    print(f'{args.octree}: {triangles} triangles, {octree.GetNumberOfNodes()} nodes')
    print('| layout | file MiB | B/triangle | write s | open ms, cold | open ms, warm '
          '| resident MiB after a cold open |')
    print('| --- | ---: | ---: | ---: | ---: | ---: | ---: |')
    for name, path in paths.items():
        cold, warm, resident = [], [], []
        for _ in range(args.repeats):
            ms, rss = open_in_a_new_process(path, True)
            cold.append(ms)
            resident.append(rss)
            warm.append(open_in_a_new_process(path, False)[0])
        size = os.path.getsize(path)
        print(f'| {name} | {size / 2 ** 20:,.0f} | {size / triangles:.1f} | '
              f'{statistics.median(writes[name]):.2f} | {statistics.median(cold):.1f} | '
              f'{statistics.median(warm):.1f} | {statistics.median(resident):,.0f} |')
    for path in paths.values():
        os.remove(path)
    os.rmdir(folder)


if __name__ == '__main__':
    main()
