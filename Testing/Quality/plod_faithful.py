"""Is the LOD a faithful picture of the model? (issue 9) Measures, as a new user would see it:

    PYTHONPATH=build/lib/python3/dist-packages xvfb-run -a -s "-screen 0 1280x1024x24 -noreset" \\
        /usr/bin/python3 Testing/Quality/plod_faithful.py --out docs/results [--quick]

Models: the Stanford bunny (69,451 triangles, open base), Lucy as given in ../shared/data (15,000
triangles: a coarse mesh), Lucy Loop-subdivided twice (240,000 triangles: a dense surface with
Lucy's thin wings, standing in for a full-resolution scan), a generated displaced sphere of
1,005,360 triangles, and a generated body with thin parts beside it (a wing, a ring, a spike).

Protocol (every view, every model):
- 640x480, view angle 30 degrees, the renderer's automatic headlight, a grey actor (colour 0.8,
  diffuse 0.9, specular 0.3, power 20), background pure blue (no lit grey pixel can have it);
- the camera is reset to the model's bounds (vtkRenderer::ResetCamera(bounds)), turned by one of
  8 azimuths (0, 45, ..., 315 degrees) and dollied: far = Dolly(0.25) (4x the reset distance),
  mid = Dolly(1), close = Dolly(3) (a third of it: the model overflows the view);
- the reference is the full-resolution mesh, smooth-shaded (vtkPolyDataNormals without splitting)
  like the LOD;
- the LOD is the ordinary pipeline: builder -> selector -> patch generator -> mapper, the
  selector fed by vtkPerceptualLODRenderBinding from the renderer (what a user gets);
- vtkQuadricDecimation of the full mesh to the LOD's triangle count, done once for that view
  (the static LOD a VTK user would make instead), smooth-shaded;
- PSNR on 8-bit luminance (plod_metrics.psnr); hole pixels: background pixels of the LOD image
  inside the reference's object mask eroded by 3 pixels (a 7x7 square); triangles per covered
  pixel: the LOD's triangles over the reference's object pixels.
Also: the finest cut (every leaf opened) against the reference at mid distance, the holes at
tolerances x8, and the trade curve (PSNR against triangles) for the default (QEF), the paper's
mean rule, and QD and meshoptimizer's simplifier (vtkMeshoptimizerDecimation, when built) at the
same counts; meshoptimizer also beside QD in every view.

Writes faithful.csv (one row per view and variant), trade.csv, and faithful.md (medians).
"""
import argparse
import csv
import math
import os
import sys

import numpy as np
from vtkmodules.vtkCommonDataModel import vtkPolyData
from vtkmodules.vtkFiltersCore import vtkAppendPolyData, vtkCleanPolyData, vtkTriangleFilter

sys.path.insert(0, os.path.dirname(os.path.abspath(__file__)))
import plod_metrics as metrics  # noqa: E402
import plod_scene  # noqa: E402
import perceptual_lod as plod  # noqa: E402
from plod_scene import read_ply as _read_ply, smooth  # noqa: E402

SIZE = (640, 480)
DISTANCES = {'far': 0.25, 'mid': 1.0, 'close': 3.0}
AZIMUTHS = [0, 45, 90, 135, 180, 225, 270, 315]
BACKGROUND = plod_scene.BLUE


# ---- models ---------------------------------------------------------------------------------

def read_ply(path):
    """The PLY file, checked, as triangles (plod_scene.read_ply)."""
    return _read_ply(path, triangles=True)


displaced_sphere = plod_scene.generated_model  # a closed detailed model: a displaced UV sphere


def make_scene(model, rule=None):
    """This protocol's scene (plod_scene.Scene): 640x480 on the blue background."""
    return plod_scene.Scene(model, size=SIZE, rule=rule, background=BACKGROUND)


