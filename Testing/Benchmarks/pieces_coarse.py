"""The levels above the pieces (issue 26): how an octree file built in pieces draws far views,
against the in-core octree of the same PLY file and against the full-resolution mesh.

    PYTHONPATH=build/lib/python3/dist-packages xvfb-run -a -s "-screen 0 1280x1024x24" \\
        /usr/bin/python3 Testing/Benchmarks/pieces_coarse.py model.ply pieces.plod [--k 6]

`pieces.plod` is the model built in pieces (plodBuildInPieces model.ply --save pieces.plod
--memory M); the in-core octree is built here from the same file (vtkMultiscaleOctreeBuilder
SetFileName). The protocol is that of Testing/Quality/plod_faithful.py (640x480, the camera
reset to the model's bounds, 4 azimuths, the ordinary pipeline fed by the render binding, the
reference smooth-shaded), at four distances: Dolly(1) (mid), 0.25 (far), 1/16 and 1/64 (the
model a few dozen pixels across). Each view is drawn from the in-core octree, from the pieces'
file as it is, and from the pieces' file with the selector's MinimumLevel at k (what the file
drew when the levels above k held structure only). Prints one row per view and the medians
per distance: triangles, PSNR against the reference, and PSNR of the pieces' image against
the in-core octree's.
"""
import argparse
import os
import sys

import numpy as np

sys.path.insert(0, os.path.join(os.path.dirname(os.path.abspath(__file__)), '..', 'Quality'))
import plod_metrics as metrics  # noqa: E402
import plod_scene  # noqa: E402
from perceptual_lod import vtkMultiscaleOctreeReader  # noqa: E402

DISTANCES = {'mid': 1.0, 'far': 0.25, 'far/16': 1 / 16, 'far/64': 1 / 64}
AZIMUTHS = [0, 90, 180, 270]


def lum(img):
    return metrics.luminance(img)


def main():
    parser = argparse.ArgumentParser(description=__doc__.split('\n')[0])
    parser.add_argument('ply')
    parser.add_argument('pieces')
    parser.add_argument('--k', type=int, default=6, help='the pieces\' ownership level')
    args = parser.parse_args()

    model = plod_scene.read_ply(args.ply, triangles=True)
    scene = plod_scene.Scene(model, size=(640, 480), background=plod_scene.BLUE)
    reader = vtkMultiscaleOctreeReader()
    reader.SetFileName(args.pieces)
    reader.Update()
    print('in core: %d nodes; pieces: %d nodes, coarsest drawn level %d' % (
        scene.octree.GetNumberOfNodes(), reader.GetOutput().GetNumberOfNodes(),
        reader.GetOutput().GetCoarsestDrawnLevel()), flush=True)
    ways = [('in core', scene.builder, 0), ('pieces', reader, 0), ('pieces, min k', reader, args.k)]
    rows = []
    for dname, dolly in DISTANCES.items():
        for az in AZIMUTHS:
            scene.reset_view(az, dolly)
            ref = lum(scene.render_actor(scene.ref_actor))
            images = {}
            row = dict(distance=dname, azimuth=az)
            for name, source, minimum in ways:
                scene.selector.SetInputConnection(source.GetOutputPort())
                scene.selector.SetMinimumLevel(minimum)
                img, tris = scene.render_lod(1.0)
                images[name] = lum(img)
                row[name] = (tris, metrics.psnr(ref, images[name]))
            row['pieces vs in core'] = metrics.psnr(images['in core'], images['pieces'])
            rows.append(row)
            print('%-7s az %3d  ' % (dname, az) + '  '.join(
                '%s %7d tris %6.2f dB' % (n, row[n][0], row[n][1]) for n, _, _ in ways) +
                '  pieces vs in core %6.2f dB' % row['pieces vs in core'], flush=True)
    print('\n| distance | ' + ' | '.join('%s: triangles, PSNR dB' % n for n, _, _ in ways) +
          ' | pieces against in core, PSNR dB |')
    print('| --- |' + ' ---: |' * (len(ways) + 1))
    for dname in DISTANCES:
        r = [x for x in rows if x['distance'] == dname]
        cells = []
        for n, _, _ in ways:
            cells.append('%d, %.2f' % (np.median([x[n][0] for x in r]),
                                       np.median([x[n][1] for x in r])))
        cells.append('%.2f' % np.median([x['pieces vs in core'] for x in r]))
        print('| %s | %s |' % (dname, ' | '.join(cells)))


if __name__ == '__main__':
    main()
