"""TMM against IPV and DPV on the moving protocol, examined (issue 27): which term decides the
order of TMM Table 2 (TMM > IPV > DPV in mean PSNR of moving images), at equal drawn triangles
and at the time-matched calibration of TMM §5.2, with one switch at a time.

    PYTHONPATH=build/lib/python3/dist-packages nice -n 10 \\
      xvfb-run -a -s "-screen 0 1280x1024x24 -noreset" \\
      /usr/bin/python3 Testing/Quality/plod_tmm.py [--out docs/results] \\
      [--models bunny,generated,lucy] [--motions T,R] [--speeds 0.5,1,2] [--dts 30,60] \\
      [--instants 12] [--calib-steps 6] [--quick]

Builds on plod_scene.py's Scene (640x480, view angle 30 degrees, one
headlight, grey material colour 0.8 / diffuse 0.9 / specular 0.3 / power 20, the selector fed
through vtkPerceptualLODRenderBinding on a simulated clock: start_clock / at) and on
plod_measure.py (imported as pm): its methods
(pm.METHODS: TMM = SRCC + MicroMotion; IPV, DPV = velocity alone, TMM §5.3's form; IPV-SRCC,
DPV-SRCC = SRCC's tolerances times the speed factor), its movements (pm.movement: T, a sine
translation of 0.6 radii amplitude and 2 s period; R, a rotation of 90 degrees per second about
the vertical axis) and its time-matched lag protocol (pm.moving). Viewing distance 1.5 d_1 as
plod_measure's moving sections.

- speed: the movement run `speed` times faster (pm.movement at time speed * t: the same path,
  speed times the screen velocity); speed 1 is plod_measure's movement.
- display instants k dt, k = 0..N; every image is compared with the full-resolution image of
  the same instant (smooth-shaded mesh): PSNR of 8-bit luminance and SSIM (plod_metrics).

Two protocols per model x motion x speed x dt (a "cell"):
1. calibrated (`protocol` = time): pm.moving, frames back to back from a pre-roll before the
   first instant, each showing the scene as it was when its work (select + patch + render,
   measured wall time) began. TMM and SRCC at their tolerances (T_s = 1 px, T_b = 4); IPV, DPV,
   IPV-SRCC and DPV-SRCC with their speed constant chosen by bisection (CALIB_STEPS steps in log
   scale over 0.05..2000 px per frame) so that their mean frame time equals TMM's (TMM §5.2, as
   pm.moving_protocol does; per cell). The wall-clock frame times are measured on 2 cores shared
   with builds: they are noisy, and `mean_frame_ms` says how close each calibration came.
2. equal drawn triangles (`protocol` = triangles): the display-rate schedule of
   pm.moving_at_budget (the frame shown at k dt is selected and drawn for the scene at
   (k - 1) dt, motion measured over dt, so no method gains or loses by its frame time). The
   target B is TMM's mean drawn count at its tolerance on that schedule; every mode then draws
   each frame with SetExactTriangleBudget(B) (fraction 1) and B/2 (fraction 0.5), its
   tolerances 16 times finer as a floor (T_s = 1/16 px, T_b = 1/4: plod_budget.py's FLOOR), so
   that the budget decides what is refined, in each mode's own priority order. IPV and DPV keep
   the constants calibrated in protocol 1 for the same cell. `fill` = drawn / budget per frame
   (mean, min); a velocity factor can lift the floor above the budget (fill < 1: that mode drew
   fewer triangles).
Modes: TMM, SRCC (TMM without its motion reduction), IPV, DPV, IPV-SRCC, DPV-SRCC.

Switches (one at a time, same cells): TMM's micro-motion reduction off (TMM -> SRCC); IPV's and
DPV's velocity criterion Alone -> ScalesErrorModel; the protocol (time-matched -> equal
triangles); the budget (B -> B/2); the speed; dt.

Writes <out>/tmm_examination.csv (one row per cell, protocol, budget fraction and mode) and
<out>/tmm_examination.md (the tables).
"""
import argparse
import csv
import math
import os
import sys
import time

