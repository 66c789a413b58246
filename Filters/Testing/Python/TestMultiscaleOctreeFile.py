"""Octree files from Python: vtkMultiscaleOctreeWriter and vtkMultiscaleOctreeReader. The arrays
read back are numpy-identical to those built, the reader maps the file (edits stay in memory),
the compact layout reads back identical in fewer bytes, and a damaged file gives an error and an
empty octree."""
import os
import tempfile
import unittest

import numpy as np
from vtkmodules.util.numpy_support import vtk_to_numpy
from vtkmodules.vtkCommonCore import vtkCommand
from vtkmodules.vtkFiltersSources import vtkSphereSource

from perceptual_lod import (vtkMultiscaleOctreeBuilder, vtkMultiscaleOctreeReader,
                            vtkMultiscaleOctreeWriter)


class Errors:
    def __init__(self, obj):
        self.messages = []
        obj.AddObserver(vtkCommand.ErrorEvent, self.on_error)

    def on_error(self, caller, event, data=None):
        self.messages.append(str(data))

    on_error.CallDataType = 'string0'


class OctreeFileTest(unittest.TestCase):
    def setUp(self):
        self.folder = tempfile.TemporaryDirectory(prefix='plod_file_')
        self.path = os.path.join(self.folder.name, 'sphere.plod')
        sphere = vtkSphereSource()
        sphere.SetThetaResolution(40)
        sphere.SetPhiResolution(40)
        self.builder = vtkMultiscaleOctreeBuilder()
        self.builder.SetInputConnection(sphere.GetOutputPort())
        writer = vtkMultiscaleOctreeWriter()
        writer.SetInputConnection(self.builder.GetOutputPort())
        writer.SetFileName(self.path)
        self.assertEqual(writer.Write(), 1, writer.GetErrorMessage())

    def tearDown(self):
        self.folder.cleanup()

    def read(self, path, verify=False):
        reader = vtkMultiscaleOctreeReader()
        errors = Errors(reader)
        reader.SetFileName(path)
        reader.SetVerifyChecksums(verify)
        reader.Update()
        return reader, errors

    def test_round_trip_is_identical(self):
        built = self.builder.GetOutput()
        reader, errors = self.read(self.path, verify=True)
        self.assertEqual(errors.messages, [])
        self.assertTrue(reader.GetMapped())
        read = reader.GetOutput()
        self.assertEqual(read.GetNumberOfNodes(), built.GetNumberOfNodes())
        self.assertEqual(read.GetOrigin(), built.GetOrigin())
        self.assertEqual(read.GetRootEdge(), built.GetRootEdge())
        for group in ('GetNodeData', 'GetClusterData', 'GetSurfaceData'):
            a, b = getattr(built, group)(), getattr(read, group)()
            self.assertEqual(a.GetNumberOfArrays(), b.GetNumberOfArrays(), group)
            for i in range(a.GetNumberOfArrays()):
                name = a.GetArrayName(i)
                x, y = vtk_to_numpy(a.GetArray(name)), vtk_to_numpy(b.GetArray(name))
                self.assertEqual(x.dtype, y.dtype, name)
                self.assertTrue(np.array_equal(x.view(np.uint8), y.view(np.uint8)), name)

    def test_compact_file_is_identical_and_smaller(self):
        compact = os.path.join(self.folder.name, 'compact.plod')
        writer = vtkMultiscaleOctreeWriter()
        writer.SetInputConnection(self.builder.GetOutputPort())
        writer.SetFileName(compact)
        writer.CompactOn()
        self.assertEqual(writer.Write(), 1, writer.GetErrorMessage())
        self.assertLess(os.path.getsize(compact), os.path.getsize(self.path) / 2)
        reader, errors = self.read(compact)
        self.assertEqual(errors.messages, [])
        self.assertTrue(reader.GetCompact())
        self.assertFalse(reader.GetMapped())
        built, read = self.builder.GetOutput(), reader.GetOutput()
        for group in ('GetNodeData', 'GetClusterData', 'GetSurfaceData'):
            a, b = getattr(built, group)(), getattr(read, group)()
            for i in range(a.GetNumberOfArrays()):
                name = a.GetArrayName(i)
                x, y = vtk_to_numpy(a.GetArray(name)), vtk_to_numpy(b.GetArray(name))
                self.assertTrue(np.array_equal(x.view(np.uint8), y.view(np.uint8)), name)

    def test_edits_stay_in_memory(self):
        reader, _ = self.read(self.path)
        shape = vtk_to_numpy(reader.GetOutput().GetNodeData().GetArray('ShapeError'))
        with open(self.path, 'rb') as f:
            before = f.read()
        shape[:] = 0.0  # copy-on-write: the file keeps its values
        with open(self.path, 'rb') as f:
            self.assertEqual(f.read(), before)

    def test_damaged_files_are_errors(self):
        with open(self.path, 'rb') as f:
            good = f.read()
        cases = {
            'truncated': (good[:len(good) // 2], 'truncated'),
            'foreign': (b'solid x\nendsolid x\n' * 10, 'not an octree file'),
            'version': (good[:8] + b'\x07' + good[9:], 'version 7'),
            'flipped header': (good[:70] + bytes([good[70] ^ 1]) + good[71:], 'corrupt header'),
        }
        for name, (content, phrase) in cases.items():
            path = os.path.join(self.folder.name, name + '.plod')
            with open(path, 'wb') as f:
                f.write(content)
            reader, errors = self.read(path)
            self.assertIn(phrase, reader.GetErrorMessage(), name)
            self.assertTrue(errors.messages, name)
            self.assertEqual(reader.GetOutput().GetNumberOfNodes(), 0, name)
        # damaged data: the checksums find it
        data = bytearray(good)
        data[len(data) - 5] ^= 0xff
        path = os.path.join(self.folder.name, 'data.plod')
        with open(path, 'wb') as f:
            f.write(bytes(data))
        reader, errors = self.read(path, verify=True)
        self.assertIn('checksum', reader.GetErrorMessage())
        self.assertEqual(reader.GetOutput().GetNumberOfNodes(), 0)


if __name__ == '__main__':
    unittest.main()
