"""Python tests of vtkPLYFileCheck: good ASCII and binary files pass with their counts, corrupt
ones fail with a message naming the problem, reader limits can be turned off, and the
measurement harness's read_ply raises ValueError on a corrupt file instead of crashing."""
import os
import shutil
import struct
import sys
import tempfile
import unittest

from perceptual_lod import vtkPLYFileCheck

HERE = os.path.dirname(os.path.abspath(__file__))
QUALITY = os.path.join(HERE, '..', '..', '..', 'Testing', 'Quality')

TETRA = [(1, 1, 1), (1, -1, -1), (-1, 1, -1), (-1, -1, 1)]
FACES = [(0, 1, 2), (0, 3, 1), (0, 2, 3), (1, 3, 2)]


def tetra(fmt, faces=FACES, vertices=4, order='<'):
    head = (f'ply\nformat {fmt} 1.0\ncomment test\nelement vertex {vertices}\n'
            'property float x\nproperty float y\nproperty float z\n'
            f'element face {len(faces)}\nproperty list uchar int vertex_indices\n'
            'end_header\n').encode()
    if fmt == 'ascii':
        rows = [' '.join(map(str, p)) for p in TETRA]
        rows += [' '.join(map(str, (len(f),) + tuple(f))) for f in faces]
        return head + ('\n'.join(rows) + '\n').encode()
    body = b''.join(struct.pack(order + '3f', *p) for p in TETRA)
    for f in faces:
        body += struct.pack(order + 'B', len(f)) + struct.pack(f'{order}{len(f)}i', *f)
    return head + body


class TestPLYFileCheck(unittest.TestCase):
    @classmethod
    def setUpClass(cls):
        cls.folder = tempfile.mkdtemp(prefix='plod_ply_py_')

    @classmethod
    def tearDownClass(cls):
        shutil.rmtree(cls.folder, ignore_errors=True)

    def write(self, name, data):
        path = os.path.join(self.folder, name)
        with open(path, 'wb') as f:
            f.write(data)
        return path

    def check(self, path, limits=True):
        c = vtkPLYFileCheck()
        c.SetFileName(path)
        c.SetReaderLimits(limits)
        return c.Check(), c.GetErrorMessage(), c

    def test_good_files_pass_with_their_counts(self):
        for fmt, order in (('ascii', '<'), ('binary_little_endian', '<'),
                           ('binary_big_endian', '>')):
            with self.subTest(fmt=fmt):
                ok, why, c = self.check(self.write(f'good_{fmt}.ply', tetra(fmt, order=order)))
                self.assertTrue(ok, why)
                self.assertEqual(why, '')
                self.assertEqual(c.GetNumberOfVertices(), 4)
                self.assertEqual(c.GetNumberOfFaces(), 4)
                self.assertEqual(c.GetMaxFaceSize(), 3)
                self.assertEqual(c.GetFormatAsString(), fmt)
                self.assertTrue(vtkPLYFileCheck.CheckFile(c.GetFileName()))

    def test_corrupt_files_fail_with_the_reason(self):
        good = tetra('binary_little_endian')
        cases = {
            'cut.ply': (good[:-5], "row 3 list 'vertex_indices': count 3 needs 12 bytes"),
            'index.ply': (tetra('ascii', [(0, 1, 2), (0, 1, 7)]),
                          "element 'face' row 1 list 'vertex_indices': vertex index 7 is not in"
                          " [0, 4) (line 16)"),
            'negative.ply': (tetra('binary_big_endian', [(0, -2, 1)], order='>'),
                             'vertex index -2'),
            'count.ply': (tetra('ascii', vertices=7), "element 'vertex' row 4 has more values"),
            'header.ply': (good.replace(b'end_header\n', b''), 'no end_header line'),
            'format.ply': (good.replace(b'binary_little_endian', b'binary'),
                           "unknown format 'binary'"),
            'type.ply': (good.replace(b'float y', b'real y'), "unknown property type 'real'"),
            'empty.ply': (b'', 'the file is empty'),
            'garbage.ply': (bytes(range(256)) * 8, 'not a PLY file'),
        }
        for name, (data, expect) in cases.items():
            with self.subTest(name=name):
                path = self.write(name, data)
                ok, why, _ = self.check(path)
                self.assertFalse(ok)
                self.assertIn(expect, why)
                self.assertNotIn('\n', why)
                self.assertFalse(vtkPLYFileCheck.CheckFile(path))
        ok, why, _ = self.check(os.path.join(self.folder, 'missing.ply'))
        self.assertFalse(ok)
        self.assertIn('cannot open', why)
        ok, why, _ = self.check(self.folder)
        self.assertFalse(ok)
        self.assertIn('is a directory', why)
        ok, why, _ = self.check(None)
        self.assertFalse(ok)
        self.assertEqual(why, 'no file name given')

    def test_reader_limits_can_be_turned_off(self):
        # a face of 300 vertices is valid PLY, but VTK 9.1's reader keeps the count in a byte
        big = tetra('ascii').replace(b'list uchar int', b'list ushort int').replace(
            b'\n3 0 1 2\n', b'\n300 ' + b' '.join([b'1'] * 300) + b'\n')
        path = self.write('big_face.ply', big)
        ok, why, c = self.check(path)
        self.assertFalse(ok)
        self.assertIn('a face of 300 vertices; vtkPLYReader (VTK 9.1) reads at most 255', why)
        ok, why, c = self.check(path, limits=False)
        self.assertTrue(ok, why)
        self.assertEqual(c.GetMaxFaceSize(), 300)

    def test_harness_read_ply_raises_on_a_corrupt_file(self):
        sys.path.insert(0, QUALITY)
        try:
            import plod_measure
        finally:
            sys.path.remove(QUALITY)
        good = plod_measure.read_ply(self.write('harness_good.ply', tetra('binary_big_endian',
                                                                          order='>')))
        self.assertEqual(good.GetNumberOfPoints(), 4)
        self.assertEqual(good.GetNumberOfPolys(), 4)
        path = self.write('harness_bad.ply', tetra('ascii', [(0, 1, 9)]))
        with self.assertRaisesRegex(ValueError, 'harness_bad.ply: .*vertex index 9 is not in'):
            plod_measure.read_ply(path)
        with self.assertRaisesRegex(ValueError, 'cannot open'):
            plod_measure.read_ply(os.path.join(self.folder, 'nothing_here.ply'))

    def test_stanford_files_pass(self):
        data = os.environ.get('PLOD_DATA_DIR', os.path.join(HERE, '..', '..', '..', '..',
                                                            'shared', 'data'))
        if not os.path.isfile(os.path.join(data, 'bun_zipper.ply')):
            self.skipTest('../shared/data (Stanford scans) not found: set PLOD_DATA_DIR')
        names = sorted(n for n in os.listdir(data) if n.endswith('.ply'))
        self.assertGreaterEqual(len(names), 15)
        for name in names:
            with self.subTest(name=name):
                ok, why, c = self.check(os.path.join(data, name))
                self.assertTrue(ok, why)
                self.assertGreater(c.GetNumberOfVertices(), 0)


if __name__ == '__main__':
    unittest.main()