def grid_surface(nu, nv, fn, closed_u, closed_v):
    """A welded triangle mesh of the parametric surface fn(u, v) on [0,1]^2 (numpy arrays)."""
    from vtkmodules.util.numpy_support import numpy_to_vtk, numpy_to_vtkIdTypeArray
    from vtkmodules.vtkCommonCore import vtkPoints
    from vtkmodules.vtkCommonDataModel import vtkCellArray
    cu = nu if closed_u else nu + 1
    cv = nv if closed_v else nv + 1
    u, v = np.meshgrid(np.arange(cu) / nu, np.arange(cv) / nv, indexing='ij')
    xyz = np.stack(fn(u.ravel(), v.ravel()), axis=1)
    idx = lambda i, j: (i % cu) * cv + (j % cv)  # noqa: E731
    i, j = np.meshgrid(np.arange(nu), np.arange(nv), indexing='ij')
    i, j = i.ravel(), j.ravel()
    a, b, c, d = idx(i, j), idx(i + 1, j), idx(i + 1, j + 1), idx(i, j + 1)
    tris = np.concatenate([np.stack([a, b, c], 1), np.stack([a, c, d], 1)])
    pd = vtkPolyData()
    pts = vtkPoints()
    pts.SetData(numpy_to_vtk(np.ascontiguousarray(xyz, dtype=np.float64), deep=1))
    pd.SetPoints(pts)
    cells = vtkCellArray()
    offsets = np.arange(0, 3 * len(tris) + 1, 3, dtype=np.int64)
    cells.SetData(numpy_to_vtkIdTypeArray(offsets, deep=1),
                  numpy_to_vtkIdTypeArray(tris.astype(np.int64).ravel(), deep=1))
    pd.SetPolys(cells)
    return pd


def _sin_pi(v):
    """sin(pi v), exactly 0 at the poles (so that they weld into closed surfaces)."""
    return np.where((v <= 0) | (v >= 1), 0.0, np.sin(np.pi * v))


def thin_parts_model(resolution=200):
    """A body with thin parts beside it, as on a statue: a displaced sphere (radius about 1), a
    thin wing (a flattened ellipsoid 0.03 thick) beside it, a thin ring (a torus whose tube is
    0.012, 1/80 of the body) around it and a thin spike (0.03 across) above it. Closed, separate
    components (no part passes through another, which a scan never does)."""
    parts = [displaced_sphere(resolution)]
    # wing: ellipsoid 1.0 x 0.015 x 0.45 half-axes, beside the body on +x
    parts.append(grid_surface(resolution, resolution // 2, lambda u, v: (
        2.4 + 1.0 * np.cos(2 * np.pi * u) * _sin_pi(v),
        0.015 * np.sin(2 * np.pi * u) * _sin_pi(v) + 0.2,
        0.45 * np.cos(np.pi * v)), True, False))
    # ring: torus of radius 1.45, tube 0.012, tilted
    def torus(u, v):
        R, r = 1.45, 0.012
        x = (R + r * np.cos(2 * np.pi * v)) * np.cos(2 * np.pi * u)
        y = (R + r * np.cos(2 * np.pi * v)) * np.sin(2 * np.pi * u)
        z = r * np.sin(2 * np.pi * v)
        return x, 0.5 * y + 0.8 * z, -0.8 * y + 0.5 * z
    parts.append(grid_surface(4 * resolution, 12, torus, True, True))
    # spike: a long thin ellipsoid above the body
    parts.append(grid_surface(resolution // 4, resolution, lambda u, v: (
        0.015 * np.cos(2 * np.pi * u) * _sin_pi(v),
        1.9 + 0.55 * np.cos(np.pi * v),
        0.015 * np.sin(2 * np.pi * u) * _sin_pi(v)), True, False))
    append = vtkAppendPolyData()
    for p in parts:
        clean = vtkCleanPolyData()
        clean.SetInputData(p)
        clean.Update()
        append.AddInputData(clean.GetOutput())
    tri = vtkTriangleFilter()
    tri.SetInputConnection(append.GetOutputPort())
    return plod_scene.output_copy(tri)


def subdivided(data, times=2):
    """Loop subdivision of a closed mesh: a dense surface with the same thin parts."""
    from vtkmodules.vtkFiltersModeling import vtkLoopSubdivisionFilter
    clean = vtkCleanPolyData()
    clean.SetInputData(data)
    loop = vtkLoopSubdivisionFilter()
    loop.SetInputConnection(clean.GetOutputPort())
    loop.SetNumberOfSubdivisions(times)
    return plod_scene.output_copy(loop)


def models(data, quick):
    out = []
    if quick:
        out.append(('generated-small', displaced_sphere(120)))
        return out
    bunny = os.path.join(data, 'bun_zipper.ply')
    lucy = os.path.join(data, 'lucy.ply')
    if os.path.exists(bunny):
        out.append(('bunny', read_ply(bunny)))
    else:
        print('skipping the bunny: %s not found' % bunny)
    if os.path.exists(lucy):
        out.append(('lucy', read_ply(lucy)))
        out.append(('lucy-dense', subdivided(read_ply(lucy))))
    else:
        print('skipping Lucy: %s not found' % lucy)
    out.append(('generated-1M', displaced_sphere(710)))
    out.append(('thin-parts', thin_parts_model(300)))
    return out