import numpy as np

sys.path.insert(0, os.path.dirname(os.path.abspath(__file__)))

import plod_measure as pm  # noqa: E402
import plod_metrics as metrics  # noqa: E402
import plod_scene  # noqa: E402

FLOOR = pm.BUDGET_FLOOR  # 1/16: plod_budget.py's FLOOR
MODES = ('TMM', 'SRCC', 'IPV', 'DPV', 'IPV-SRCC', 'DPV-SRCC')
# at equal triangles also SIZE: velocity alone without its speed factor (IPV with constant 1e9):
# the order in which IPV and DPV refine under a budget (projected cell size), whatever the speed
VELOCITY = pm.VELOCITY_METHODS  # IPV, DPV, IPV-SRCC, DPV-SRCC
PAPER = ('TMM', 'IPV', 'DPV')       # TMM Table 2's three, velocity alone (TMM §5.3's form)
SCALED = ('TMM', 'IPV-SRCC', 'DPV-SRCC')
FRACTIONS = (1.0, 0.5)
GEN_RES = 400  # plod_scene.generated_model(400): a closed displaced sphere of 318,400 triangles

FIELDS = ['model', 'motion', 'speed', 'dt', 'protocol', 'fraction', 'budget', 'mode', 'constant',
          'mean_psnr', 'std_psnr', 'mean_ssim', 'mean_triangles', 'mean_frame_ms', 'fill_mean',
          'fill_min', 'over_budget_frames', 'pixels_per_frame', 'seconds']


class Collector:
    """A frame_writer for pm.moving: keeps the per-instant PSNR and SSIM."""

    def __init__(self):
        self.rows = []

    def writerow(self, row):
        self.rows.append(row)


MOVEMENT = pm.movement  # plod_measure's, kept: run_time_matched swaps pm.movement for a run


def scaled_movement(kind, speed):
    def at(scene, t, distance):
        return MOVEMENT(scene, kind, speed * t, distance)
    return at


def references(scene, move, dt, distance, instants):
    refs = []
    for k in range(instants + 1):
        offset, angle, dist = move(scene, k * dt, distance)
        scene.set_view(dist, offset, angle)
        refs.append(scene.render(scene.full)[0])
    return refs


def run_time_matched(scene, name, move, dt, distance, instants, refs, speed=None, full=False,
                     preroll=0.25):
    """pm.moving with the scaled movement (pm.movement is looked up at call time, so it is
    swapped for the run). Returns (mean PSNR, std, mean frame ms, mean triangles, mean SSIM)."""
    saved = pm.movement
    pm.movement = lambda sc, kind, t, d: move(sc, t, d)
    try:
        col = Collector() if full else None
        p, ms, tris, sd = pm.moving(scene, name, 'X', dt, distance, instants, refs, speed=speed,
                                    frame_writer=col, preroll=preroll)
    finally:
        pm.movement = saved
    ssim = float(np.mean([r['ssim'] for r in col.rows])) if full else float('nan')
    return p, sd, ms, tris, ssim


def calibrate(scene, name, move, dt, distance, instants, refs, target_ms, steps, preroll):
    lo, hi = 0.05, 2000.0
    best = None
    for _ in range(steps):
        mid = math.sqrt(lo * hi)
        r = run_time_matched(scene, name, move, dt, distance, instants, refs, speed=mid,
                             preroll=preroll)
        if best is None or abs(r[2] - target_ms) < abs(best[0] - target_ms):
            best = (r[2], mid)
        if r[2] > target_ms:  # too slow: more reduction, a smaller constant
            hi = mid
        else:
            lo = mid
    return best[1]


