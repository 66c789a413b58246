"""The triangle budget's trade curve (issue 14): PSNR against triangles for the budget mode,
with both stop rules, beside the tolerance mode and vtkQuadricDecimation, on the same views as
plod_faithful.py's trade curves (mid distance, azimuth 0 and 90, smooth-shaded full-resolution
reference).

    PYTHONPATH=build/lib/python3/dist-packages xvfb-run -a -s "-screen 0 1280x1024x24 -noreset" \\
      /usr/bin/python3 Testing/Quality/plod_budget.py [--models bunny,lucy,generated] [--out docs/results]

- tolerance: T_s = s px, T_b = 4 s, s in 0.25 ... 16 (the default mode);
- budget-stop, budget-skip: the triangle counts the tolerance points draw, as TriangleBudget,
  with a floor of tolerances 16 times finer (T_s = 1/16 px), so that the budget decides which
  cells are refined (in order of error over tolerance) and the tolerances only bound it; the
  first with BUDGET_STOP_AT_FIRST_MISFIT (the walk ends at the first refinement that does not
  fit), the second with BUDGET_SKIP_MISFITS (such refinements are skipped);
- budget-stop@count, budget-skip@count: the same with the budget set to what the tolerance cut
  counts (GetNumberOfBudgetTriangles: without a budget, the triangles its refined cells own,
  back-facing ones and those touching hidden cells included, which the patches do not draw);
- QD: vtkQuadricDecimation of the full mesh to the same count, once per view.
Models: the Stanford bunny and Lucy (a real scan, decimated by a third party: 15,000 triangles)
from the data folder when there (skipped, with a message, when not), and the generated UV sphere.
Columns: `target` the tolerance point's drawn triangles, `budget` the TriangleBudget given,
`triangles` drawn, `budget_triangles` (the selector's count, what the budget bounds), `fill` =
triangles / target, `select_ms` the median of 5 forced selections of that cut.
Nesting (both rules, azimuth 0): 30 budgets from 5 % to 100 % of the count of the tolerance cut
at T_s = 1 px (each 11 % above the previous, floor as above); `coarsened` counts the cells a
budget refines that the next, larger one does not, `changed` the cut entries that change.
Writes <out>/budget.csv and <out>/budget_nesting.csv and prints a table of medians.
--sections incremental: the incremental selection against the full walk on an orbit (11 frames,
3 degrees apart), per frame, in <out>/incremental.csv.
--sections drawn: what a budget draws, estimated and exact (SetExactTriangleBudget), on every
model (the closed ones count the back faces out), far, mid and close, azimuths 0, 90 and 180,
budgets of 5, 10, 25 and 50 % of what the cut at tolerances 1/16 px draws: the triangles drawn,
the selector's count, fill = drawn / budget and the median selection time, in
<out>/budget_drawn.csv, with the range of fills per mode printed.
--sections foveation: screen foveation's factor table against every factor computed (a budget
that does not bind), rates 2 and 8, azimuths 0 and 90: same cut and same image, factors
computed, PSNR, in <out>/foveation_table.csv (exits 1 when a cut differs).
"""
import argparse
import csv
import os
import sys

import numpy as np
from vtkmodules.util.numpy_support import vtk_to_numpy

sys.path.insert(0, os.path.dirname(os.path.abspath(__file__)))