# ---- rendering ------------------------------------------------------------------------------

def is_background(img):
    return (img[..., 0] == 0) & (img[..., 1] == 0) & (img[..., 2] == 255)


def exterior(background):
    """The background pixels connected (4-neighbours) to the image border: what a shrunken
    outline exposes. Background inside the object that is not connected to it is a see-through
    gap."""
    reach = np.zeros_like(background)
    reach[0, :] = background[0, :]
    reach[-1, :] = background[-1, :]
    reach[:, 0] |= background[:, 0]
    reach[:, -1] |= background[:, -1]
    while True:
        grown = reach.copy()
        grown[1:] |= reach[:-1]
        grown[:-1] |= reach[1:]
        grown[:, 1:] |= reach[:, :-1]
        grown[:, :-1] |= reach[:, 1:]
        grown &= background
        if (grown == reach).all():
            return reach
        reach = grown


def hole_split(inner, img, ref_mask=None):
    """Hole pixels (background inside the reference's eroded mask), as (all, enclosed gaps,
    depth): the depth is how far inside the reference's silhouette the deepest hole pixel lies
    (chessboard distance to the nearest pixel outside it, in pixels; 0 without `ref_mask`). A
    contour tolerance of T pixels lets the outline move by up to about T pixels: holes no deeper
    than that are the outline drawn within tolerance."""
    background = is_background(img)
    holes = inner & background
    if not holes.any():
        return 0, 0, 0
    gaps = holes & ~exterior(background)
    depth = 0
    if ref_mask is not None:
        m = ref_mask.copy()
        while (holes & m).any() and depth < 256:
            depth += 1
            m = metrics.erode(m, 1)
    return int(holes.sum()), int(gaps.sum()), depth


def lum(img):
    return metrics.luminance(img)


HAVE_MESHOPT = hasattr(plod, 'vtkMeshoptimizerDecimation')


def meshopt(full, target):
    """meshoptimizer's simplifier (the second static baseline), or None when not built."""
    if not HAVE_MESHOPT:
        return None, 0
    mo = plod.vtkMeshoptimizerDecimation()
    mo.SetInputData(full)
    mo.SetTargetNumberOfTriangles(max(1, int(target)))
    mo.Update()
    return smooth(mo.GetOutput()), mo.GetNumberOfTriangles()


# ---- measurements ---------------------------------------------------------------------------

def measure_views(name, scene, writer, scales=(1.0, 8.0), with_qd=True):
    rows = []
    for dname, dolly in DISTANCES.items():
        for az in AZIMUTHS:
            scene.reset_view(az, dolly)
            ref = scene.render_actor(scene.ref_actor)
            ref_mask = ~is_background(ref)
            inner = metrics.erode(ref_mask, 3)
            covered = int(ref_mask.sum())
            for scale in scales:
                img, tris = scene.render_lod(scale)
                holes, gaps, depth = hole_split(inner, img, ref_mask)
                row = dict(model=name, distance=dname, azimuth=az, scale=scale, triangles=tris,
                           psnr=metrics.psnr(lum(ref), lum(img)), holes=holes, gaps=gaps,
                           hole_depth=depth,
                           covered=covered,
                           tri_per_px=tris / max(1, covered),
                           select_ms=scene.selector.GetSelectTime() * 1e3,
                           patch_ms=scene.patches.GetGenerateTime() * 1e3,
                           qd_triangles='', qd_psnr='', qd_holes='', mo_triangles='',
                           mo_psnr='')
                if with_qd and scale == 1.0 and tris > 0:
                    qd, qd_tris, _ = plod_scene.decimated(scene.full, tris)
                    qimg = scene.render_data(qd)
                    row['qd_triangles'] = qd_tris
                    row['qd_psnr'] = metrics.psnr(lum(ref), lum(qimg))
                    row['qd_holes'] = int((inner & is_background(qimg)).sum())
                    mo, mo_tris = meshopt(scene.full, tris)
                    if mo is not None:
                        row['mo_triangles'] = mo_tris
                        row['mo_psnr'] = metrics.psnr(lum(ref), lum(scene.render_data(mo)))
                writer.writerow(row)
                rows.append(row)
                print('%-14s %-5s az %3d x%-3g tris %7d psnr %6.2f qd %6s holes %4d tri/px %.3f' % (
                    name, dname, az, scale, tris, row['psnr'],
                    '%.2f' % row['qd_psnr'] if row['qd_psnr'] != '' else '-', holes,
                    row['tri_per_px']), flush=True)
    return rows


