"""SRCC against its baselines, examined (issue 27): SRCC, SCVC and PSEC at equal drawn
triangles, judged by PSNR, SSIM, Zhu's perceptual metric and an outline error, with an ablation
of SRCC's terms.

    PYTHONPATH=build/lib/python3/dist-packages nice -n 10 \\
      xvfb-run -a -s "-screen 0 1280x1024x24 -noreset" \\
      /usr/bin/python3 Testing/Quality/plod_srcc.py [--out docs/results] \\
      [--models bunny,lucy,lucy-dense,generated,thin-parts] [--distances far,mid,close] \\
      [--azimuths 0,45,...,315] [--quick]

(about 9 minutes on 2 shared cores for the defaults; docs/results/srcc_examination.md).

Protocol (plod_faithful.py's scene, a plod_scene.Scene: 640x480, view angle 30 degrees, headlight, the grey actor
(colour 0.8, diffuse 0.9, specular 0.3, power 20) on a pure blue background, the selector fed
through vtkPerceptualLODRenderBinding, so it sees the actor's material; the reference is the
full-resolution mesh, smooth-shaded):
- models: the Stanford bunny (bun_zipper.ply) and Lucy (lucy.ply) from the data folder when
  there (skipped with a message when not), Lucy Loop-subdivided twice (lucy-dense,
  pf.subdivided), the generated closed displaced sphere (pf.displaced_sphere(GEN_RES)) and the
  generated body with thin parts (pf.thin_parts_model(THIN_RES));
- views: far, mid, close (pf.DISTANCES) at the harness's 8 azimuths (pf.AZIMUTHS);
- triangle counts per view: what SRCC's tolerance cut draws (no budget) at its default
  tolerances scaled by 1, 2 and 4 (T_s = 1, 2, 4 px, T_b = 4 T_s): three counts that SRCC itself
  would choose for that view, from fine to coarse;
- every mode is then drawn at each count with SetExactTriangleBudget on and the tolerances 16
  times finer as a floor (T_s = 1/16 px, T_b = 1/4: plod_budget.py's FLOOR), so that the budget
  decides what is refined, in the order of each mode's own priority, and no mode draws more
  than the count (the drawn counts are recorded: `triangles`, `fill` = triangles / target);
- scores against the reference of the same view: PSNR of 8-bit luminance, SSIM
  (plod_metrics.ssim), Zhu's perceptual metric as an error, pm_err = |VPs(LOD) - VPs(ref)| /
  TPs(ref) (plod_metrics.perceptual_metric, 16 pixels per degree; the difference of the visible
  detail fraction, in units of the reference's object pixels), and the outline error:
  outline_px = pixels of the reference's object mask that are background in the LOD image
  (missed) plus pixels background in the reference that the LOD covers (added), object masks
  from the background colour; outline_rel = outline_px / the reference silhouette's perimeter
  (its object pixels with a 4-neighbour of background colour, pixels outside the image not
  counted), i.e. the mean outline displacement in pixels along the outline. Missed pixels
  include see-through holes inside the silhouette. Undefined (NaN, left out of the medians)
  when the reference covers the whole frame (no perimeter).
Ablation (SRCC, same counts, same floor, one switch at a time): T_b = T_s / 4, T_s, 2 T_s,
16 T_s (srcc-tb0.25, -tb1, -tb2, -tb16), T_b = 1e6 (contour only, srcc-tbinf), topology rule off
(TopologyTolerance 1e6, srcc-topo-off); the material: SRCC, SCVC and PSEC again with a specular
actor (colour 0.8, diffuse 0.6, specular 0.9, power 60; the reference too), variants *-spec.
The contour band and the size floor have no setting on the selector and are not switched.
srcc-tol is SRCC's tolerance cut itself (no budget), for reference. An ablation cell counts
only where the variant drew at least MIN_FILL of the count (contour only draws less where its
floor cut is smaller than the count).

Writes <out>/srcc_examination.csv and prints the summary tables (medians over azimuths and
counts; margin = SRCC minus the better of SCVC and PSEC in each view and count, positive when
SRCC is better: for the error metrics the sign is turned).
"""
import argparse
import csv
import os
import sys
import time

import numpy as np

sys.path.insert(0, os.path.dirname(os.path.abspath(__file__)))

import plod_faithful as pf  # noqa: E402
import plod_metrics as metrics  # noqa: E402
import plod_scene  # noqa: E402

