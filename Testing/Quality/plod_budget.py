"""The triangle budget's trade curve (issue 14): PSNR against triangles for the budget mode
beside the tolerance mode and vtkQuadricDecimation, on the same views as plod_faithful.py's
trade curves (mid distance, azimuth 0 and 90, smooth-shaded full-resolution reference).

    PYTHONPATH=build/lib/python3/dist-packages xvfb-run -a -s "-screen 0 1280x1024x24 -noreset" \\
      /usr/bin/python3 Testing/Quality/plod_budget.py [--models bunny,generated] [--out docs/results]

- tolerance: T_s = s px, T_b = 4 s, s in 0.25 ... 16 (the default mode);
- budget: the same triangle counts as the tolerance points, as TriangleBudget, with a floor
  of tolerances 16 times finer (T_s = 1/16 px), so that the budget decides which cells are
  refined (in order of error over tolerance) and the tolerances only bound it;
- QD: vtkQuadricDecimation of the full mesh to the same count, once per view.
Writes <out>/budget.csv and prints a table of medians.
"""
import argparse
import csv
import os
import sys

sys.path.insert(0, os.path.dirname(os.path.abspath(__file__)))

import plod_faithful as pf  # noqa: E402
import plod_metrics as metrics  # noqa: E402

FLOOR = 1.0 / 16


def measure(name, model, scales=(0.25, 0.5, 1, 2, 4, 8, 16)):
    """Rows of the three methods at the tolerance mode's counts, both azimuths."""
    rows = []
    scene = pf.Scene(model)
    for az in (0, 90):
        scene.view(az, pf.DISTANCES['mid'])
        ref = scene.render_actor(scene.ref_actor)

        def row(method, target, triangles, img):
            rows.append(dict(model=name, azimuth=az, method=method, target=target,
                             triangles=triangles, psnr=metrics.psnr(pf.lum(ref), pf.lum(img))))
        for scale in scales:
            scene.selector.SetTriangleBudget(0)
            img, tris = scene.render_lod(scale)
            row('tolerance', tris, tris, img)
            if tris == 0:
                continue
            scene.selector.SetTriangleBudget(tris)
            img, btris = scene.render_lod(FLOOR)
            row('budget', tris, btris, img)
            scene.selector.SetTriangleBudget(0)
            qd, qd_tris = pf.decimated(scene.full, tris)
            row('QD', tris, qd_tris, scene.render_data(qd))
    return rows


def main():
    ap = argparse.ArgumentParser()
    ap.add_argument('--out', default='docs/results')
    ap.add_argument('--data', default=pf.DEFAULT_DATA)
    ap.add_argument('--models', default='bunny,generated')
    args = ap.parse_args()
    wanted = set(args.models.split(','))
    rows = []
    bunny = os.path.join(args.data, 'bun_zipper.ply')
    if 'bunny' in wanted:
        if os.path.exists(bunny):
            rows += measure('bunny', pf.read_ply(bunny))
        else:
            print('bunny skipped: %s not found' % bunny)
    if 'generated' in wanted:
        rows += measure('generated', pf.displaced_sphere(400))
    path = os.path.join(args.out, 'budget.csv')
    with open(path, 'w', newline='') as f:
        writer = csv.DictWriter(f, ['model', 'azimuth', 'method', 'target', 'triangles', 'psnr'])
        writer.writeheader()
        writer.writerows(rows)
    print('%-10s %3s %8s | %-22s | %-22s | %-22s' % ('model', 'az', 'target', 'tolerance',
                                                     'budget', 'QD'))
    keys = sorted({(r['model'], r['azimuth'], r['target']) for r in rows})
    for key in keys:
        cells = []
        for method in ('tolerance', 'budget', 'QD'):
            r = [x for x in rows if (x['model'], x['azimuth'], x['target']) == key
                 and x['method'] == method]
            cells.append('%7d tri %6.2f dB' % (r[0]['triangles'], r[0]['psnr']) if r else '-')
        print('%-10s %3d %8d | %s' % (key[0], key[1], key[2], ' | '.join(cells)))
    print('written:', path)


if __name__ == '__main__':
    main()