def measure_finest(name, scene, writer):
    """The finest cut (every leaf opened) against the reference at mid distance."""
    cutter = plod.vtkMultiscaleOctreeCutter()
    cutter.SetInputConnection(scene.builder.GetOutputPort())
    cutter.SetLevel(-1)
    patches = plod.vtkMultiscalePatchGenerator()
    patches.SetInputConnection(cutter.GetOutputPort())
    finest = plod_scene.output_copy(patches)
    rows = []
    for az in AZIMUTHS:
        scene.reset_view(az, DISTANCES['mid'])
        ref = scene.render_actor(scene.ref_actor)
        img = scene.render_data(finest)
        holes, gaps, _ = hole_split(metrics.erode(~is_background(ref), 3), img)
        row = dict(model=name, distance='mid', azimuth=az, scale='finest',
                   triangles=finest.GetNumberOfPolys(), psnr=metrics.psnr(lum(ref), lum(img)),
                   holes=holes, gaps=gaps, hole_depth='',
                   covered=int((~is_background(ref)).sum()), tri_per_px='', select_ms='',
                   patch_ms=patches.GetGenerateTime() * 1e3, qd_triangles='', qd_psnr='',
                   qd_holes='', mo_triangles='', mo_psnr='')
        writer.writerow(row)
        rows.append(row)
    print('%-14s finest: %d triangles (input %d), PSNR median %.2f dB' % (
        name, finest.GetNumberOfPolys(), scene.model.GetNumberOfPolys(),
        np.median([r['psnr'] for r in rows])), flush=True)
    return rows


def trade_curve(name, scenes, writer, scales=(0.25, 0.5, 1, 2, 4, 8, 16)):
    """PSNR against triangles at mid distance (azimuth 0 and 90) for each vertex rule, QD and
    meshoptimizer (the static ones at the default rule's counts)."""
    rows = []

    def emit(**row):
        writer.writerow(row)
        rows.append(row)
    for az in (0, 90):
        for rule, scene in scenes.items():
            scene.reset_view(az, DISTANCES['mid'])
            ref = scene.render_actor(scene.ref_actor)
            for scale in scales:
                img, tris = scene.render_lod(scale)
                emit(model=name, azimuth=az, method=rule, scale=scale, triangles=tris,
                     psnr=metrics.psnr(lum(ref), lum(img)))
                if rule == 'qef' and tris > 0:
                    qd, qd_tris, _ = plod_scene.decimated(scene.full, tris)
                    emit(model=name, azimuth=az, method='QD', scale=scale, triangles=qd_tris,
                         psnr=metrics.psnr(lum(ref), lum(scene.render_data(qd))))
                    mo, mo_tris = meshopt(scene.full, tris)
                    if mo is not None:
                        emit(model=name, azimuth=az, method='meshopt', scale=scale,
                             triangles=mo_tris,
                             psnr=metrics.psnr(lum(ref), lum(scene.render_data(mo))))
    return rows


def at_triangles(curve, tris):
    """PSNR of a trade curve [(triangles, psnr)] at `tris`, interpolated in log(triangles);
    None outside the curve's range."""
    pts = sorted((t, p) for t, p in curve if t > 0 and not math.isinf(p))
    for (t0, p0), (t1, p1) in zip(pts, pts[1:]):
        if t0 <= tris <= t1:
            if t1 == t0:
                return p0
            w = (math.log(tris) - math.log(t0)) / (math.log(t1) - math.log(t0))
            return p0 + w * (p1 - p0)
    return None