import plod_faithful as pf  # noqa: E402
import plod_scene  # noqa: E402
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
    scene = pf.make_scene(model)
    for az in (0, 90):
        scene.reset_view(az, pf.DISTANCES['mid'])
        ref = scene.render_actor(scene.ref_actor)

        def row(method, target, triangles, img, ms=float('nan'), budget=0):
            rows.append(dict(model=name, azimuth=az, method=method, target=target, budget=budget,
                             triangles=triangles,
                             budget_triangles=scene.selector.GetNumberOfBudgetTriangles()
                             if method != 'QD' else triangles,
                             fill=triangles / target if target else float('nan'), select_ms=ms,
                             psnr=metrics.psnr(pf.lum(ref), pf.lum(img))))
        for scale in scales:
            scene.selector.SetTriangleBudget(0)
            img, tris = scene.render_lod(scale)
            counted = scene.selector.GetNumberOfBudgetTriangles()
            row('tolerance', tris, tris, img, select_ms(scene))
            if tris == 0:
                continue
            for suffix, budget in (('', tris), ('@count', counted)):
                for method, rule in RULES:
                    getattr(scene.selector, 'SetBudgetStopRuleTo' + rule)()
                    scene.selector.SetTriangleBudget(budget)
                    img, btris = scene.render_lod(FLOOR)
                    row(method + suffix, tris, btris, img, select_ms(scene), budget)
            scene.selector.SetTriangleBudget(0)
            qd, qd_tris, _ = plod_scene.decimated(scene.full, tris)
            row('QD', tris, qd_tris, scene.render_data(qd))
    return rows


def nesting(name, model, steps=30):
    """Rows of the nesting measurement (module docstring), one per stop rule."""
    scene = pf.make_scene(model)
    scene.reset_view(0, pf.DISTANCES['mid'])
    scene.selector.SetTriangleBudget(0)
    scene.render_lod(1.0)
    count = scene.selector.GetNumberOfBudgetTriangles()
    parent = vtk_to_numpy(scene.selector.GetOutput().GetNodeData().GetArray('Parent'))

    def cut():
        state = vtk_to_numpy(
            scene.selector.GetOutput().GetNodeData().GetArray('CutState')).copy()
        above = np.zeros(len(state), bool)  # nodes are stored level by level: parents first
        for n in range(len(state)):
            above[n] = state[n] == 0 and (parent[n] < 0 or above[parent[n]])
        return above | (state == 3), state  # refined: above the cut, or an opened leaf
    rows = []
    for method, rule in RULES:
        getattr(scene.selector, 'SetBudgetStopRuleTo' + rule)()
        coarsened = changed = entries = 0
        previous = None
        for budget in np.geomspace(0.05 * count, count, steps).astype(int):
            scene.selector.SetTriangleBudget(int(budget))
            scene.render_lod(FLOOR)
            refined, state = cut()
            if previous is not None:
                coarsened += int((previous[0] & ~refined).sum())
                changed += int((previous[1] != state).sum())
                entries += int((state > 0).sum())
            previous = (refined, state)
        rows.append(dict(model=name, method=method, steps=steps, count=count,
                         coarsened=coarsened, changed=changed, cut_entries=entries))
    scene.selector.SetTriangleBudget(0)
    return rows


def incremental(name, model, steps=11, step_degrees=3.0):
    """Rows of the incremental selection against the full walk on the same orbit: the camera
    reset to the model's bounds, mid distance, turned step_degrees a frame from azimuth 0; each
    frame's PSNR against the smooth-shaded full-resolution image of that view, triangles drawn
    and counted. The incremental selector starts each frame from its previous cut."""
    rows = []
    scenes = {}
    for method in ('full', 'incremental'):
        scene = pf.make_scene(model)
        scene.selector.SetIncrementalSelection(method == 'incremental')
        scenes[method] = scene
    for k in range(steps):
        az = k * step_degrees
        ref = None
        for method, scene in scenes.items():
            scene.reset_view(az, pf.DISTANCES['mid'])
            if ref is None:
                ref = scene.render_actor(scene.ref_actor)
            img, tris = scene.render_lod(1.0)
            rows.append(dict(model=name, frame=k, azimuth=az, method=method, triangles=tris,
                             budget_triangles=scene.selector.GetNumberOfBudgetTriangles(),
                             visited=scene.selector.GetNumberOfVisitedNodes(),
                             psnr=metrics.psnr(pf.lum(ref), pf.lum(img))))
    return rows


