"""Building an octree file from a PLY file in bounded memory (plodBuildInPieces: the file split
into pieces built one after the other), beside the in-core build of the same file in the same
run (vtkMultiscaleOctreeBuilder.SetFileName), each in its own process so that each peak is its
own; then the time to open the file built in pieces (vtkMultiscaleOctreeReader, mapped). Prints
one Markdown row per way: wall seconds, millions of input triangles per second, peak resident
memory, temporary disk, file bytes per input triangle.

    PYTHONPATH=build/lib/python3/dist-packages /usr/bin/python3 \
        Testing/Benchmarks/build_in_pieces.py model.ply --memory 4G [--in-core] [--tmp folder]

Generate the models with build/bin/plodGenerateScan (bounded memory). The file built in pieces
is written beside the model as <model>.pieces.plod and removed at the end.
"""
import argparse
import json
import os
import re
import resource
import subprocess
import sys
import time

HERE = os.path.dirname(os.path.abspath(__file__))

IN_CORE = r'''
import json, os, resource, sys, time
from perceptual_lod import vtkMultiscaleOctreeBuilder, vtkMultiscaleOctreeWriter
path, out = sys.argv[1], sys.argv[2]
start = time.perf_counter()
builder = vtkMultiscaleOctreeBuilder()
builder.SetFileName(path)
builder.Update()
writer = vtkMultiscaleOctreeWriter()
writer.SetInputData(builder.GetOutput())
writer.SetFileName(out)
ok = writer.Write()
wall = time.perf_counter() - start
print(json.dumps({'ok': bool(ok), 'wall': wall, 'triangles': builder.GetNumberOfInputTriangles(),
                  'bytes': os.path.getsize(out) if ok else 0,
                  'peak': resource.getrusage(resource.RUSAGE_SELF).ru_maxrss * 1024}))
'''

OPEN = r'''
import json, resource, sys, time
from perceptual_lod import vtkMultiscaleOctreeReader
start = time.perf_counter()
reader = vtkMultiscaleOctreeReader()
reader.SetFileName(sys.argv[1])
reader.Update()
wall = time.perf_counter() - start
print(json.dumps({'open': wall, 'nodes': reader.GetOutput().GetNumberOfNodes(),
                  'mapped': bool(reader.GetMapped()),
                  'peak': resource.getrusage(resource.RUSAGE_SELF).ru_maxrss * 1024}))
'''


def child(code, *args):
    run = subprocess.run([sys.executable, '-c', code, *args], capture_output=True, text=True)
    if run.returncode != 0:
        sys.exit(run.stderr)
    return json.loads(run.stdout.strip().splitlines()[-1])


def in_pieces(program, model, out, memory, tmp):
    command = [program, model, '--save', out, '--memory', memory] + (['--tmp', tmp] if tmp else [])
    start = time.perf_counter()
    run = subprocess.run(command, capture_output=True, text=True)
    wall = time.perf_counter() - start
    if run.returncode != 0:
        sys.exit(run.stdout + run.stderr)
    split = re.search(r'split: (\d+) pieces', run.stdout)
    built = re.search(r'temporary disk (\d+) MiB, file ([0-9.]+) bytes per input triangle',
                      run.stdout)
    usable = re.search(r'\(([0-9.]+) M input triangles/s\), peak (\d+) MiB', run.stdout)
    return {'wall': wall, 'pieces': int(split.group(1)), 'temporary': int(built.group(1)),
            'bytes_per_triangle': float(built.group(2)), 'rate': float(usable.group(1)),
            'peak': float(usable.group(2)) * 1024 * 1024, 'log': run.stdout}


def main():
    ap = argparse.ArgumentParser(description=__doc__.split('\n')[0])
    ap.add_argument('model')
    ap.add_argument('--memory', default='4G')
    ap.add_argument('--in-core', action='store_true', help='also the in-core build, first')
    ap.add_argument('--tmp', default='')
    ap.add_argument('--program', default=os.path.join(HERE, '..', '..', 'build', 'bin',
                                                         'plodBuildInPieces'))
    args = ap.parse_args()
    out = args.model + '.pieces.plod'
    MiB = 1024.0 * 1024.0
    print('| model | way | wall s | M triangles/s | peak MiB | temporary MiB | file B/triangle '
          '| open ms |')
    print('| --- | --- | ---: | ---: | ---: | ---: | ---: | ---: |')
    name = os.path.basename(args.model)
    if args.in_core:
        core_out = args.model + '.incore.plod'
        r = child(IN_CORE, args.model, core_out)
        if os.path.exists(core_out):
            os.remove(core_out)
        print(f'| {name} | in core | {r["wall"]:.1f} | {r["triangles"] / r["wall"] / 1e6:.2f} | '
              f'{r["peak"] / MiB:,.0f} | 0 | {r["bytes"] / max(1, r["triangles"]):.1f} | |',
              flush=True)
    p = in_pieces(os.path.abspath(args.program), args.model, out, args.memory, args.tmp)
    o = child(OPEN, out)
    os.remove(out)
    print(f'| {name} | in pieces ({p["pieces"]}, --memory {args.memory}) | {p["wall"]:.1f} | '
          f'{p["rate"]:.2f} | {p["peak"] / MiB:,.0f} | {p["temporary"]:,} | '
          f'{p["bytes_per_triangle"]:.1f} | {o["open"] * 1e3:.0f} |', flush=True)
    sys.stderr.write(p['log'])


if __name__ == '__main__':
    main()
