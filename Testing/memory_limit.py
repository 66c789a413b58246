"""End-to-end check of a program's --memory option on a PLY model: a limit the model cannot fit
in is refused from the header before anything is read (exit 1, a message that says how many
faces fit, no octree file) unless --save names a file, when the model is built in pieces within
the limit (the file opens, no temporary file is left); a limit no piece fits is refused with no
file and no temporary file; a limit with room builds it; a size that is not one is refused.

    memory_limit.py <program> [arguments...]
"""
import os
import struct
import subprocess
import sys
import tempfile


def grid_ply(n):
    """A binary PLY of an n x n grid of points (2 (n-1)^2 triangles) with a bumpy height."""
    points = [(i / n, j / n, ((i * 7 + j * 13) % 5) / (5.0 * n)) for j in range(n) for i in range(n)]
    faces = []
    for j in range(n - 1):
        for i in range(n - 1):
            a = j * n + i
            faces += [(a, a + 1, a + n + 1), (a, a + n + 1, a + n)]
    head = (f'ply\nformat binary_little_endian 1.0\nelement vertex {len(points)}\n'
            'property float x\nproperty float y\nproperty float z\n'
            f'element face {len(faces)}\nproperty list uchar int vertex_indices\nend_header\n')
    body = b''.join(struct.pack('<3f', *p) for p in points)
    body += b''.join(struct.pack('<B3i', 3, *f) for f in faces)
    return head.encode() + body, len(faces)


def grid_stl(n):
    """The same grid as a binary STL."""
    data, _ = grid_ply(n)
    head, body = data.split(b'end_header\n', 1)
    points = [struct.unpack_from('<3f', body, 12 * i) for i in range(n * n)]
    faces = []
    for j in range(n - 1):
        for i in range(n - 1):
            a = j * n + i
            faces += [(a, a + 1, a + n + 1), (a, a + n + 1, a + n)]
    out = bytearray(b'grid'.ljust(80, b' '))
    out += struct.pack('<I', len(faces))
    for f in faces:
        out += struct.pack('<3f', 0, 0, 1)
        for k in f:
            out += struct.pack('<3f', *points[k])
        out += b'\0\0'
    return bytes(out)


def main():
    command = sys.argv[1:]
    failures = []
    with tempfile.TemporaryDirectory(prefix='plod_memory_') as folder:
        model = os.path.join(folder, 'grid.ply')
        out = os.path.join(folder, 'grid.plod')
        data, faces = grid_ply(120)
        with open(model, 'wb') as f:
            f.write(data)
        run = subprocess.run(command + [model, '--memory', '1M'],
                             capture_output=True, text=True, timeout=300)
        print(run.stdout + run.stderr)
        if run.returncode != 1 or 'at most' not in run.stderr or 'Nothing was read' not in run.stderr:
            failures.append(f'--memory 1M: exit {run.returncode}, no refusal saying what fits')
        elif 'with --save, the model is built in pieces' not in run.stdout:
            failures.append('--memory 1M: no word of the build in pieces')
        else:
            fit = int(run.stderr.split('at most ')[1].split()[0])
            if not 0 < fit < faces:
                failures.append(f'--memory 1M: {fit} faces said to fit of {faces}')
        # with --save: built in pieces within the limit, straight into the file
        run = subprocess.run(command + [model, '--memory', '1M', '--save', out],
                             capture_output=True, text=True, timeout=300)
        print(run.stdout + run.stderr)
        left = [n for n in os.listdir(folder) if n not in ('grid.ply', 'grid.plod')]
        if run.returncode != 0 or 'built in pieces' not in run.stdout or not os.path.exists(out):
            failures.append(f'--memory 1M --save: exit {run.returncode}, {run.stderr.strip()}')
        elif left:
            failures.append(f'--memory 1M --save: temporary files left: {left}')
        elif 'octree: ' not in run.stdout:
            failures.append('--memory 1M --save: the built file was not opened and described')
        elif 'structure only' in run.stdout and 'hold structure only' not in run.stderr:
            failures.append('--memory 1M --save: the levels above the pieces hold structure '
                            'only without a warning that says why')
        os.remove(out) if os.path.exists(out) else None
        # a limit that not even one cell with its halo fits: refused, nothing left behind
        run = subprocess.run(command + [model, '--memory', '0.02M', '--save', out],
                             capture_output=True, text=True, timeout=300)
        left = [n for n in os.listdir(folder) if n != 'grid.ply']
        if run.returncode != 1 or 'more memory' not in run.stderr or left:
            failures.append(f'--memory 0.02M --save: exit {run.returncode}, left {left}, '
                            f'{run.stderr.strip()}')
        run = subprocess.run(command + [model, '--memory', '0.5G', '--save', out],
                             capture_output=True, text=True, timeout=300)
        if run.returncode != 0 or not os.path.exists(out) or 'header: ' not in run.stdout:
            failures.append(f'--memory 0.5G: exit {run.returncode}, {run.stderr.strip()}')
        # an STL model is refused from its check's counts before VTK's reader runs
        stl = os.path.join(folder, 'grid.stl')
        with open(stl, 'wb') as f:
            f.write(grid_stl(120))
        run = subprocess.run(command + [stl, '--memory', '1M'],
                             capture_output=True, text=True, timeout=300)
        if run.returncode != 1 or 'at most' not in run.stderr or 'Nothing was read' not in run.stderr:
            failures.append(f'STL --memory 1M: exit {run.returncode}, {run.stderr.strip()}')
        run = subprocess.run(command + [stl, '--memory', '0.5G'],
                             capture_output=True, text=True, timeout=300)
        if run.returncode != 0:
            failures.append(f'STL --memory 0.5G: exit {run.returncode}, {run.stderr.strip()}')
        run = subprocess.run(command + [model, '--memory', 'lots'],
                             capture_output=True, text=True, timeout=300)
        if run.returncode != 1 or '--memory takes a size' not in run.stderr:
            failures.append(f'--memory lots: exit {run.returncode}, {run.stderr.strip()}')
    for f in failures:
        print('FAIL ' + f)
    print(f'{len(failures)} failure(s)')
    return 1 if failures else 0


if __name__ == '__main__':
    sys.exit(main())
