"""The image metrics against hand-computed values."""
import math
import unittest

import numpy as np

import plod_metrics as m


class TestMetrics(unittest.TestCase):
    def setUp(self):
        rng = np.random.default_rng(1)
        self.image = rng.integers(0, 256, size=(64, 80)).astype(np.float64)

    def test_identical_images(self):
        self.assertEqual(m.psnr(self.image, self.image), math.inf)
        self.assertAlmostEqual(m.ssim(self.image, self.image), 1.0, places=12)

    def test_known_noise(self):
        # +-d on alternate pixels: MSE = d^2 exactly, PSNR = 10 log10(255^2 / d^2)
        d = 5.0
        noise = np.where((np.indices(self.image.shape).sum(axis=0) % 2) == 0, d, -d)
        self.assertAlmostEqual(m.psnr(self.image, self.image + noise),
                               10 * math.log10(255.0 ** 2 / d ** 2), places=12)
        self.assertAlmostEqual(m.psnr(self.image, self.image + 1.0), 20 * math.log10(255.0),
                               places=12)

    def test_one_pixel_shift(self):
        # a vertical step edge (0 left, 200 right) shifted by one pixel: one column of 64 pixels
        # differs by 200 out of 64 x 80: MSE = 200^2 / 80
        a = np.zeros((64, 80))
        a[:, 40:] = 200
        b = np.zeros((64, 80))
        b[:, 41:] = 200
        self.assertAlmostEqual(m.psnr(a, b), 10 * math.log10(255.0 ** 2 * 80 / 200.0 ** 2),
                               places=12)
        self.assertLess(m.ssim(a, b), 1.0)

    def test_ssim_of_constant_images(self):
        # constant x and y: sigma terms vanish, SSIM = (2xy + C1) / (x^2 + y^2 + C1)
        x, y = 100.0, 120.0
        c1 = (0.01 * 255) ** 2
        self.assertAlmostEqual(m.ssim(np.full((32, 32), x), np.full((32, 32), y)),
                               (2 * x * y + c1) / (x * x + y * y + c1), places=12)

    def test_ssim_is_symmetric_and_bounded(self):
        noisy = self.image + np.random.default_rng(2).normal(0, 20, self.image.shape)
        s = m.ssim(self.image, noisy)
        self.assertAlmostEqual(s, m.ssim(noisy, self.image), places=12)
        self.assertTrue(0 < s < 1)

    def test_perceptual_metric(self):
        # a flat grey disc on black has no visible detail inside, edges only; a textured disc
        # has more visible detail pixels; an empty image has no object pixels
        # (a level-j coefficient covers 2^j pixels: 3 levels on a 256-pixel image keep the
        # edge ring of the flat disc narrow)
        yy, xx = np.indices((256, 256))
        disc = ((yy - 128) ** 2 + (xx - 128) ** 2) < 100 ** 2
        flat = np.where(disc, 128.0, 0.0)
        textured = np.where(disc, 128.0 + 60.0 * ((xx // 2 + yy // 2) % 2), 0.0)
        ppd = m.pixels_per_degree(30, 256)
        pm_flat, vps_flat, tps = m.perceptual_metric(flat, 0.0, ppd, levels=3)
        pm_tex, vps_tex, tps_tex = m.perceptual_metric(textured, 0.0, ppd, levels=3)
        self.assertEqual(tps, int(disc.sum()))
        self.assertEqual(tps_tex, tps)
        self.assertLess(pm_flat, 0.25)
        self.assertGreater(pm_tex, pm_flat)
        self.assertEqual(m.perceptual_metric(np.zeros((16, 16)), 0.0, ppd), (0.0, 0, 0))
        # the Haar details of a constant image are zero
        for _, d in m.haar_details(np.full((16, 16), 7.0), 3):
            self.assertEqual(d.max(), 0.0)
        # the CSF peaks at 1 near 8 cycles/degree and falls at both ends
        self.assertAlmostEqual(float(m.csf(np.array([8.0]))[0]), 1.0, places=2)
        self.assertLess(float(m.csf(np.array([0.5]))[0]), 0.5)
        self.assertLess(float(m.csf(np.array([60.0]))[0]), 0.2)


if __name__ == '__main__':
    unittest.main()
