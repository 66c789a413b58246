"""The triangle budget's trade curve (issue 14): PSNR against triangles for the budget mode,
with both stop rules, beside the tolerance mode and vtkQuadricDecimation, on the same views as
plod_faithful.py's trade curves (mid distance, azimuth 0 and 90, smooth-shaded full-resolution
reference).

    PYTHONPATH=build/lib/python3/dist-packages xvfb-run -a -s "-screen 0 1280x1024x24 -noreset" \\
      /usr/bin/python3 Testing/Quality/plod_budget.py [--models bunny,lucy,generated] [--out docs/results]

- tolerance: T_s = s px, T_b = 4 s, s in 0.25 ... 16 (the default mode);
- budget-stop, budget-skip: the same triangle counts as the tolerance points, as TriangleBudget,
  with a floor of tolerances 16 times finer (T_s = 1/16 px), so that the budget decides which
  cells are refined (in order of error over tolerance) and the tolerances only bound it; the
  first with BUDGET_STOP_AT_FIRST_MISFIT (the walk ends at the first refinement that does not
  fit), the second with BUDGET_SKIP_MISFITS (such refinements are skipped);
- QD: vtkQuadricDecimation of the full mesh to the same count, once per view.
Models: the Stanford bunny and Lucy (a real scan, decimated by a third party: 15,000 triangles)
from the data folder when there (skipped, with a message, when not), and the generated UV sphere.
Columns: `triangles` drawn, `budget_triangles` (the selector's count, what the budget bounds),
`fill` = triangles / target, `select_ms` the median of 5 forced selections of that cut.
Writes <out>/budget.csv and prints a table of medians.
"""
import argparse
import csv
import os
import sys

import numpy as np

sys.path.insert(0, os.path.dirname(os.path.abspath(__file__)))

import plod_faithful as pf  # noqa: E402
import plod_metrics as metrics  # noqa: E402

FLOOR = 1.0 / 16


def select_ms(scene, reps=5):
    """Median time of `reps` selections of the current view and settings (forced)."""
    times = []
    for _ in range(reps):
        scene.selector.Modified()
        scene.selector.Update()
        times.append(scene.selector.GetSelectTime() * 1e3)
    return float(np.median(times))


RULES = (('budget-stop', 'StopAtFirstMisfit'), ('budget-skip', 'SkipMisfits'))


def measure(name, model, scales=(0.25, 0.5, 1, 2, 4, 8, 16)):
    """Rows of the four methods at the tolerance mode's counts, both azimuths."""
    rows = []
    scene = pf.Scene(model)
    for az in (0, 90):
        scene.view(az, pf.DISTANCES['mid'])
        ref = scene.render_actor(scene.ref_actor)

        def row(method, target, triangles, img, ms=float('nan')):
            rows.append(dict(model=name, azimuth=az, method=method, target=target,
                             triangles=triangles,
                             budget_triangles=scene.selector.GetNumberOfBudgetTriangles()
                             if method != 'QD' else triangles,
                             fill=triangles / target if target else float('nan'), select_ms=ms,
                             psnr=metrics.psnr(pf.lum(ref), pf.lum(img))))
        for scale in scales:
            scene.selector.SetTriangleBudget(0)
            img, tris = scene.render_lod(scale)
            row('tolerance', tris, tris, img, select_ms(scene))
            if tris == 0:
                continue
            for method, rule in RULES:
                getattr(scene.selector, 'SetBudgetStopRuleTo' + rule)()
                scene.selector.SetTriangleBudget(tris)
                img, btris = scene.render_lod(FLOOR)
                row(method, tris, btris, img, select_ms(scene))
            scene.selector.SetTriangleBudget(0)
            qd, qd_tris = pf.decimated(scene.full, tris)
            row('QD', tris, qd_tris, scene.render_data(qd))
    return rows


def main():
    ap = argparse.ArgumentParser()
    ap.add_argument('--out', default='docs/results')
    ap.add_argument('--data', default=pf.DEFAULT_DATA)
    ap.add_argument('--models', default='bunny,lucy,generated')
    args = ap.parse_args()
    wanted = set(args.models.split(','))
    rows = []
    for key, file in (('bunny', 'bun_zipper.ply'), ('lucy', 'lucy.ply')):
        path = os.path.join(args.data, file)
        if key not in wanted:
            continue
        if os.path.exists(path):
            rows += measure(key, pf.read_ply(path))
        else:
            print('%s skipped: %s not found' % (key, path))
    if 'generated' in wanted:
        rows += measure('generated', pf.displaced_sphere(400))
    path = os.path.join(args.out, 'budget.csv')
    with open(path, 'w', newline='') as f:
        writer = csv.DictWriter(f, ['model', 'azimuth', 'method', 'target', 'triangles',
                                    'budget_triangles', 'fill', 'select_ms', 'psnr'])
        writer.writeheader()
        writer.writerows(rows)
    methods = ('tolerance', 'budget-stop', 'budget-skip', 'QD')
    print('%-10s %3s %8s | %s' % ('model', 'az', 'target',
                                  ' | '.join('%-29s' % m for m in methods)))
    keys = sorted({(r['model'], r['azimuth'], r['target']) for r in rows})
    for key in keys:
        cells = []
        for method in methods:
            r = [x for x in rows if (x['model'], x['azimuth'], x['target']) == key
                 and x['method'] == method]
            cells.append('%7d tri %6.2f dB %6.2f ms' % (r[0]['triangles'], r[0]['psnr'],
                                                       r[0]['select_ms']) if r else '-')
        print('%-10s %3d %8d | %s' % (key[0], key[1], key[2], ' | '.join(cells)))
    print('written:', path)
    return rows


if __name__ == '__main__':
    main()