FLOOR = 1.0 / 16
SCALES = (1, 2, 4)
GEN_RES = 400
THIN_RES = 300
BG_LUM = float(metrics.luminance(np.array([[[0, 0, 255]]]))[0, 0])
PPD = metrics.pixels_per_degree(30.0, pf.SIZE[1])
SPECULAR = dict(diffuse=0.6, specular=0.9, power=60.0)
GREY = plod_scene.GREY  # the harness's material
HUGE = 1e6


def _preset_ratio():
    """T_b / T_s of the selector's defaults (the papers' preset: one home, the kernel's)."""
    from perceptual_lod import vtkPerceptualLODSelector
    s = vtkPerceptualLODSelector()
    return s.GetBrightnessTolerance() / s.GetContourTolerance()


PRESET = _preset_ratio()

# metric -> True when higher is better
METRICS = (('psnr', True), ('ssim', True), ('pm_err', False), ('outline_rel', False))
# ablation variants of SRCC: (name, T_b / T_s, topology tolerance or None for the default)
ABLATION = (('srcc-tb0.25', 0.25, None), ('srcc-tb1', 1.0, None), ('srcc-tb2', 2.0, None),
            ('srcc-tb16', 16.0, None), ('srcc-tbinf', None, None), ('srcc-topo-off', PRESET, HUGE))
MIN_FILL = 0.95  # an ablation cell counts only when the variant drew at least this share
MODES = {'srcc': 'SRCC', 'scvc': 'SCVC', 'psec': 'PSEC'}

FIELDS = ['model', 'distance', 'azimuth', 'scale', 'target', 'variant', 'mode', 'material',
          'ts', 'tb', 'topology', 'budget', 'triangles', 'fill', 'binding', 'psnr', 'ssim', 'pm',
          'pm_ref', 'pm_err', 'missed', 'added', 'outline_px', 'perimeter', 'ref_area',
          'outline_rel', 'seconds']


def set_material(scene, m):
    for actor in (scene.lod_actor, scene.ref_actor):
        plod_scene.set_material(actor, m['diffuse'], m['specular'], m['power'])


def render(scene, mode, ts, tb, topology, budget):
    """The LOD image with everything set explicitly: mode, tolerances, topology tolerance, and
    an exact budget (0: the tolerance cut)."""
    s = scene.selector
    getattr(s, 'SetErrorModelTo' + MODES[mode])()
    s.SetContourTolerance(ts)
    s.SetBrightnessTolerance(tb)
    s.SetTopologyTolerance(topology)
    s.SetExactTriangleBudget(budget > 0)
    s.SetTriangleBudget(budget)
    return scene.render_cut()


class Reference:
    """The reference image of a view and what the scores need of it."""

    def __init__(self, img):
        self.img = img
        self.lum = pf.lum(img)
        self.mask = ~pf.is_background(img)
        self.area = int(self.mask.sum())
        bg = ~self.mask
        edge = np.zeros_like(self.mask)
        edge[1:] |= bg[:-1]
        edge[:-1] |= bg[1:]
        edge[:, 1:] |= bg[:, :-1]
        edge[:, :-1] |= bg[:, 1:]
        self.perimeter = int((self.mask & edge).sum())
        _, self.vps, self.tps = metrics.perceptual_metric(self.lum, BG_LUM, PPD)
        self.pm = self.vps / max(1, self.tps)


def score(ref, img):
    lum = pf.lum(img)
    mask = ~pf.is_background(img)
    missed = int((ref.mask & ~mask).sum())
    added = int((~ref.mask & mask).sum())
    _, vps, _ = metrics.perceptual_metric(lum, BG_LUM, PPD)
    return dict(psnr=metrics.psnr(ref.lum, lum), ssim=metrics.ssim(ref.lum, lum),
                pm=vps / max(1, ref.tps), pm_ref=ref.pm,
                pm_err=abs(vps - ref.vps) / max(1, ref.tps), missed=missed, added=added,
                outline_px=missed + added, perimeter=ref.perimeter, ref_area=ref.area,
                outline_rel=(missed + added) / ref.perimeter if ref.perimeter else float('nan'))


