#!/usr/bin/python3
# SPDX-License-Identifier: BSD-3-Clause
"""Writes the seed inputs of FuzzOctreeBuild into Testing/Fuzz/corpus/ (run with /usr/bin/python3).

The input format is documented at the top of FuzzOctreeBuild.cxx: FRONT (the model) | CONTROL
(build environment, cuts, views) | one byte, the length of CONTROL. This script mirrors the
decoder's order of reads; keep the two in step. Seeds are small and named after what they hold
(`seed-<name>`); the fuzzer's own finds go beside them as libFuzzer names them.

    /usr/bin/python3 Testing/Fuzz/make_seeds.py [output directory]
"""
import math
import os
import struct
import sys

# ---------------------------------------------------------------------------------------------
# FRONT

CLOUD, DOUBLE, INT64, NORMALS, POINT_DIFFUSE, POINT_SPECULAR, TRI_DIFFUSE, TRI_SPECULAR = (
    1, 2, 4, 8, 16, 32, 64, 128)
VIEWPOINTS, COMMON_VIEWPOINT = 64, 128  # the same bits, for clouds

# indices into the decoder's tables
SCALE = {1.0: 0, 1e-3: 1, 1e3: 2, 1e-7: 3, 1e-12: 4, 1e-20: 5, 1e-28: 6, 1e-30: 7, 1e-33: 8,
         1e20: 9, 1e28: 10, 1e30: 11, 1e33: 12, 1e300: 13, 1e-300: 14, 1e-310: 15}
OFFSET = {0.0: 0, 1.0: 1, 1e6: 2, -1e6: 3, 1e7 + 0.5: 4, 3e8: 5, 1e12: 6, 1e15: 7, 1e20: 8,
          1e30: 9, 1e300: 10, -1e300: 11, 1e-300: 12, 2.0 ** 32: 13, 2.0 ** 24: 14, 2.0 ** 53: 15}
MEMORY = {4e9: 0, 1e9: 1, 1e8: 2, 1e7: 3, 1e6: 4, 3e5: 5, 1e5: 6, 1e4: 7, 1000: 8, 1: 9,
          1e-300: 10, 5e-324: 11, math.inf: 12, 1e300: 13, 2e6: 14, 5e7: 15}
SPECIAL = {'nan': 0, 'inf': 1, '-inf': 2, '0': 3, '-0': 4, 'denorm_min': 5, '1e-310': 6,
           'float_denorm_min': 7, 'float_min': 8, '1e-30': 9, '1e30': 10, '1e300': 11,
           '-1e300': 12, 'dbl_max': 13, 'flt_max': 14, '-flt_max': 15}
SPECIAL_INDEX = {-1: 0, -2: 1, 'np': 2, 'np+1': 3, 'int32_min': 4, 'int32_max': 5,
                 'int64_min': 6, 'int64_max': 7, '2^32': 8, '2^32+1': 9, '-2^32': 10}
SHAPES = {'sphere': 0, 'torus': 1, 'nested': 2, 'heightfield': 3, 'box': 4, 'tube': 5}


def u16(x):
    return struct.pack('<H', x)


def s16(x):
    return struct.pack('<h', x)


def fixed(x):
    """A coordinate in fixed point (scale 1, no offset), or a named special value."""
    if isinstance(x, str):
        return s16(-32768 + SPECIAL[x])
    v = int(round(x * 256))
    assert -32768 + 16 <= v <= 32767, x
    return s16(v)


def header(kind, points, triangles, level=-1, qef=True, memory=4e9, material=0,
           encoding=0, scale=1.0, axes=0, offset=0.0, indices=0):
    """The nine header bytes. encoding: 0 fixed point, 1 float32, 2 float64, 3 shape."""
    return bytes([
        kind,
        level + 2,
        (1 if qef else 0) | (MEMORY[memory] << 1) | (material << 5),
    ]) + u16(points) + u16(triangles) + bytes([
        encoding | (SCALE[scale] << 2) | (axes << 6),
        OFFSET[offset] | (indices << 4),
    ])


