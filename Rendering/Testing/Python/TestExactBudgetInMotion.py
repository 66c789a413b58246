"""The exact triangle budget (vtkPerceptualLODSelector's default) on a real scan in motion (run
under xvfb-run -a; skips without ../shared/data): Lucy moved as the TMM examination moves it
(Testing/Quality/plod_tmm.py: plod_measure's translation T at 0.5 and 1 times its speed, frames
1/60 and 1/30 s apart, the render binding on a simulated clock), SRCC and TMM with the
examination's budgets (B = 3058 and B/2 = 1529, the tolerances 1/16 of the papers' as the floor).
Issue 27: every frame draws at most its budget, and at least 90 % of it where the tolerance cut
would draw more; the selector reports what the patch generator draws. Before the exact count's steps down grew with each walk that
still drew too many, SRCC drew 1531 and 1530 triangles of 1529 in two frames here."""
import math
import os
import sys
import unittest

HERE = os.path.dirname(os.path.abspath(__file__))
sys.path.insert(0, os.path.join(HERE, '..', '..', '..', 'Testing', 'Quality'))
import plod_measure as pm  # noqa: E402
import plod_scene  # noqa: E402
import plod_tmm  # noqa: E402

DATA = os.environ.get('PLOD_DATA_DIR', os.path.join(HERE, '..', '..', '..', '..', 'shared', 'data'))
LUCY = os.path.join(DATA, 'lucy.ply')


@unittest.skipUnless(os.path.exists(LUCY), f'{LUCY} not found (the Stanford data): skipped')
class ExactBudgetInMotion(unittest.TestCase):
    def test_every_frame_within_its_budget(self):
        scene = plod_scene.Scene(plod_scene.read_ply(LUCY), 'lucy', (640, 480), level=8)
        s = scene.selector
        self.assertTrue(s.GetExactTriangleBudget())  # the default
        distance = 1.5 * scene.radius / math.sin(math.radians(scene.view_angle) / 2)
        frames = binding = 0
        for speed in (0.5, 1.0):
            move = plod_tmm.scaled_movement('T', speed)
            for dt in (1 / 60, 1 / 30):
                for mode in ('SRCC', 'TMM'):
                    for budget in (1529, 3058):
                        pm.set_method(scene, mode, plod_tmm.FLOOR)
                        s.SetFrameInterval(dt)
                        s.SetTriangleBudget(budget)
                        offset, angle, dist = move(scene, -2 * dt, distance)
                        scene.start_clock()
                        scene.at(-2 * dt)
                        scene.set_view(dist, offset, angle)
                        for k in range(11):
                            offset, angle, dist = move(scene, (k - 1) * dt, distance)
                            scene.at((k - 1) * dt)
                            scene.set_view(dist, offset, angle)
                            _, drawn, _, _ = scene.lod()
                            what = f'{mode} speed {speed} dt {dt:.4f} budget {budget} frame {k}'
                            self.assertLessEqual(drawn, budget, what)
                            self.assertEqual(s.GetNumberOfBudgetTriangles(), drawn, what)
                            if s.GetBudgetWasBinding():  # (the tolerance cut draws more)
                                self.assertGreaterEqual(drawn, 0.9 * budget, what)
                                binding += 1
                            frames += 1
        s.SetTriangleBudget(0)
        self.assertEqual(frames, 176)
        self.assertGreater(binding, 100)


if __name__ == '__main__':
    unittest.main()