def run_display_rate(scene, name, move, dt, distance, instants, refs, budget, speed=None):
    """pm.moving_at_budget's schedule with an exact budget (0: the papers' tolerances, no
    budget) and SSIM. Returns a dict of the figures."""
    s = scene.selector
    if name == 'SIZE':  # velocity alone with no speed factor: IPV's order, constant 1e9
        name, speed = 'IPV', 1e9
    pm.set_method(scene, name, FLOOR if budget else 1.0)
    if speed is not None:
        pm.set_velocity_constant(scene, name, speed)
    s.SetFrameInterval(dt)
    s.SetExactTriangleBudget(budget > 0)
    s.SetTriangleBudget(budget)
    offset, angle, dist = move(scene, -2 * dt, distance)
    scene.start_clock()
    scene.at(-2 * dt)
    scene.set_view(dist, offset, angle)
    ps, ss, tris, times, pix = [], [], [], [], []
    for k in range(instants + 1):
        offset, angle, dist = move(scene, (k - 1) * dt, distance)
        scene.at((k - 1) * dt)
        scene.set_view(dist, offset, angle)
        data, t, sel, pat = scene.lod()
        img, rms = scene.render(data)
        ps.append(metrics.psnr(refs[k], img))
        ss.append(metrics.ssim(refs[k], img))
        tris.append(t)
        times.append(sel + pat + rms)
        pix.append(s.GetObjectSpeed())
    s.SetTriangleBudget(0)
    s.SetExactTriangleBudget(False)
    finite = [v for v in ps if math.isfinite(v)]
    fills = [t / budget for t in tris] if budget else [1.0]
    return dict(mean_psnr=float(np.mean(finite)), std_psnr=float(np.std(finite)),
                mean_ssim=float(np.mean(ss)), mean_triangles=float(np.mean(tris)),
                mean_frame_ms=float(np.mean(times)), fill_mean=float(np.mean(fills)),
                fill_min=float(np.min(fills)),
                over_budget_frames=int(sum(t > budget for t in tris)) if budget else 0,
                pixels_per_frame=float(np.mean(pix)))


def measure(name, scene, writer, motions, speeds, dts, instants, steps, preroll, started):
    rows = []
    distance = 1.5 * scene.radius / math.sin(math.radians(scene.view_angle) / 2)
    for kind in motions:
        for speed in speeds:
            move = scaled_movement(kind, speed)
            for dt in dts:
                t0 = time.perf_counter()
                refs = references(scene, move, dt, distance, instants)
                base = dict(model=name, motion=kind, speed=speed, dt=dt)

                def emit(protocol, fraction, budget, mode, constant, fig, t1):
                    row = dict(base, protocol=protocol, fraction=fraction, budget=budget,
                               mode=mode, constant=constant,
                               seconds=time.perf_counter() - t1, **fig)
                    writer.writerow(row)
                    rows.append(row)
                # 1. time-matched (TMM §5.2)
                consts = {}
                for mode in ('TMM', 'SRCC'):
                    t1 = time.perf_counter()
                    p, sd, ms, tris, ss = run_time_matched(scene, mode, move, dt, distance,
                                                           instants, refs, full=True,
                                                           preroll=preroll)
                    if mode == 'TMM':
                        target = ms
                    emit('time', float('nan'), 0, mode, float('nan'),
                         dict(mean_psnr=p, std_psnr=sd, mean_ssim=ss, mean_triangles=tris,
                              mean_frame_ms=ms), t1)
                for mode in VELOCITY:
                    t1 = time.perf_counter()
                    c = calibrate(scene, mode, move, dt, distance, instants, refs, target, steps,
                                  preroll)
                    consts[mode] = c
                    p, sd, ms, tris, ss = run_time_matched(scene, mode, move, dt, distance,
                                                           instants, refs, speed=c, full=True,
                                                           preroll=preroll)
                    emit('time', float('nan'), 0, mode, c,
                         dict(mean_psnr=p, std_psnr=sd, mean_ssim=ss, mean_triangles=tris,
                              mean_frame_ms=ms), t1)
                # 2. equal drawn triangles on the display-rate schedule
                t1 = time.perf_counter()
                tol = run_display_rate(scene, 'TMM', move, dt, distance, instants, refs, 0)
                emit('tolerance', float('nan'), 0, 'TMM', float('nan'), tol, t1)
                for fraction in FRACTIONS:
                    budget = max(1, int(round(fraction * tol['mean_triangles'])))
                    for mode in MODES + ('SIZE',):
                        t1 = time.perf_counter()
                        fig = run_display_rate(scene, mode, move, dt, distance, instants, refs,
                                               budget, speed=consts.get(mode))
                        emit('triangles', fraction, budget, mode,
                             consts.get(mode, float('nan')), fig, t1)
                cell = [r for r in rows if r['motion'] == kind and r['speed'] == speed
                        and r['dt'] == dt]
                print('[%5.0f s] %s %s x%g dt 1/%d (%.0f s, %.1f px/frame)' % (
                    time.time() - started, name, kind, speed, round(1 / dt),
                    time.perf_counter() - t0, tol['pixels_per_frame']), flush=True)
                for prot, frac in (('time', None), ('triangles', 1.0), ('triangles', 0.5)):
                    sel = [r for r in cell if r['protocol'] == prot
                           and (frac is None or r['fraction'] == frac)]
                    print('    %-9s %-4s ' % (prot, '' if frac is None else frac) + ' | '.join(
                        '%s %.2f %.3f %d%s' % (
                            r['mode'], r['mean_psnr'], r['mean_ssim'], r['mean_triangles'],
                            '' if prot == 'time' else ' f%.2f' % r['fill_min'])
                        for r in sel), flush=True)
    return rows