def mesh(points, triangles, kind=0, normals=None, point_diffuse=None, point_specular=None,
         tri_diffuse=None, tri_specular=None, encoding=0, **head):
    """A mesh: points as (x, y, z) tuples, triangles as index triples (u16 indices, or
    SPECIAL_INDEX names)."""
    kind |= (NORMALS if normals else 0) | (POINT_DIFFUSE if point_diffuse else 0) | (
        POINT_SPECULAR if point_specular else 0) | (TRI_DIFFUSE if tri_diffuse else 0) | (
        TRI_SPECULAR if tri_specular else 0)
    out = header(kind, len(points), len(triangles), encoding=encoding, indices=0, **head)
    out += coordinates(points, encoding, kind & DOUBLE)
    for t in triangles:
        for i in t:
            out += u16(0xfff0 + SPECIAL_INDEX[i]) if not isinstance(i, int) or i < 0 else u16(i)
    out += extras(kind, normals, point_diffuse, point_specular, tri_diffuse, tri_specular)
    return out


def cloud(points, kind=0, normals=None, viewpoints=None, viewpoint=None, encoding=0, **head):
    kind |= CLOUD | (NORMALS if normals else 0) | (VIEWPOINTS if viewpoints else 0) | (
        COMMON_VIEWPOINT if viewpoint else 0)
    out = header(kind, len(points), 0, encoding=encoding, **head)
    out += coordinates(points, encoding, kind & DOUBLE)
    out += extras(kind, normals, None, None, None, None)
    for v in (viewpoints or []):
        out += b''.join(fixed(c) for c in v)
    if viewpoint:
        out += b''.join(fixed(c) for c in viewpoint)
    return out


def coordinates(points, encoding, double):
    out = b''
    for p in points:
        for c in p:
            if encoding == 0:
                out += fixed(c)
            elif encoding == 1:
                out += struct.pack('<f', c)
            else:
                out += struct.pack('<d', c)
    return out


def normal_byte(c):
    if c == 'nan':
        return -128
    if c == 'inf':
        return 127
    return max(-126, min(126, int(round(c * 64))))


def extras(kind, normals, point_diffuse, point_specular, tri_diffuse, tri_specular):
    out = b''
    if normals:
        out += bytes(normal_byte(c) & 0xff for n in normals for c in n)
    for values in (point_diffuse, point_specular, tri_diffuse, tri_specular):
        if values:
            out += bytes(values)  # bytes < 240: value / 200; 240 + i: the decoder's Materials[i]
    return out


def shape(name, u, v, noise=0, duplicate=False, gap=0, kind=0, **head):
    """A generated shape (encoding 3); `noise` indexes {0, 0, 1e-6, 1e-3, 1e-2, 0.05, 0.3, 1}."""
    out = header(kind, 0, 0, encoding=3, **head)
    out += bytes([SHAPES[name], (u - 3) % 62, (v - 2) % 62,
                  noise | (8 if duplicate else 0) | (gap << 6), 0])
    # no corruption; the noise bytes (3 per point) come from the generator: the input ends here
    return out


# ---------------------------------------------------------------------------------------------
# CONTROL

def control(parallel=0, compare=False, abort=0, fill=0, no_workspace=False, no_mask=False,
            patch_options=0, cull=(0, 0, 0, 40), cuts=(), corrupt=(), views=()):
    out = bytes([parallel | (4 if compare else 0) | (abort << 3),
                 fill | (4 if no_workspace else 0) | (8 if no_mask else 0) | (patch_options << 4)])
    out += bytes([cull[0]]) + bytes(c & 0xff for c in cull[1:]) + bytes([0, 0])
    out += bytes([len(cuts)])
    for c in cuts:  # (seed, refine probability, hidden probability, options)
        out += bytes(c)
    out += bytes([len(corrupt)])
    for c in corrupt:  # (seed, changes - 1)
        out += bytes(c)
    out += bytes([len(views)])
    for v in views:
        out += v
    return out