def foveation(name, model, rates=(2.0, 8.0), azimuths=(0, 90)):
    """Rows of screen foveation's table on a real model: the camera reset to the model's bounds,
    mid distance, the gaze a little off the view axis; the tolerance walk (factor bounded by
    the table, computed only where a test falls within the bounds) against a budget that does
    not bind (every factor computed): the cuts must be equal node for node, and so their
    images; PSNR against the smooth-shaded full-resolution image of the view."""
    rows = []
    scene = pf.make_scene(model)
    s = scene.selector
    s.SetFoveationModeToScreen()
    for az in azimuths:
        scene.reset_view(az, pf.DISTANCES['mid'])
        camera = scene.renderer.GetActiveCamera()
        gaze = np.array(camera.GetDirectionOfProjection()) + 0.15 * np.array(camera.GetViewUp())
        s.SetGazeDirection(*(gaze / np.linalg.norm(gaze)))
        ref = scene.render_actor(scene.ref_actor)
        for rate in rates:
            s.SetFoveationRate(rate)
            cuts, images = [], []
            for exact in (False, True):
                s.SetTriangleBudget(10 ** 9 if exact else 0)
                img, tris = scene.render_lod(1.0)
                state = vtk_to_numpy(s.GetOutput().GetNodeData().GetArray('CutState')).copy()
                cuts.append(state)
                images.append(img)
                assert not s.GetBudgetWasBinding()
                rows.append(dict(model=name, azimuth=az, rate=rate,
                                 walk='budget (exact)' if exact else 'tolerance (table)',
                                 triangles=tris, visited=s.GetNumberOfVisitedNodes(),
                                 factors=s.GetNumberOfFoveationFactors(),
                                 psnr=metrics.psnr(pf.lum(ref), pf.lum(img))))
            rows[-1]['same_cut'] = rows[-2]['same_cut'] = bool(np.array_equal(*cuts))
            rows[-1]['same_image'] = rows[-2]['same_image'] = bool(np.array_equal(*images))
    s.SetTriangleBudget(0)
    return rows


def drawn(name, model, fractions=(0.05, 0.1, 0.25, 0.5), azimuths=(0, 90, 180)):
    """Rows of the drawn-count measurement (module docstring)."""
    rows = []
    scene = pf.make_scene(model)
    for dname, dolly in pf.DISTANCES.items():
        for az in azimuths:
            scene.reset_view(az, dolly)
            scene.selector.SetTriangleBudget(0)
            scene.selector.ExactTriangleBudgetOff()
            _, full = scene.render_lod(FLOOR)
            hid = scene.selector.GetHidBackFaces()
            for fraction in fractions:
                budget = max(100, int(fraction * full))
                for mode in ('estimated', 'exact'):
                    scene.selector.SetExactTriangleBudget(mode == 'exact')
                    scene.selector.SetTriangleBudget(budget)
                    _, tris = scene.render_lod(FLOOR)
                    rows.append(dict(model=name, closed=int(hid), distance=dname, azimuth=az,
                                     mode=mode, tolerance_drawn=full, budget=budget,
                                     triangles=tris,
                                     budget_triangles=scene.selector.GetNumberOfBudgetTriangles(),
                                     cut_triangles=scene.selector.GetNumberOfCutTriangles(),
                                     fill=tris / budget, select_ms=select_ms(scene)))
            scene.selector.ExactTriangleBudgetOff()
            scene.selector.SetTriangleBudget(0)
    return rows


def write_rows(path, fields, rows):
    """Writes `rows` (dicts) to the CSV file `path` with the columns `fields`."""
    with open(path, 'w', newline='') as f:
        writer = csv.DictWriter(f, fields)
        writer.writeheader()
        writer.writerows(rows)


