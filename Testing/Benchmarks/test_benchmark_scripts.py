"""The Python benchmark scripts run: on a small octree file, each one a few frames or one
repeat, exit 0 and print the lines docs/benchmarks.md quotes (so that a change of API does not
leave them broken until the next measurement). Figures are not checked: speed is measured, not
tested."""
import os
import subprocess
import sys
import tempfile
import unittest

from vtkmodules.vtkFiltersSources import vtkSphereSource
from vtkmodules.vtkIOPLY import vtkPLYWriter

from perceptual_lod import vtkMultiscaleOctreeBuilder, vtkMultiscaleOctreeWriter

HERE = os.path.dirname(os.path.abspath(__file__))


class BenchmarkScriptsTest(unittest.TestCase):
    @classmethod
    def setUpClass(cls):
        cls.folder = tempfile.TemporaryDirectory(prefix='plod_bench_')
        cls.octree = os.path.join(cls.folder.name, 'sphere.plod')
        sphere = vtkSphereSource()
        sphere.SetThetaResolution(60)
        sphere.SetPhiResolution(60)
        builder = vtkMultiscaleOctreeBuilder()
        builder.SetInputConnection(sphere.GetOutputPort())
        writer = vtkMultiscaleOctreeWriter()
        writer.SetInputConnection(builder.GetOutputPort())
        writer.SetFileName(cls.octree)
        assert writer.Write() == 1, writer.GetErrorMessage()

    @classmethod
    def tearDownClass(cls):
        cls.folder.cleanup()

    def run_script(self, *args):
        done = subprocess.run([sys.executable, os.path.join(HERE, args[0])] + list(args[1:]),
                              capture_output=True, text=True, env=dict(os.environ))
        self.assertEqual(done.returncode, 0, done.stderr)
        return done.stdout

    def test_flight(self):
        out = self.run_script('plod_flight.py', self.octree, '--frames', '6', '--cache-limit',
                              '1')
        self.assertIn('first frame', out)
        self.assertIn('the mapped octree resident', out)
        self.assertIn('resident MiB over the flight', out)
        self.assertIn('resident at the last frame', out)

    def test_flight_with_background_loading(self):
        out = self.run_script('plod_flight.py', self.octree, '--frames', '6',
                              '--background-loading')
        self.assertIn('first frame', out)
        self.assertIn('background loading:', out)
        self.assertIn('refinements read by the thread', out)

    @unittest.skipUnless(os.environ.get('DISPLAY'), 'the rendered flight needs an X display '
                         '(run under xvfb-run -a)')
    def test_flight_rendered(self):
        out = self.run_script('plod_flight.py', self.octree, '--frames', '4', '--render',
                              '--background-loading')
        self.assertIn('frames timed: whole', out)
        self.assertIn('first frame', out)
        self.assertIn('background loading:', out)

    def test_orbit(self):
        out = self.run_script('patches_orbit.py', self.octree, '--frames', '4', '--budget',
                              '500', '--exact')
        self.assertIn('patches median', out)

    @unittest.skipUnless(os.environ.get('DISPLAY'), 'needs a display (xvfb-run)')
    def test_pieces_coarse(self):
        ply = os.path.join(self.folder.name, 'sphere.ply')
        pieces = os.path.join(self.folder.name, 'sphere-pieces.plod')
        sphere = vtkSphereSource()  # fine enough for a finest level below the pieces' (6)
        sphere.SetThetaResolution(400)
        sphere.SetPhiResolution(400)
        writer = vtkPLYWriter()
        writer.SetInputConnection(sphere.GetOutputPort())
        writer.SetFileName(ply)
        self.assertEqual(writer.Write(), 1)
        builder = vtkMultiscaleOctreeBuilder()
        builder.SetFileName(ply)
        builder.SetOctreeFileName(pieces)
        builder.BuildInPiecesOn()
        builder.Update()
        self.assertGreater(builder.GetOutput().GetNumberOfNodes(), 0)
        out = self.run_script('pieces_coarse.py', ply, pieces)
        self.assertIn('| far/64 |', out)
        self.assertIn('coarsest drawn level 0', out)

    def test_file_layouts(self):
        out = self.run_script('file_layouts.py', self.octree, '--repeats', '1', '--tmp',
                              self.folder.name)
        self.assertIn('| mapped |', out)
        self.assertIn('| compact |', out)


if __name__ == '__main__':
    unittest.main()