# ---- summary ------------------------------------------------------------------------------

def groups(rows):
    """{(model, motion, speed, dt, protocol, fraction or None): {mode: row}}."""
    out = {}
    for r in rows:
        if r['protocol'] == 'tolerance':
            continue
        frac = None if r['protocol'] == 'time' else r['fraction']
        out.setdefault((r['model'], r['motion'], r['speed'], r['dt'], r['protocol'], frac),
                       {})[r['mode']] = r
    return out


def best(cell, modes, metric='mean_psnr'):
    return max(modes, key=lambda m: cell[m][metric])


def dtname(dt):
    return '1/%d' % round(1 / dt)


def stats(values):
    v = [x for x in values if x == x]
    if not v:
        return '-'
    return '%+.2f / %+.2f / %+.2f' % (min(v), float(np.mean(v)), max(v))


def summary(rows, command, seconds, settings):
    g = groups(rows)
    keys = sorted(g, key=lambda k: (k[0], k[1], k[2], k[3], k[4] != 'time',
                                    -(k[5] or 0)))
    prot_name = {('time', None): 'time-matched', ('triangles', 1.0): 'equal tri. B',
                 ('triangles', 0.5): 'equal tri. B/2'}
    L = ['# TMM against IPV and DPV on the moving protocol, examined (issue 27)', '',
         'Generated by `Testing/Quality/plod_tmm.py`; every figure is in `tmm_examination.csv` '
         '(one row per cell, protocol and mode). Run time %.0f s on 2 shared cores (offscreen '
         'Mesa llvmpipe, 640x480).' % seconds, '', '```', command, '```', '',
         '## Protocol', '']
    L += settings
    L += ['', 'The protocol in full is in the script\'s docstring. In short: moving images, '
          'compared at every display instant k dt (k = 0..N) with the full-resolution image '
          'of the same instant; PSNR of 8-bit luminance and SSIM, mean over the instants.',
          '- **time-matched** (TMM §5.2, `pm.moving`): frames back to back, each showing the '
          'scene as it was when its select + patch + render began (lag). TMM and SRCC at their '
          'tolerances (T_s = 1 px); IPV, DPV, IPV-SRCC, DPV-SRCC with their speed constant '
          'bisected per cell so that their mean frame time equals TMM\'s.',
          '- **equal triangles**: display-rate schedule (no lag difference: the frame shown at '
          'k dt is drawn for (k - 1) dt). B = TMM\'s mean drawn count at its tolerance; every '
          'mode draws each frame with `SetExactTriangleBudget` at B and at B/2, tolerances '
          '1/16 of the papers\' as a floor. IPV and DPV keep the constants calibrated for the '
          'same cell.',
          '- modes: TMM (SRCC + micro motion), SRCC (no motion model), IPV and DPV (TMM §5.3: '
          'velocity alone), IPV-SRCC and DPV-SRCC (SRCC\'s tolerances times the speed factor, '
          '`VELOCITY_SCALES_ERROR_MODEL`).',
          '- speed: plod_measure\'s movement run `speed` times faster (same path); '
          '`px/frame` is the object\'s mean screen speed per dt as the selector measures it '
          '(TMM at tolerance, display-rate run).', '']
    # fill
    L += ['## Drawn triangles at equal budgets (fill = drawn / budget per frame)', '',
          '| mode | frames over budget | fill min | fill mean (median over runs) | runs with '
          'fill min < 0.95 |', '| --- | ---: | ---: | ---: | ---: |']
    for m in MODES + ('SIZE',):
        sel = [r for r in rows if r['protocol'] == 'triangles' and r['mode'] == m]
        if sel:
            L.append('| %s | %d | %.3f | %.3f | %d of %d |' % (
                m, sum(r['over_budget_frames'] for r in sel), min(r['fill_min'] for r in sel),
                float(np.median([r['fill_mean'] for r in sel])),
                sum(r['fill_min'] < 0.95 for r in sel), len(sel)))
    # main tables
    L += ['', '## Mean PSNR (dB) / mean SSIM per cell', '',
          '`best` among TMM, IPV, DPV (TMM Table 2\'s three; paper forms) and, after the slash, '
          'among all six modes. `order` = yes when TMM >= IPV >= DPV in mean PSNR.', '',
          '| model | motion | speed | dt | px/frame | protocol | TMM | SRCC | IPV | DPV | '
          'IPV-SRCC | DPV-SRCC | SIZE | best | order |',
          '| --- | --- | ---: | --- | ---: | --- | ---: | ---: | ---: | ---: | ---: | ---: | '
          '---: | --- | --- |']
    tolrows = {(r['model'], r['motion'], r['speed'], r['dt']): r for r in rows
               if r['protocol'] == 'tolerance'}
    for k in keys:
        c = g[k]
        if not all(m in c for m in MODES):
            continue
        px = tolrows[k[:4]]['pixels_per_frame'] if k[:4] in tolrows else float('nan')
        order = c['TMM']['mean_psnr'] >= c['IPV']['mean_psnr'] >= c['DPV']['mean_psnr']
        L.append('| %s | %s | %g | %s | %.1f | %s | %s | %s | %s | %s |' % (
            k[0], k[1], k[2], dtname(k[3]), px, prot_name[(k[4], k[5])],
            ' | '.join('%.2f / %.3f' % (c[m]['mean_psnr'], c[m]['mean_ssim']) if m in c
                       else '-' for m in MODES + ('SIZE',)),
            best(c, PAPER), best(c, MODES), 'yes' if order else 'no'))
    # triangles and frame time in the time-matched protocol
    L += ['', '## Time-matched protocol: mean triangles drawn, mean frame ms, constant', '',
          '| model | motion | speed | dt | TMM | SRCC | IPV | DPV | IPV-SRCC | DPV-SRCC |',
          '| --- | --- | ---: | --- | ---: | ---: | ---: | ---: | ---: | ---: |']
    for k in keys:
        if k[4] != 'time':
            continue
        c = g[k]
        L.append('| %s | %s | %g | %s | %s |' % (k[0], k[1], k[2], dtname(k[3]), ' | '.join(
            '%d, %.1f ms%s' % (c[m]['mean_triangles'], c[m]['mean_frame_ms'],
                               '' if c[m]['constant'] != c[m]['constant']
                               else ', C %.3g' % c[m]['constant']) for m in MODES)))
    # wins
    L += ['', '## Which mode wins how often (mean PSNR; mean SSIM in brackets)', '',
          '| model | protocol | cells | TMM Table 2 order holds | best of TMM/IPV/DPV: TMM | '
          'IPV | DPV | best of all six: ' + ' | '.join(MODES) + ' |',
          '| --- | --- | ---: | ---: | ---: | ---: | ---: | ' +
          ' | '.join('---:' for _ in MODES) + ' |']
    models = sorted({k[0] for k in keys}, key=lambda m: [r['model'] for r in rows].index(m))
    for model in models + ['all']:
        for pk in (('time', None), ('triangles', 1.0), ('triangles', 0.5)):
            sel = [g[k] for k in keys if (model == 'all' or k[0] == model)
                   and (k[4], k[5]) == pk and all(m in g[k] for m in MODES)]
            if not sel:
                continue
            order = sum(c['TMM']['mean_psnr'] >= c['IPV']['mean_psnr'] >= c['DPV']['mean_psnr']
                        for c in sel)

            def count(modes, m):
                return '%d [%d]' % (sum(best(c, modes) == m for c in sel),
                                    sum(best(c, modes, 'mean_ssim') == m for c in sel))
            L.append('| %s | %s | %d | %d | %s | %s |' % (
                model, prot_name[pk], len(sel), order,
                ' | '.join(count(PAPER, m) for m in PAPER),
                ' | '.join(count(MODES, m) for m in MODES)))
    # switches
    L += ['', '## Switches, one at a time', '',
          'Each row: the change in mean PSNR (dB) that one switch makes, over the cells '
          '(min / mean / max), and how often the winner among TMM, IPV and DPV changes with it. '
          '`TMM − best velocity` is TMM minus the better of IPV and DPV (paper forms).', '',
          '| switch | protocol | cells | change of PSNR (min / mean / max) | change of SSIM '
          '(mean) | winner of TMM/IPV/DPV changes |',
          '| --- | --- | ---: | --- | ---: | ---: |']

    def switch(label, pk, pairs):
        """pairs: [(cell, a_mode, b_mode, winner_modes_after)]"""
        if not pairs:
            return
        d = [c[b]['mean_psnr'] - c[a]['mean_psnr'] for c, a, b, _ in pairs]
        ds = [c[b]['mean_ssim'] - c[a]['mean_ssim'] for c, a, b, _ in pairs]
        # the winner's role (TMM, IPV or DPV) before and after the switch
        flips = sum(PAPER.index(best(c, PAPER)) != after.index(best(c, after))
                    for c, _, _, after in pairs)
        L.append('| %s | %s | %d | %s | %+.4f | %d |' % (label, pk, len(pairs), stats(d),
                                                       float(np.mean(ds)), flips))
    for pk in (('time', None), ('triangles', 1.0), ('triangles', 0.5)):
        sel = [g[k] for k in keys if (k[4], k[5]) == pk and all(m in g[k] for m in MODES)]
        name = prot_name[pk]
        switch('TMM motion reduction off (TMM → SRCC)', name,
               [(c, 'TMM', 'SRCC', ('SRCC', 'IPV', 'DPV')) for c in sel])
        switch('IPV criterion Alone → ScalesErrorModel', name,
               [(c, 'IPV', 'IPV-SRCC', ('TMM', 'IPV-SRCC', 'DPV')) for c in sel])
        switch('DPV criterion Alone → ScalesErrorModel', name,
               [(c, 'DPV', 'DPV-SRCC', ('TMM', 'IPV', 'DPV-SRCC')) for c in sel])
        if pk[0] == 'triangles':
            switch('IPV speed factor off (IPV → SIZE)', name,
                   [(c, 'IPV', 'SIZE', ('TMM', 'SIZE', 'DPV')) for c in sel if 'SIZE' in c])
            switch('DPV speed factor off (DPV → SIZE)', name,
                   [(c, 'DPV', 'SIZE', ('TMM', 'IPV', 'SIZE')) for c in sel if 'SIZE' in c])
            switch('TMM order → size order (TMM → SIZE)', name,
                   [(c, 'TMM', 'SIZE', ('SIZE', 'IPV', 'DPV')) for c in sel if 'SIZE' in c])
    # protocol / budget / speed / dt as switches on TMM's margin
    L += ['', '## TMM − best velocity method (paper forms IPV, DPV), by switch', '',
          'Margin = TMM − max(IPV, DPV) in mean PSNR (dB), min / mean / max over the cells in '
          'the group; `TMM best` = cells where TMM is ahead of both. Same for the SRCC-scaled '
          'forms and for SRCC (no motion) in place of TMM.', '',
          '| group | protocol | cells | TMM − best(IPV, DPV) | TMM best | '
          'TMM − best(IPV-SRCC, DPV-SRCC) | SRCC − best(IPV, DPV) | TMM − SIZE |',
          '| --- | --- | ---: | --- | ---: | --- | --- | --- |']

    def margin(c, a='TMM', pair=('IPV', 'DPV')):
        return c[a]['mean_psnr'] - max(c[m]['mean_psnr'] for m in pair)
    dims = [('all', lambda k: True)]
    dims += [('%s' % m, (lambda m: lambda k: k[0] == m)(m)) for m in models]
    dims += [('motion %s' % x, (lambda x: lambda k: k[1] == x)(x))
             for x in sorted({k[1] for k in keys})]
    dims += [('speed %g' % x, (lambda x: lambda k: k[2] == x)(x))
             for x in sorted({k[2] for k in keys})]
    dims += [('dt %s' % dtname(x), (lambda x: lambda k: k[3] == x)(x))
             for x in sorted({k[3] for k in keys}, reverse=True)]
    for label, f in dims:
        for pk in (('time', None), ('triangles', 1.0), ('triangles', 0.5)):
            sel = [g[k] for k in keys if f(k) and (k[4], k[5]) == pk
                   and all(m in g[k] for m in MODES)]
            if not sel:
                continue
            L.append('| %s | %s | %d | %s | %d | %s | %s | %s |' % (
                label, prot_name[pk], len(sel), stats([margin(c) for c in sel]),
                sum(margin(c) > 0 for c in sel),
                stats([margin(c, 'TMM', ('IPV-SRCC', 'DPV-SRCC')) for c in sel]),
                stats([margin(c, 'SRCC') for c in sel]),
                stats([c['TMM']['mean_psnr'] - c['SIZE']['mean_psnr'] for c in sel
                       if 'SIZE' in c])))
    return L