def measure(name, model, writer, distances, azimuths, scales):
    rows = []
    scene = pf.make_scene(model)
    s = scene.selector
    topo_default = s.GetTopologyTolerance()
    print('%s: %d triangles, octree built in %.1f s, default T_s %g T_b %g topology %g' % (
        name, model.GetNumberOfPolys(), scene.build_s, s.GetContourTolerance(),
        s.GetBrightnessTolerance(), topo_default), flush=True)

    for dname in distances:
        for az in azimuths:
            scene.reset_view(az, pf.DISTANCES[dname])
            set_material(scene, GREY)
            ref = Reference(scene.render_actor(scene.ref_actor))
            targets = []
            for scale in scales:
                t0 = time.perf_counter()
                img, tris = render(scene, 'srcc', scale, PRESET * scale, topo_default, 0)
                targets.append((scale, tris))
                rows.append(dict(variant='srcc-tol', mode='SRCC', material='grey', ts=scale,
                                 tb=PRESET * scale, topology=topo_default, budget=0, scale=scale,
                                 target=tris, triangles=tris, fill=1.0, binding=0,
                                 seconds=time.perf_counter() - t0, **score(ref, img)))
                rows[-1].update(model=name, distance=dname, azimuth=az)
                writer.writerow(rows[-1])
            jobs = [(v, v.upper(), PRESET, topo_default) for v in ('srcc', 'scvc', 'psec')]
            jobs += [(v, 'SRCC', ratio, topo if topo is not None else topo_default)
                     for v, ratio, topo in ABLATION]
            for material in ('grey', 'specular'):
                if material == 'specular':
                    set_material(scene, SPECULAR)
                    ref = Reference(scene.render_actor(scene.ref_actor))
                    jobs = [(v + '-spec', v.upper(), PRESET, topo_default)
                            for v in ('srcc', 'scvc', 'psec')]
                for scale, target in targets:
                    if target <= 0:
                        continue
                    for variant, mode, ratio, topo in jobs:
                        tb = HUGE if ratio is None else ratio * FLOOR
                        t0 = time.perf_counter()
                        img, tris = render(scene, mode.lower(), FLOOR, tb, topo, target)
                        row = dict(model=name, distance=dname, azimuth=az, scale=scale,
                                   target=target, variant=variant, mode=mode, material=material,
                                   ts=FLOOR, tb=tb, topology=topo, budget=target,
                                   triangles=tris, fill=tris / target,
                                   binding=int(s.GetBudgetWasBinding()),
                                   seconds=time.perf_counter() - t0)
                        row.update(score(ref, img))
                        writer.writerow(row)
                        rows.append(row)
            set_material(scene, GREY)
            done = [r for r in rows if r['distance'] == dname and r['azimuth'] == az]
            print('  %-5s az %3d targets %s: %d images, %.1f s' % (
                dname, az, [t for _, t in targets], len(done),
                sum(r['seconds'] for r in done)), flush=True)
            for scale, target in targets:
                cell = {r['variant']: r for r in done if r['target'] == target}
                print('    x%d %6d tri | ' % (scale, target) + ' | '.join(
                    '%s %d %.2fdB %.4f pm%.3f ol%.2f' % (
                        v, cell[v]['triangles'], cell[v]['psnr'], cell[v]['ssim'],
                        cell[v]['pm_err'], cell[v]['outline_rel'])
                    for v in ('srcc', 'scvc', 'psec') if v in cell), flush=True)
    return rows


# ---- summary --------------------------------------------------------------------------------

def cells(rows):
    """{(model, distance, azimuth, scale): {variant: row}} for the budget rows."""
    out = {}
    for r in rows:
        if r['budget'] > 0:
            out.setdefault((r['model'], r['distance'], r['azimuth'], r['scale']), {})[
                r['variant']] = r
    return out


def advantage(a, b, metric, higher):
    """How much a is better than b by the metric (positive: a better; NaN when undefined)."""
    return a[metric] - b[metric] if higher else b[metric] - a[metric]


def better_baseline(cell, metric, higher, suffix=''):
    c, p = cell['scvc' + suffix], cell['psec' + suffix]
    return c if advantage(c, p, metric, higher) >= 0 else p


def margin(cell, metric, higher, variant='srcc', suffix=''):
    """A variant's advantage over the better of SCVC and PSEC in one cell."""
    return advantage(cell[variant + suffix], better_baseline(cell, metric, higher, suffix),
                     metric, higher)


def med(values):
    values = [v for v in values if v == v]
    return float(np.median(values)) if values else float('nan')


def fmt(metric, v, sign=True):
    if v != v:
        return '-'
    f = {'psnr': '%.2f', 'ssim': '%.4f', 'pm_err': '%.4f', 'outline_rel': '%.3f'}[metric]
    return (f.replace('%', '%+') if sign else f) % v


def variant_cells(sel, variant):
    """The cells where the variant drew at least MIN_FILL of the target (equal triangles)."""
    return [c for c in sel if c[variant]['fill'] >= MIN_FILL]