ERROR = {'srcc': 0, 'scvc': 1, 'psec': 2, 'distance': 3}
MOTION = {'none': 0, 'micro': 1, 'ipv': 2, 'dpv': 3}
FOVEA = {'off': 0, 'object': 1, 'screen': 2}
EYE = {'box': 0, 'vertex': 2, 'point': 3, 'far': 4, 'cell': 5, 'centre': 6, 'raw': 7}
FRUSTUM = {'none': 0, 'camera': 1, 'random': 2, 'degenerate': 3}
TOL = {0: 0, 1e-300: 1, 0.1: 2, 0.5: 3, 1: 4, 2: 5, 4: 6, 16: 7, 100: 8, 1e6: 9, 1e30: 10,
       1e300: 11, math.inf: 12, 5e-324: 13, 1e-12: 14, 3: 15}
PIXEL = {1000: 0, 1: 1, 1e-300: 2, 1e300: 3, 0.5: 4, 4000: 5, 1e6: 6, 1e-6: 7}
VELOCITY = {1: 0, 1.5: 1, 10: 2, 1e30: 3, math.inf: 4, 1e300: 5}


def view(error='srcc', motion_model='none', fovea='off', parallel=False, hide=True, eye='far',
         eye_dir=(40, 30, 50), eye_arg=b'\x01', frustum='camera', frustum_args=None,
         lights=(), headlight=True, contour=1, brightness=4, topology=1, pixels=1000,
         material=False, velocity=1, distance_level=0, motion_scale=0, motion=bytes(12),
         fovea_rate=0, psec=0):
    """One view, in the order DecodeView reads it."""
    b1 = EYE[eye] | (FRUSTUM[frustum] << 3) | (len(lights) << 5) | (128 if headlight else 0)
    out = bytes([ERROR[error] | (MOTION[motion_model] << 2) | (FOVEA[fovea] << 4) |
                 (64 if parallel else 0) | (128 if hide else 0), b1])
    out += bytes(c & 0xff for c in eye_dir)
    if eye in ('vertex', 'point', 'far', 'cell', 'raw'):
        out += eye_arg  # u16 node or point; a distance index; a level; or six bytes
    if frustum == 'camera':
        out += frustum_args or bytes([0, 1, 1, 2])  # view angle, aspect, near, far
    elif frustum == 'random':
        out += frustum_args or bytes(24)
    elif frustum == 'degenerate':
        out += frustum_args or bytes(6)
    out += bytes([0, 0, 0xc0])  # projection direction (0, 0, -1)
    out += bytes([PIXEL[pixels], TOL[contour] | (TOL[brightness] << 4),
                  TOL[topology] | (16 if material else 0), 2, 0, 1])  # diffuse 1, specular 0, k 1
    for positional, x, y, z, f in lights:
        out += bytes([(1 if positional else 0) | f, x & 0xff, y & 0xff, z & 0xff])
        if positional and f & 2:
            out += u16(0)  # the light on node 0's vertex
    out += bytes([motion_scale]) + bytes(m & 0xff for m in motion)  # A (9) and b (3)
    out += bytes([VELOCITY[velocity], psec, distance_level * 4 & 0xff])  # psec: PSECFactors
    # foveation: rate, point, up, centre, height, weights, gaze (0, 0, -1)
    out += bytes([fovea_rate]) + bytes([10, 20, 0, 0, 0, 64, 0, 0, 0, 0, 64, 64, 0, 0, 0xc0])
    return out


def seed(front, ctl=None):
    ctl = control() if ctl is None else ctl
    assert len(ctl) < 256
    return front + ctl + bytes([len(ctl)])


# ---------------------------------------------------------------------------------------------
# The seeds