def repeat(entry, kind, speed, dt, instants, preroll, n, path):
    key, make = entry
    scene = make()
    move = scaled_movement(kind, speed)
    distance = 1.5 * scene.radius / math.sin(math.radians(scene.view_angle) / 2)
    refs = references(scene, move, dt, distance, instants)
    fields = ['model', 'motion', 'speed', 'dt', 'mode', 'run', 'mean_psnr', 'std_psnr',
              'mean_frame_ms', 'mean_triangles']
    out = []
    with open(path, 'w', newline='') as f:
        w = csv.DictWriter(f, fields)
        w.writeheader()
        for run in range(n):
            for mode in ('TMM', 'SRCC'):
                p, sd, ms, tris, _ = run_time_matched(scene, mode, move, dt, distance, instants,
                                                      refs, preroll=preroll)
                row = dict(model=key, motion=kind, speed=speed, dt=dt, mode=mode, run=run,
                           mean_psnr=p, std_psnr=sd, mean_frame_ms=ms, mean_triangles=tris)
                w.writerow(row)
                out.append(row)
                print('run %d %s %.2f dB %.1f ms %d tri' % (run, mode, p, ms, tris), flush=True)
    for mode in ('TMM', 'SRCC'):
        ps = [r['mean_psnr'] for r in out if r['mode'] == mode]
        ms = [r['mean_frame_ms'] for r in out if r['mode'] == mode]
        print('%s: mean PSNR %.2f +- %.2f dB (min %.2f, max %.2f); frame %.1f +- %.1f ms' % (
            mode, np.mean(ps), np.std(ps), min(ps), max(ps), np.mean(ms), np.std(ms)))


