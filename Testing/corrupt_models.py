"""End-to-end check that a program given a corrupt or missing model fails cleanly: it exits with
a non-zero status (not killed by a signal) and says on stderr which file is wrong and why.

    corrupt_models.py [--own-ply-reader] <program> [arguments...]

--own-ply-reader: the program reads PLY without VTK's reader, which needs 'vertex' first: the
model whose 'face' comes first must then be read (exit 0).

The models are written to a temporary folder; each one's path is appended to the arguments in
turn. Exit status 0 when every model is handled so; the lines printed say what was seen.
"""
import os
import struct
import subprocess
import sys
import tempfile

TETRA = [(1, 1, 1), (1, -1, -1), (-1, 1, -1), (-1, -1, 1)]
FACES = [(0, 1, 2), (0, 3, 1), (0, 2, 3), (1, 3, 2)]


def header(fmt, vertices=4, faces=4, count='uchar'):
    return (f'ply\nformat {fmt} 1.0\nelement vertex {vertices}\nproperty float x\n'
            f'property float y\nproperty float z\nelement face {faces}\n'
            f'property list {count} int vertex_indices\nend_header\n').encode()


def binary_body(faces=FACES, counts=None):
    body = b''.join(struct.pack('<3f', *p) for p in TETRA)
    for k, f in enumerate(faces):
        n = counts[k] if counts and k < len(counts) else len(f)
        body += struct.pack('<B', n) + struct.pack(f'<{len(f)}i', *f)
    return body


def ascii_body(faces=FACES):
    rows = [' '.join(str(c) for c in p) for p in TETRA]
    rows += [' '.join(str(i) for i in (len(f),) + f) for f in faces]
    return ('\n'.join(rows) + '\n').encode()


def binary_stl(header=b'solid tetra'):
    """The tetrahedron as a binary STL whose header starts with 'solid', as many writers' do."""
    body = header.ljust(80, b'\0') + struct.pack('<I', len(FACES))
    for f in FACES:
        corners = [c for i in f for c in TETRA[i]]
        body += struct.pack('<12f', 0, 0, 0, *corners) + b'\0\0'
    return body


def obj(vertices=TETRA, faces=FACES):
    lines = ['v ' + ' '.join(str(c) for c in p) for p in vertices]
    lines += ['f ' + ' '.join(str(i + 1) for i in f) for f in faces]
    return ('\n'.join(lines) + '\n').encode()