def trade_summary(trade_rows):
    """Per model: PSNR of the mean rule, QD and meshopt at the default rule's triangle counts
    (interpolated along each curve), medians over scales and azimuths."""
    if not trade_rows:
        return []
    lines = ['', '## Trade curve (mid distance, azimuths 0 and 90, tolerances x0.25 to x16)', '',
             'Each method\'s PSNR at the triangle counts of the default (QEF) LOD, interpolated '
             'along its own curve in log(triangles); the difference is the median over the '
             'points both curves cover. Full curves in trade.csv.', '',
             '| model | QEF - mean rule (dB) | QEF - QD (dB) | QEF - meshopt (dB) | points |',
             '| --- | ---: | ---: | ---: | ---: |']
    models_seen = []
    for r in trade_rows:
        if r['model'] not in models_seen:
            models_seen.append(r['model'])
    for m in models_seen:
        cells = []
        npts = 0
        for other in ('mean', 'QD', 'meshopt'):
            diffs = []
            for az in (0, 90):
                sel = [r for r in trade_rows if r['model'] == m and r['azimuth'] == az]
                qef = [(r['triangles'], r['psnr']) for r in sel if r['method'] == 'qef']
                oc = [(r['triangles'], r['psnr']) for r in sel if r['method'] == other]
                for t, p in qef:
                    q = at_triangles(oc, t)
                    if q is not None and not math.isinf(p):
                        diffs.append(p - q)
            cells.append('%+.2f' % float(np.median(diffs)) if diffs else '-')
            npts = max(npts, len(diffs))
        lines.append('| %s | %s | %d |' % (m, ' | '.join(cells), npts))
    return lines


def plot_trade(trade_rows, out):
    """trade_<model>.png: PSNR against triangles at azimuth 0 for every method."""
    try:
        import matplotlib
        matplotlib.use('Agg')
        import matplotlib.pyplot as plt
    except ImportError:
        return
    styles = {'qef': ('LOD, QEF vertices (default)', 'C0', 'o-'),
              'mean': ('LOD, mean rule', 'C1', 's--'),
              'QD': ('vtkQuadricDecimation once', 'C2', '^-'),
              'meshopt': ('meshoptimizer once', 'C3', 'v:')}
    for m in sorted({r['model'] for r in trade_rows}):
        fig, ax = plt.subplots(figsize=(6, 4))
        for method, (label, colour, style) in styles.items():
            pts = sorted((r['triangles'], r['psnr']) for r in trade_rows
                         if r['model'] == m and r['azimuth'] == 0 and r['method'] == method
                         and r['triangles'] > 0 and not math.isinf(r['psnr']))
            if pts:
                ax.plot([p[0] for p in pts], [p[1] for p in pts], style, color=colour,
                        label=label)
        ax.set_xscale('log')
        ax.set_xlabel('triangles drawn')
        ax.set_ylabel('PSNR against full resolution (dB)')
        ax.set_title('%s, mid distance, azimuth 0' % m)
        ax.grid(True, alpha=0.3)
        ax.legend(fontsize=8)
        fig.tight_layout()
        fig.savefig(os.path.join(out, 'trade_%s.png' % m), dpi=100)
        plt.close(fig)