def main():
    ap = argparse.ArgumentParser()
    ap.add_argument('--out', default='docs/results')
    ap.add_argument('--data', default=os.path.join(os.path.dirname(os.path.abspath(__file__)),
                                                   '..', '..', '..', 'shared', 'data'))
    ap.add_argument('--models', default='bunny,generated')
    ap.add_argument('--motions', default='T,R')
    ap.add_argument('--speeds', default='0.5,1,2')
    ap.add_argument('--dts', default='30,60', help='frame rates: dt = 1/rate')
    ap.add_argument('--instants', type=int, default=12)
    ap.add_argument('--calib-steps', type=int, default=6)
    ap.add_argument('--preroll', type=float, default=0.25)
    ap.add_argument('--repeat', type=int, default=0,
                    help='instead of the study: run TMM and SRCC time-matched this many times on '
                         'the same setting (first model, motion, speed, dt) and write '
                         'tmm_examination_repeat.csv: how much the wall-clock protocol varies '
                         'between identical runs')
    ap.add_argument('--quick', action='store_true',
                    help='a small generated model, T at speed 1, dt 1/30, 4 instants')
    args = ap.parse_args()
    started = time.time()
    motions = args.motions.split(',')
    speeds = [float(x) for x in args.speeds.split(',')]
    dts = [1.0 / float(x) for x in args.dts.split(',')]
    instants, steps = args.instants, args.calib_steps
    size = (640, 480)
    scenes = []
    if args.quick:
        scenes.append(('generated-small', lambda: plod_scene.Scene(
            plod_scene.generated_model(80), 'generated-small', size, level=6)))
        motions, speeds, dts, instants, steps = ['T'], [1.0], [1 / 30], 4, 3
    else:
        for key in args.models.split(','):
            if key in ('bunny', 'lucy'):
                path = os.path.join(args.data, 'bun_zipper.ply' if key == 'bunny' else 'lucy.ply')
                if not os.path.exists(path):
                    print('%s skipped: %s not found' % (key, path))
                    continue
                scenes.append((key, (lambda key, path: lambda: plod_scene.Scene(
                    plod_scene.read_ply(path), key, size, level=8))(key, path)))
            elif key == 'generated':
                scenes.append((key, lambda: plod_scene.Scene(
                    plod_scene.generated_model(GEN_RES), 'generated', size, level=8)))
    os.makedirs(args.out, exist_ok=True)
    if args.repeat:
        repeat(scenes[0], motions[0], speeds[0], dts[0], instants, args.preroll, args.repeat,
               os.path.join(args.out, 'tmm_examination_repeat.csv'))
        return
    suffix = '_quick' if args.quick else ''
    path = os.path.join(args.out, 'tmm_examination%s.csv' % suffix)
    rows = []
    with open(path, 'w', newline='') as f:
        writer = csv.DictWriter(f, FIELDS)
        writer.writeheader()
        for key, make in scenes:
            t0 = time.perf_counter()
            scene = make()
            print('%s: %d triangles, scene built in %.1f s' % (
                key, scene.full.GetNumberOfPolys(), time.perf_counter() - t0), flush=True)
            rows += measure(key, scene, writer, motions, speeds, dts, instants, steps,
                            args.preroll, started)
            f.flush()
            del scene
    seconds = time.time() - started
    settings = ['- models: %s' % ', '.join(k for k, _ in scenes),
                '- motions: %s; speeds: %s; dt: %s; instants N = %d; calibration steps %d; '
                'pre-roll %.2f s' % (', '.join(motions), ', '.join('%g' % s for s in speeds),
                                     ', '.join(dtname(d) for d in dts), instants, steps,
                                     args.preroll)]
    command = ('PYTHONPATH=/work/tmm/lib/python3/dist-packages nice -n 10 xvfb-run -a -s '
               '"-screen 0 1280x1024x24 -noreset" /usr/bin/python3 Testing/Quality/plod_tmm.py '
               + ' '.join(sys.argv[1:]))
    lines = summary(rows, command, seconds, settings)
    md = os.path.join(args.out, 'tmm_examination%s.md' % suffix)
    with open(md, 'w') as f:
        f.write('\n'.join(lines) + '\n')
    print('\n'.join(lines))
    print('written: %s (%d rows), %s; %.0f s' % (path, len(rows), md, seconds))


if __name__ == '__main__':
    main()