TETRA = [(0, 0, 0), (1, 0, 0), (0, 1, 0), (0, 0, 1)]
TETRA_T = [(0, 2, 1), (0, 1, 3), (0, 3, 2), (1, 2, 3)]
CUBE = [(x, y, z) for z in (-1, 1) for y in (-1, 1) for x in (-1, 1)]
CUBE_T = [(0, 2, 3), (0, 3, 1), (4, 5, 7), (4, 7, 6), (0, 1, 5), (0, 5, 4),
          (2, 6, 7), (2, 7, 3), (0, 4, 6), (0, 6, 2), (1, 3, 7), (1, 7, 5)]


def sphere_points(n, radius=1.0):
    """Fibonacci points on a sphere, with their outward normals."""
    pts, nrm = [], []
    for i in range(n):
        z = 1 - 2 * (i + 0.5) / n
        r = math.sqrt(1 - z * z)
        a = i * math.pi * (3 - math.sqrt(5))
        p = (r * math.cos(a), r * math.sin(a), z)
        pts.append(tuple(radius * c for c in p))
        nrm.append(p)
    return pts, nrm


def seeds():
    default_views = (view(), view(eye='box', eye_dir=(5, -3, 2), frustum='none'),
                     view(error='scvc', eye='vertex', eye_arg=u16(0), frustum='random',
                          frustum_args=bytes([64, 0, 0, 32, 192, 0, 0, 32, 0, 64, 0, 32,
                                              0, 192, 0, 32, 0, 0, 64, 32, 0, 0, 192, 32])))
    rich = control(cuts=((1, 128, 40, 0), (2, 200, 80, 3)), corrupt=((3, 2),),
                   views=default_views)
    out = {}
    out['tetrahedron'] = seed(mesh(TETRA, TETRA_T), rich)
    out['tetrahedron-level21-mean'] = seed(mesh(TETRA, TETRA_T, level=21, qef=False), rich)
    out['cube'] = seed(mesh(CUBE, CUBE_T), rich)
    out['cube-level0'] = seed(mesh(CUBE, CUBE_T, level=0, kind=INT64), rich)
    out['cube-float-int64-level3'] = seed(
        mesh(CUBE, CUBE_T, level=3, kind=INT64, encoding=1), rich)
    out['cube-double-level5-normals-material'] = seed(mesh(
        CUBE, CUBE_T, level=5, kind=DOUBLE, encoding=2, normals=CUBE,
        point_diffuse=[0, 50, 100, 200, 240 + 4, 240 + 5, 240 + 9, 180],
        tri_specular=[i * 16 for i in range(12)]), rich)
    out['cube-open'] = seed(mesh(CUBE, CUBE_T[:-2]), rich)
    out['cube-inside-out-and-again'] = seed(mesh(
        CUBE, CUBE_T + [(a, c, b) for a, b, c in CUBE_T]), rich)
    # a long sliver of tiny triangles: 1000 long, 1e-4 wide
    strip = [(x * 1000.0 / 99, (i % 2) * 1e-4, 0.0) for x in range(100) for i in (0, 1)]
    strip_t = [(2 * k, 2 * k + 2, 2 * k + 1) for k in range(99)] + [
        (2 * k + 1, 2 * k + 2, 2 * k + 3) for k in range(99)]
    out['sliver'] = seed(mesh(strip, strip_t, kind=DOUBLE, encoding=2), rich)
    out['sliver-level21'] = seed(mesh(strip, strip_t, kind=DOUBLE, encoding=2, level=21), rich)
    # bad input: NaN and infinite points, indices out of range, negative, repeated
    bad_p = CUBE + [('nan', 0, 0), (0, 'inf', 0), ('-inf', '-inf', 'nan'), ('1e300', 0, 0)]
    bad_t = CUBE_T + [(0, 8, 1), (9, 1, 2), (10, 11, 3), (0, 0, 1), (1, 2, 1), (-1, 0, 1),
                      ('np', 0, 1), ('int32_min', 1, 2), ('2^32+1', 2, 3), (0, 'int64_max', 1)]
    out['nan-inf-and-bad-indices'] = seed(mesh(bad_p, bad_t, kind=INT64), rich)
    out['nan-inf-and-bad-indices-int32'] = seed(mesh(bad_p, bad_t), rich)
    out['all-triangles-bad'] = seed(mesh(bad_p, [(0, 0, 0), (8, 9, 10), (-1, 1, 2)]), rich)
    out['one-triangle'] = seed(mesh(TETRA[:3], TETRA_T[:1]), rich)
    out['coincident-points'] = seed(mesh([(1, 1, 1)] * 4, TETRA_T), rich)
    out['denormal-coordinates'] = seed(mesh(
        [('denorm_min', 0, 0), (0, 'float_denorm_min', 0), (0, 0, '1e-310'),
         ('float_min', 'float_min', 0)], TETRA_T), rich)
    # far from the origin, tiny and huge scales
    out['far-1e6-tiny'] = seed(mesh(CUBE, CUBE_T, scale=1e-7, offset=1e6, axes=2, kind=DOUBLE),
                               rich)
    out['far-1e6-tiny-float'] = seed(mesh(CUBE, CUBE_T, scale=1e-3, offset=1e6, axes=3), rich)
    out['far-1e15'] = seed(mesh(CUBE, CUBE_T, scale=1e3, offset=1e15, axes=1, kind=DOUBLE), rich)
    out['far-1e300'] = seed(mesh(CUBE, CUBE_T, offset=1e300, axes=2, kind=DOUBLE), rich)
    out['scale-1e-30'] = seed(mesh(CUBE, CUBE_T, scale=1e-30, kind=DOUBLE), rich)
    out['scale-1e-33'] = seed(mesh(CUBE, CUBE_T, scale=1e-33, kind=DOUBLE), rich)
    out['scale-1e28'] = seed(mesh(CUBE, CUBE_T, scale=1e28, kind=DOUBLE), rich)
    out['scale-1e30'] = seed(mesh(CUBE, CUBE_T, scale=1e30, kind=DOUBLE), rich)
    out['scale-1e300'] = seed(mesh(CUBE, CUBE_T, scale=1e300, kind=DOUBLE), rich)
    # memory limits: lowered, refused
    sph = shape('sphere', 24, 16)
    out['memory-1e5'] = seed(shape('sphere', 24, 16, memory=1e5), rich)
    out['memory-1000'] = seed(shape('sphere', 24, 16, memory=1000), rich)
    out['memory-user-level'] = seed(shape('sphere', 24, 16, memory=1e5, level=12), rich)
    # generated shapes
    out['sphere'] = seed(sph, rich)
    out['sphere-noisy-mean'] = seed(shape('sphere', 40, 30, noise=5, qef=False), rich)
    out['torus'] = seed(shape('torus', 32, 12), rich)
    out['torus-thin'] = seed(shape('torus', 48, 8, gap=1), rich)
    out['tube-thin'] = seed(shape('tube', 40, 6, gap=2), rich)
    out['nested-thin-wall'] = seed(shape('nested', 20, 14, gap=2), rich)
    out['heightfield-open'] = seed(shape('heightfield', 30, 30, noise=3), rich)
    out['box'] = seed(shape('box', 24, 24, level=6), rich)
    out['sphere-duplicated-reversed'] = seed(shape('sphere', 16, 10, duplicate=True), rich)
    out['sphere-far-tiny'] = seed(shape('sphere', 20, 12, scale=1e-7, offset=1e6, axes=2,
                                        kind=DOUBLE), rich)
    # point clouds
    pts, nrm = sphere_points(300)
    out['cloud-sphere'] = seed(cloud(pts), rich)
    out['cloud-sphere-normals'] = seed(cloud(pts, normals=nrm, kind=DOUBLE), rich)
    out['cloud-sphere-level5'] = seed(cloud(pts, level=5), rich)
    out['cloud-sphere-viewpoint'] = seed(cloud(pts, viewpoint=(0, 0, 0)), rich)
    out['cloud-sphere-scanners'] = seed(cloud(pts[:120], viewpoints=[
        tuple(3 * c for c in p) for p in pts[:120]]), rich)
    out['cloud-plane'] = seed(cloud([(x / 8, y / 8, 0) for x in range(20) for y in range(20)],
                                    viewpoint=(0, 0, 5)), rich)
    out['cloud-with-nan'] = seed(cloud(pts[:100] + [('nan', 0, 0), (0, 'inf', 0)]), rich)
    out['cloud-one-point'] = seed(cloud([(1, 2, 3)]), rich)
    out['cloud-duplicates'] = seed(cloud([(0.5, 0.5, 0.5)] * 200 + pts[:50]), rich)
    out['cloud-far-tiny'] = seed(cloud(pts[:200], scale=1e-7, offset=1e6, axes=2, kind=DOUBLE),
                                 rich)
    # the build's environment: ParallelFor variants, determinism, abort, fills
    for variant in range(4):
        out['sphere-parallel-%d-compare' % variant] = seed(
            shape('sphere', 20, 12), control(parallel=variant, compare=True, fill=variant))
    out['cloud-compare'] = seed(cloud(pts[:150]), control(parallel=3, compare=True))
    for k in (1, 3, 9, 20, 31):
        out['sphere-abort-%d' % k] = seed(shape('sphere', 20, 12), control(abort=k))
        out['cloud-abort-%d' % k] = seed(cloud(pts[:150]), control(abort=k))
    # views: eye inside, on a vertex, far away; zero and huge tolerances; lights; motion
    views = (
        view(eye='centre', frustum='none'),
        view(eye='vertex', eye_arg=u16(3), frustum='camera', contour=0, brightness=0),
        view(error='scvc', eye='far', eye_arg=b'\x05', contour=0),
        view(error='psec', parallel=True, frustum='degenerate', frustum_args=bytes([1] * 6)),
        view(error='distance', distance_level=3, eye='cell', eye_arg=b'\x04'),
        view(motion_model='dpv', velocity=math.inf, contour=1e30),
        view(motion_model='micro', motion_scale=6, motion=bytes([0, 10, 0, 246, 0, 0, 0, 0, 3, 5, 0, 0]), lights=((True, 10, 20, 30, 2 | 4 * 2 | 32 * 2),
                                                     (False, 0, 0, 64, 4 | 32))),
        view(fovea='screen', fovea_rate=2, eye='raw', eye_arg=s16(-32768 + 5) + s16(0) + s16(256)),
        view(eye='point', eye_arg=u16(7), hide=False, topology=0, pixels=1e300),
    )
    for i in range(0, len(views), 3):
        ctl = control(views=views[i:i + 3], patch_options=i)
        out['sphere-views-%d' % i] = seed(sph, ctl)
        out['cube-views-%d' % i] = seed(mesh(CUBE, CUBE_T), ctl)
        out['cloud-views-%d' % i] = seed(cloud(pts[:150]), ctl)
    out['heightfield-views-open'] = seed(shape('heightfield', 20, 20),
                                         control(views=(views[8], views[0], views[6])))
    out['empty'] = b''
    # regressions: inputs that found bugs (see the commits that fixed them)
    out['regression-cloud-counts'] = seed(cloud(pts[:100] + [('nan', 0, 0)], level=3), rich)
    out['regression-cloud-memory-limit'] = seed(cloud(pts, level=6, memory=1e5), rich)
    out['regression-psec-factor'] = seed(mesh(CUBE, CUBE_T, level=3), control(views=(
        view(error='psec', contour=0, brightness=0, frustum='none', psec=1),)))
    return out


def main():
    here = os.path.dirname(os.path.abspath(__file__))
    folder = sys.argv[1] if len(sys.argv) > 1 else os.path.join(here, 'corpus')
    os.makedirs(folder, exist_ok=True)
    total = 0
    for name, data in sorted(seeds().items()):
        with open(os.path.join(folder, 'seed-' + name), 'wb') as f:
            f.write(data)
        total += len(data)
    print('%d seeds, %d bytes, in %s' % (len(seeds()), total, folder))


if __name__ == '__main__':
    main()