def models():
    """(file name, bytes, None for a missing file, 'dir' or 'fifo', expected message part)"""
    full = header('binary_little_endian') + binary_body()
    swapped = (b'ply\nformat ascii 1.0\nelement face 4\nproperty list uchar int vertex_indices\n'
               b'element vertex 4\nproperty float x\nproperty float y\nproperty float z\n'
               b'end_header\n')
    asc = ascii_body()
    split = asc.index(b'3 0 1 2')
    return [
        ('cut_binary.ply', full[:len(full) - 30],
         "element 'face' row 1 list 'vertex_indices': count 3 needs 12 bytes"),
        ('index_out_of_range.ply', header('ascii') + ascii_body([(0, 1, 2), (0, 3, 9)] + FACES[2:]),
         "element 'face' row 1 list 'vertex_indices': vertex index 9 is not in [0, 4)"),
        ('negative_index.ply',
         header('binary_little_endian') + binary_body([(0, 1, -1)] + FACES[1:]),
         'vertex index -1 is not in [0, 4)'),
        ('list_count_255.ply', header('binary_little_endian') + binary_body(counts=[3, 3, 3, 255]),
         'count 255 needs 1020 bytes but only 12'),
        ('vertex_count_lies.ply', header('binary_little_endian', vertices=9) + binary_body(),
         "the file ends inside element 'vertex' row 8 of 9"),
        ('face_count_lies.ply', header('ascii', faces=7) + asc,
         "the file ends inside element 'face' row 4 of 7"),
        ('face_before_vertex.ply', swapped + asc[split:] + asc[:split], "needs 'vertex' first"),
        ('no_end_header.ply', header('ascii').replace(b'end_header\n', b'') + asc,
         'is end_header missing?'),
        ('garbage.ply', bytes((i * 73 + 41) % 256 for i in range(2000)), 'not a PLY file'),
        ('empty.ply', b'', 'the file is empty'),
        ('missing.ply', None, 'cannot open: No such file or directory'),
        ('folder.ply', 'dir', 'is a directory'),
        ('empty.stl', b'', 'the file is empty'),
        # STL and OBJ (plod::CheckSTLFile, plod::CheckOBJFile): VTK's readers would read a cut
        # STL in part and a NaN OBJ vertex as (0, 0, 0), and keep an index out of range
        ('cut_binary.stl', binary_stl()[:-30],
         'the file is cut inside triangle 3 of 4 (triangles count from 0; 20 of its 50 bytes'),
        ('nan_vertex.obj', obj([TETRA[0], ('nan', 'nan', 'nan')] + TETRA[2:]),
         "line 2: vertex 2 (OBJ counts from 1) has the coordinate 'nan'"),
        ('index_out_of_range.obj', obj(faces=[(0, 1, 2), (0, 3, 9)] + FACES[2:]),
         "line 6: vertex index 10 in '10' is out of range: 4 are defined before this line"),
        ('missing.obj', None, 'cannot open: No such file or directory'),
        ('folder.vtp', 'dir', 'is a directory'),
        # FIFOs: opening one would wait for a writer; a program must refuse it at once
        ('fifo.ply', 'fifo', 'is not a regular file'),
        ('fifo.stl', 'fifo', 'is not a regular file'),
        ('fifo.plod', 'fifo', 'is not a regular file'),
        # octree files (vtkMultiscaleOctreeReader): recognised by their magic, then refused
        ('short.plod', b'PLODOCT\n' + bytes(20), 'too short for an octree file'),
        ('version9.plod', b'PLODOCT\n' + struct.pack('<I', 9) + bytes(116),
         'octree file format version 9'),
        ('bad_checksum.plod', b'PLODOCT\n' + struct.pack('<4I', 1, 0x01020304, 128, 0) + bytes(104),
         'corrupt header (checksum mismatch)'),
    ]


def main():
    if len(sys.argv) < 2:
        print(__doc__)
        return 2
    # a program that reads PLY with its own reader (plod::ReadPLYMesh) takes the elements in any
    # order, as the format allows; VTK's reader needs 'vertex' first
    own_reader = '--own-ply-reader' in sys.argv
    command = [a for a in sys.argv[1:] if a != '--own-ply-reader']
    failures = 0
    with tempfile.TemporaryDirectory(prefix='plod_corrupt_') as folder:
        for name, content, expect in models():
            path = os.path.join(folder, name)
            if content == 'dir':
                os.mkdir(path)
            elif content == 'fifo':
                os.mkfifo(path)
            elif content is not None:
                with open(path, 'wb') as f:
                    f.write(content)
            try:
                run = subprocess.run(command + [path], capture_output=True, text=True,
                                     errors='replace', timeout=60 if content == 'fifo' else 300)
            except subprocess.TimeoutExpired:
                print(f'FAIL {name}: no answer (hung)')
                failures += 1
                continue
            problems = []
            if own_reader and name == 'face_before_vertex.ply':
                if run.returncode != 0:
                    failures += 1
                    print(f'FAIL {name}: exit {run.returncode}, but its own reader takes any order')
                else:
                    print(f'ok   {name}: read (elements in any order)')
                continue
            if run.returncode < 0:
                problems.append(f'killed by signal {-run.returncode}')
            elif run.returncode == 0:
                problems.append('exit status 0')
            if f'{path}: ' not in run.stderr or expect not in run.stderr:
                problems.append(f'no line "{path}: ...{expect}..." on stderr')
            if 'cannot read a model from' not in run.stderr:
                problems.append('no "cannot read a model from" line')
            if problems:
                failures += 1
                print(f'FAIL {name}: ' + '; '.join(problems))
                print('  stderr: ' + run.stderr.strip().replace('\n', '\n          '))
            else:
                line = next(x for x in run.stderr.splitlines() if x.startswith(path + ': '))
                print(f'ok   {name}: exit {run.returncode}: {line[len(folder) + 1:]}')
    print(f'{failures} failure(s)')
    return 1 if failures else 0


if __name__ == '__main__':
    sys.exit(main())