def summary(rows, trade_rows, out):
    def med(values):
        values = [v for v in values if v != '' and v is not None and not
                  (isinstance(v, float) and math.isinf(v))]
        return float(np.median(values)) if values else float('nan')
    lines = ['# Faithful surface: measured (issue 9)', '',
             'Made by `Testing/Quality/plod_faithful.py` (its docstring gives the protocol). '
             'Medians over 8 azimuths.', '',
             'Hole pixels: background inside the full-resolution silhouette eroded by 3 pixels; '
             'in brackets the enclosed ones (not connected to the background around the object), '
             'then the depth of the deepest hole pixel inside the full-resolution silhouette. '
             'A contour tolerance of T pixels lets the outline move by about T pixels: at '
             'tolerances x8 (T = 8) holes up to about 8 pixels deep are the outline drawn within '
             'the tolerance the user asked for.', '',
             '| model | distance | LOD triangles | LOD PSNR | QD PSNR | LOD - QD (dB) | '
             'LOD - meshopt (dB) | '
             'hole px (max) [gaps] depth | hole px x8 (max) [gaps] depth | '
             'triangles / covered px |',
             '| --- | --- | ---: | ---: | ---: | ---: | ---: | ---: | ---: | ---: |']
    models_seen = []
    for r in rows:
        if r['model'] not in models_seen:
            models_seen.append(r['model'])
    for m in models_seen:
        for d in DISTANCES:
            base = [r for r in rows if r['model'] == m and r['distance'] == d and r['scale'] == 1.0]
            x8 = [r for r in rows if r['model'] == m and r['distance'] == d and r['scale'] == 8.0]
            if not base:
                continue
            diff = [r['psnr'] - r['qd_psnr'] for r in base if r['qd_psnr'] != '']
            mdiff = [r['psnr'] - r['mo_psnr'] for r in base if r.get('mo_psnr', '') != '']
            lines.append('| %s | %s | %d | %.2f | %.2f | %+.2f | %s | %d [%d] %dpx | %s | %.3f |' % (
                m, d, med([r['triangles'] for r in base]), med([r['psnr'] for r in base]),
                med([r['qd_psnr'] for r in base]), med(diff),
                '%+.2f' % med(mdiff) if mdiff else '-',
                max(r['holes'] for r in base), max(r['gaps'] for r in base),
                max(r['hole_depth'] for r in base),
                '%d [%d] %dpx' % (max(r['holes'] for r in x8), max(r['gaps'] for r in x8),
                                  max(r['hole_depth'] for r in x8))
                if x8 else '-',
                med([r['tri_per_px'] for r in base])))
    fin = [r for r in rows if r['scale'] == 'finest']
    if fin:
        lines += ['', '| model | finest cut triangles | PSNR against the input, mid (median) | '
                  'hole px (max) |', '| --- | ---: | ---: | ---: |']
        for m in models_seen:
            f = [r for r in fin if r['model'] == m]
            if f:
                p = med([r['psnr'] for r in f])
                lines.append('| %s | %d | %s | %d |' % (
                    m, f[0]['triangles'], 'identical (inf)' if math.isnan(p) else '%.2f' % p,
                    max(r['holes'] for r in f)))
    lines += trade_summary(trade_rows)
    with open(os.path.join(out, 'faithful.md'), 'w') as f:
        f.write('\n'.join(lines) + '\n')
    print('\n'.join(lines))


# The Stanford scans: $PLOD_DATA_DIR, else ../shared/data beside the repository.
DEFAULT_DATA = os.environ.get('PLOD_DATA_DIR', os.path.join(
    os.path.dirname(os.path.abspath(__file__)), '..', '..', '..', 'shared', 'data'))


def main():
    ap = argparse.ArgumentParser()
    ap.add_argument('--out', default='docs/results')
    ap.add_argument('--data', default=DEFAULT_DATA)
    ap.add_argument('--quick', action='store_true')
    ap.add_argument('--models', default='')
    ap.add_argument('--no-trade', action='store_true')
    ap.add_argument('--trade', action='store_true', help='trade curves with --quick too')
    ap.add_argument('--tag', default='', help='suffix of the output files')
    args = ap.parse_args()
    os.makedirs(args.out, exist_ok=True)
    fields = ['model', 'distance', 'azimuth', 'scale', 'triangles', 'psnr', 'holes', 'gaps',
              'hole_depth', 'covered',
              'tri_per_px', 'select_ms', 'patch_ms', 'qd_triangles', 'qd_psnr', 'qd_holes',
              'mo_triangles', 'mo_psnr']
    all_rows = []
    trade_rows = []
    with open(os.path.join(args.out, 'faithful%s.csv' % args.tag), 'w', newline='') as f, \
            open(os.path.join(args.out, 'trade%s.csv' % args.tag), 'w', newline='') as g:
        writer = csv.DictWriter(f, fieldnames=fields)
        writer.writeheader()
        trade = csv.DictWriter(g, fieldnames=['model', 'azimuth', 'method', 'scale', 'triangles',
                                              'psnr'])
        trade.writeheader()
        for name, model in models(args.data, args.quick):
            if args.models and name not in args.models.split(','):
                continue
            scene = make_scene(model)
            print('%s: %d triangles, octree %d nodes, level %d, built in %.2f s' % (
                name, model.GetNumberOfPolys(), scene.builder.GetOutput().GetNumberOfNodes(),
                scene.builder.GetOutput().GetFinestLevel(), scene.build_s), flush=True)
            all_rows += measure_views(name, scene, writer, with_qd=True)
            if hasattr(scene.builder.GetOutput(), 'GetNumberOfSurfaceTriangles'):
                all_rows += measure_finest(name, scene, writer)
            if not args.no_trade and (args.trade or not args.quick):
                trade_rows += trade_curve(name, {'qef': scene, 'mean': make_scene(model, 'mean')},
                                          trade)
    summary(all_rows, trade_rows, args.out)
    plot_trade(trade_rows, args.out)


if __name__ == '__main__':
    main()