def main():
    ap = argparse.ArgumentParser()
    ap.add_argument('--out', default='docs/results')
    ap.add_argument('--data', default=pf.DEFAULT_DATA)
    ap.add_argument('--models', default='bunny,lucy,generated')
    ap.add_argument('--sections', default='budget,incremental',
                    help='budget (the trade curves and nesting), incremental (against the full '
                         'walk on an orbit), drawn (what a budget draws, estimated and exact), '
                         'foveation (screen foveation\'s table against the exact factors); the '
                         'others keep their CSV files')
    args = ap.parse_args()
    sections = set(args.sections.split(','))
    wanted = set(args.models.split(','))
    rows, nested = [], []
    models = []
    for key, file in (('bunny', 'bun_zipper.ply'), ('lucy', 'lucy.ply')):
        path = os.path.join(args.data, file)
        if key not in wanted:
            continue
        if os.path.exists(path):
            models.append((key, pf.read_ply(path)))
        else:
            print('%s skipped: %s not found' % (key, path))
    if 'generated' in wanted:
        models.append(('generated', pf.displaced_sphere(400)))
    if 'incremental' in sections:
        inc = []
        for key, model in models:
            inc += incremental(key, model)
        path = os.path.join(args.out, 'incremental.csv')
        write_rows(path, ['model', 'frame', 'azimuth', 'method', 'triangles', 'budget_triangles',
                          'visited', 'psnr'], inc)
        for key, _ in models:
            for method in ('full', 'incremental'):
                r = [x for x in inc if x['model'] == key and x['method'] == method]
                print('%-10s %-12s PSNR %.2f to %.2f dB (mean %.2f), triangles %d to %d' % (
                    key, method, min(x['psnr'] for x in r), max(x['psnr'] for x in r),
                    sum(x['psnr'] for x in r) / len(r), min(x['triangles'] for x in r),
                    max(x['triangles'] for x in r)))
        print('written:', path)
    if 'drawn' in sections:
        rows_drawn = []
        for key, model in models:
            rows_drawn += drawn(key, model)
        path = os.path.join(args.out, 'budget_drawn.csv')
        write_rows(path, ['model', 'closed', 'distance', 'azimuth', 'mode', 'tolerance_drawn',
                          'budget', 'triangles', 'budget_triangles', 'cut_triangles', 'fill',
                          'select_ms'], rows_drawn)
        for key, _ in models:
            for mode in ('estimated', 'exact'):
                r = [x for x in rows_drawn if x['model'] == key and x['mode'] == mode]
                print('%-10s %-9s closed %d: fill %.3f to %.3f (median %.3f), over the budget '
                      '%d of %d, select median %.2f ms' % (
                          key, mode, r[0]['closed'], min(x['fill'] for x in r),
                          max(x['fill'] for x in r), float(np.median([x['fill'] for x in r])),
                          sum(x['triangles'] > x['budget'] for x in r), len(r),
                          float(np.median([x['select_ms'] for x in r]))))
        print('written:', path)
    if 'foveation' in sections:
        fov = []
        for key, model in models:
            fov += foveation(key, model)
        path = os.path.join(args.out, 'foveation_table.csv')
        write_rows(path, ['model', 'azimuth', 'rate', 'walk', 'triangles', 'visited', 'factors',
                          'psnr', 'same_cut', 'same_image'], fov)
        for r in fov:
            print('%(model)-10s az %(azimuth)3d K %(rate)4.1f %(walk)-18s %(triangles)7d tri '
                  '%(visited)7d visited %(factors)7d factors %(psnr)6.2f dB same cut '
                  '%(same_cut)s, same image %(same_image)s' % r)
        if not all(r['same_cut'] and r['same_image'] for r in fov):
            sys.exit('the table\'s cut differs from the exact one')
        print('written:', path)
    if 'budget' not in sections:
        return rows
    for key, model in models:
        rows += measure(key, model)
        nested += nesting(key, model)
    write_rows(os.path.join(args.out, 'budget_nesting.csv'),
               ['model', 'method', 'steps', 'count', 'coarsened', 'changed', 'cut_entries'], nested)
    for r in nested:
        print('%(model)-10s %(method)-12s %(steps)d budgets up to %(count)d: %(coarsened)d cells '
              'coarsened as the budget rose, %(changed)d cut entries changed' % r)
    path = os.path.join(args.out, 'budget.csv')
    write_rows(path, ['model', 'azimuth', 'method', 'target', 'budget', 'triangles',
                      'budget_triangles', 'fill', 'select_ms', 'psnr'], rows)
    methods = ('tolerance', 'budget-stop', 'budget-skip', 'budget-stop@count',
               'budget-skip@count', 'QD')
    print('%-10s %3s %8s | %s' % ('model', 'az', 'target',
                                  ' | '.join('%-30s' % m for m in methods)))
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