def summary(rows, models, distances):
    cs = cells(rows)
    lines = []
    lines += ['## SRCC, SCVC and PSEC at equal drawn triangles (grey material)', '',
              'Medians over the azimuths and the three counts of each view. `margin`: median '
              'over those cells of SRCC minus the better of SCVC and PSEC in that cell '
              '(positive: SRCC better; pm_err and outline_rel are errors, their sign is '
              'turned); `wins`: cells where SRCC is at least as good as both; `best`: the best '
              'median ("tie" when equal).', '',
              '| model | distance | metric | SRCC | SCVC | PSEC | best | margin | wins |',
              '| --- | --- | --- | ---: | ---: | ---: | --- | ---: | ---: |']
    for m in models:
        for d in distances:
            sel = [c for k, c in cs.items() if k[0] == m and k[1] == d and 'psec' in c]
            if not sel:
                continue
            for metric, higher in METRICS:
                md = {v: med([c[v][metric] for c in sel]) for v in ('srcc', 'scvc', 'psec')}
                if any(x != x for x in md.values()):
                    best = '-'
                else:
                    top = (max if higher else min)(md.values())
                    winners = [MODES[v] for v in md if md[v] == top]
                    best = winners[0] if len(winners) == 1 else 'tie'
                mg = [x for x in (margin(c, metric, higher) for c in sel) if x == x]
                lines.append('| %s | %s | %s | %s | %s | %s | %s | %s | %d/%d |' % (
                    m, d, metric, fmt(metric, md['srcc'], False),
                    fmt(metric, md['scvc'], False), fmt(metric, md['psec'], False), best,
                    fmt(metric, med(mg)), sum(x >= 0 for x in mg), len(mg)))
    # compact: the PSNR and outline margins per model and distance
    lines += ['', '## Margin of SRCC to the better baseline, compact (median over cells)', '',
              '| model | distance | PSNR (dB) | SSIM | pm_err | outline_rel |',
              '| --- | --- | ---: | ---: | ---: | ---: |']
    for m in models:
        for d in distances:
            sel = [c for k, c in cs.items() if k[0] == m and k[1] == d and 'psec' in c]
            if sel:
                lines.append('| %s | %s | %s |' % (m, d, ' | '.join(
                    fmt(metric, med([margin(c, metric, higher) for c in sel]))
                    for metric, higher in METRICS)))
    # drawn counts
    lines += ['', '## Drawn triangles (fill = drawn / target, all budget rows)', '',
              '| variant | fill min | fill median | fill max | over target | below %.2f |'
              % MIN_FILL, '| --- | ---: | ---: | ---: | ---: | ---: |']
    variants = []
    for r in rows:
        if r['budget'] > 0 and r['variant'] not in variants:
            variants.append(r['variant'])
    for v in variants:
        f = [r['fill'] for r in rows if r['variant'] == v and r['budget'] > 0]
        lines.append('| %s | %.3f | %.3f | %.3f | %d | %d |' % (
            v, min(f), float(np.median(f)), max(f), sum(x > 1 for x in f),
            sum(x < MIN_FILL for x in f)))
    # ablation, per model
    abl = [a[0] for a in ABLATION] + ['srcc-spec']
    lines += ['', '## Ablation: one switch of SRCC at a time, same counts (all distances)', '',
              'Per metric: `change` = median over the cells of the variant minus default SRCC '
              '(positive = better); `margin` = median of the variant minus the better of SCVC '
              'and PSEC in the same cell. Cells where the variant drew less than %d %% of the '
              'count are left out (`n` = cells kept). srcc-spec: SRCC, SCVC, PSEC and the '
              'reference all with the specular material, so only its margin compares (against '
              'SCVC and PSEC with that material). First row per model: default SRCC.'
              % (100 * MIN_FILL), '',
              '| model | variant | n | ' + ' | '.join(
                  '%s change | %s margin' % (m, m) for m, _ in METRICS) + ' |',
              '| --- | --- | ---: | ' + ' | '.join('---: | ---:' for _ in METRICS) + ' |']
    moves = {}
    for m in models:
        sel = [c for k, c in cs.items() if k[0] == m and 'psec' in c]
        if not sel:
            continue
        lines.append('| %s | srcc (default) | %d | %s |' % (m, len(sel), ' | '.join(
            '- | %s' % fmt(metric, med([margin(c, metric, higher) for c in sel]))
            for metric, higher in METRICS)))
        for variant in abl:
            kept = variant_cells(sel, variant)
            cellsout = []
            for metric, higher in METRICS:
                base = med([margin(c, metric, higher) for c in kept])
                if variant == 'srcc-spec':
                    ch = float('nan')
                    mg = med([margin(c, metric, higher, 'srcc', '-spec') for c in kept])
                else:
                    ch = med([advantage(c[variant], c['srcc'], metric, higher) for c in kept])
                    mg = med([margin(c, metric, higher, variant) for c in kept])
                moves.setdefault((m, metric), []).append((variant, mg - base, ch))
                cellsout.append('%s | %s' % (fmt(metric, ch), fmt(metric, mg)))
            lines.append('| %s | %s | %d | %s |' % (m, variant, len(kept), ' | '.join(cellsout)))
    # ablation per distance: margins
    for metric, higher in METRICS:
        lines += ['', '## Ablation by distance: margin to the better baseline, %s' % metric, '',
                  '| model | distance | srcc | ' + ' | '.join(abl) + ' |',
                  '| --- | --- | ---: | ' + ' | '.join('---:' for _ in abl) + ' |']
        for m in models:
            for d in distances:
                sel = [c for k, c in cs.items() if k[0] == m and k[1] == d and 'psec' in c]
                if not sel:
                    continue
                out = [fmt(metric, med([margin(c, metric, higher) for c in sel]))]
                for variant in abl:
                    kept = variant_cells(sel, variant)
                    if variant == 'srcc-spec':
                        v = med([margin(c, metric, higher, 'srcc', '-spec') for c in kept])
                    else:
                        v = med([margin(c, metric, higher, variant) for c in kept])
                    out.append(fmt(metric, v) + ('' if len(kept) == len(sel) else
                                                 ' (%d/%d)' % (len(kept), len(sel))))
                lines.append('| %s | %s | %s |' % (m, d, ' | '.join(out)))
    lines += ['', '## Which switch moves SRCC\'s margin most (all distances)', '',
              '| model | metric | switch | change of margin |', '| --- | --- | --- | ---: |']
    for (m, metric), lst in moves.items():
        lst = [x for x in lst if x[1] == x[1]]
        if lst:
            v, dm, _ = max(lst, key=lambda x: abs(x[1]))
            lines.append('| %s | %s | %s | %s |' % (m, metric, v, fmt(metric, dm)))
    return lines


