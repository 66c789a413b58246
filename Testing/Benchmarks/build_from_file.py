"""Building an octree from a PLY file, two ways, each in its own process (so each peak is its
own): vtkPLYReader's polydata into vtkMultiscaleOctreeBuilder (what a VTK user writes), and the
builder reading the file itself (SetFileName: no polydata). Prints, per way, the wall time, the
builder's read and build times and the process's peak resident memory, in bytes per triangle.

    PYTHONPATH=build/lib/python3/dist-packages /usr/bin/python3 \
        Testing/Benchmarks/build_from_file.py model.ply [--repeat 3] [--memory MiB]

Generate large models with build/bin/plodGenerateScan (bounded memory).
"""
import argparse
import json
import resource
import statistics
import subprocess
import sys
import time

CHILD = r'''
import json, resource, sys, time
from vtkmodules.vtkIOPLY import vtkPLYReader
from perceptual_lod import vtkMultiscaleOctreeBuilder
way, path, memory = sys.argv[1], sys.argv[2], float(sys.argv[3])
start = time.perf_counter()
builder = vtkMultiscaleOctreeBuilder()
builder.SetMemoryLimit(memory)
if way == 'reader':
    reader = vtkPLYReader()
    reader.SetFileName(path)
    builder.SetInputConnection(reader.GetOutputPort())
else:
    builder.SetFileName(path)
builder.Update()
wall = time.perf_counter() - start
octree = builder.GetOutput()
print(json.dumps({'wall': wall, 'read': builder.GetReadTime(), 'build': builder.GetBuildTime(),
                  'triangles': builder.GetNumberOfInputTriangles(),
                  'nodes': octree.GetNumberOfNodes(),
                  'peak': resource.getrusage(resource.RUSAGE_SELF).ru_maxrss * 1024}))
'''


def run(way, path, memory):
    out = subprocess.run([sys.executable, '-c', CHILD, way, path, str(memory)],
                         capture_output=True, text=True, check=True)
    return json.loads(out.stdout.strip().splitlines()[-1])


def main():
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument('model')
    ap.add_argument('--repeat', type=int, default=3)
    ap.add_argument('--memory', type=float, default=0, help='MemoryLimit in MiB (0: automatic)')
    args = ap.parse_args()
    rows = {'reader': [], 'file': []}
    for _ in range(args.repeat):
        for way in rows:  # alternated, so that a busy moment slows both
            rows[way].append(run(way, args.model, args.memory))
    print('| way | triangles | wall s | read s | build s | peak MB | peak bytes/triangle |')
    print('| --- | ---: | ---: | ---: | ---: | ---: | ---: |')
    names = {'reader': 'vtkPLYReader + builder', 'file': 'builder.SetFileName'}
    for way, runs in rows.items():
        med = lambda k: statistics.median(r[k] for r in runs)
        t = runs[0]['triangles']
        print(f"| {names[way]} | {t} | {med('wall'):.2f} | {med('read'):.2f} | "
              f"{med('build'):.2f} | {med('peak') / 1e6:.0f} | {med('peak') / max(1, t):.0f} |")
    same = all(r['nodes'] == rows['reader'][0]['nodes'] for r in rows['file'])
    print(f"same octree size both ways: {same}")


if __name__ == '__main__':
    main()