def main():
    ap = argparse.ArgumentParser()
    ap.add_argument('--out', default='docs/results')
    ap.add_argument('--data', default=pf.DEFAULT_DATA)
    ap.add_argument('--models', default='bunny,lucy,lucy-dense,generated,thin-parts')
    ap.add_argument('--distances', default='far,mid,close')
    ap.add_argument('--azimuths', default=','.join(str(a) for a in pf.AZIMUTHS))
    ap.add_argument('--quick', action='store_true',
                    help='a small generated model, mid distance, azimuth 0 (a smoke test)')
    args = ap.parse_args()
    wanted = args.models.split(',')
    distances = args.distances.split(',')
    azimuths = [int(a) for a in args.azimuths.split(',')]
    models = []
    if args.quick:
        models = [('generated-small', pf.displaced_sphere(80))]
        distances, azimuths = ['mid'], (0,)
    else:
        for key, file in (('bunny', 'bun_zipper.ply'), ('lucy', 'lucy.ply'),
                          ('lucy-dense', 'lucy.ply')):
            path = os.path.join(args.data, file)
            if key not in wanted:
                continue
            if not os.path.exists(path):
                print('%s skipped: %s not found' % (key, path))
            elif key == 'lucy-dense':  # Lucy Loop-subdivided twice (plod_faithful's)
                models.append((key, pf.subdivided(pf.read_ply(path))))
            else:
                models.append((key, pf.read_ply(path)))
        if 'generated' in wanted:
            models.append(('generated', pf.displaced_sphere(GEN_RES)))
        if 'thin-parts' in wanted:
            models.append(('thin-parts', pf.thin_parts_model(THIN_RES)))
    os.makedirs(args.out, exist_ok=True)
    path = os.path.join(args.out, 'srcc_examination%s.csv' % ('_quick' if args.quick else ''))
    t0 = time.perf_counter()
    rows = []
    with open(path, 'w', newline='') as f:
        writer = csv.DictWriter(f, FIELDS)
        writer.writeheader()
        for key, model in models:
            rows += measure(key, model, writer, distances, azimuths, SCALES)
            f.flush()
    lines = summary(rows, [k for k, _ in models], distances)
    print('\n'.join(lines))
    print('written: %s (%d rows), %.0f s' % (path, len(rows), time.perf_counter() - t0))


if __name__ == '__main__':
    main()
