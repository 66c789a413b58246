"""The image metrics against hand-computed values, independent implementations and
synthetic stimuli whose answer is known.

- PSNR and SSIM against scikit-image (skipped with a message when it is missing) and against a
  direct per-window SSIM written here from Wang et al. 2004 (no skimage needed).
- luminance, the Haar decomposition and the CSF against hand values and the published formula.
- Zhu's PM on sinusoidal gratings: a grating of period 2^j pixels, phased so that each level-j
  block holds one period with the positive lobe in its left half, has the same level-j detail
  in every block, known in closed form (see aligned_haar_gain); with the level's mean equal to
  the grating's mean, it is visible exactly when contrast * gain * CSF(ppd / 2^j) exceeds the
  threshold. The tests find that boundary by bisection on perceptual_metric and compare it with
  the prediction at 2, 4, 8 and 16 cycles per degree, and check the outline of a flat object is
  never counted as detail.
"""
import math
import unittest

import numpy as np
from numpy.lib.stride_tricks import sliding_window_view

import plod_metrics as m

try:
    from skimage.metrics import peak_signal_noise_ratio, structural_similarity
    SKIMAGE_MISSING = None
except ImportError as error:  # CI installs python3-skimage (scripts/install-deps.sh)
    SKIMAGE_MISSING = ('scikit-image is not installed (apt install python3-skimage): '
                       'the cross-check of PSNR/SSIM against it is skipped (%s)' % error)


class TestMetrics(unittest.TestCase):
    def setUp(self):
        rng = np.random.default_rng(1)
        self.image = rng.integers(0, 256, size=(64, 80)).astype(np.float64)

    def test_identical_images(self):
        self.assertEqual(m.psnr(self.image, self.image), math.inf)
        self.assertAlmostEqual(m.ssim(self.image, self.image), 1.0, places=12)

    def test_erode_is_a_square_with_background_outside(self):
        mask = np.zeros((7, 7), dtype=bool)
        mask[1:6, 1:6] = True
        want = np.zeros((7, 7), dtype=bool)
        want[2:5, 2:5] = True
        np.testing.assert_array_equal(m.erode(mask, 1), want)
        self.assertEqual(int(m.erode(mask, 2).sum()), 1)
        self.assertTrue(m.erode(mask, 2)[3, 3])
        full = np.ones((5, 5), dtype=bool)
        want = np.zeros((5, 5), dtype=bool)
        want[1:4, 1:4] = True
        np.testing.assert_array_equal(m.erode(full, 1), want)

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
        # a flat grey disc on black has no visible detail (its outline is not detail either:
        # pm_flat is 0, see TestPerceptualOutline); a textured disc has more visible detail
        # pixels; an empty image has no object pixels
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


# ---------------------------------------------------------------------------------------------
# Independent references, written from the papers, sharing no code with plod_metrics.

def reference_ssim_map(a, b, size=11, sigma=1.5, k1=0.01, k2=0.03, peak=255.0):
    """SSIM (Wang et al. 2004, eq. 13) of every size x size window lying wholly inside the
    images: weighted means, centred variances and covariance over each window, with the 2-D
    Gaussian weights built as one normalised array."""
    r = (size - 1) // 2
    y, x = np.mgrid[-r:r + 1, -r:r + 1]
    w = np.exp(-(x * x + y * y) / (2.0 * sigma * sigma))
    w /= w.sum()
    wa = sliding_window_view(np.asarray(a, dtype=np.float64), (size, size))
    wb = sliding_window_view(np.asarray(b, dtype=np.float64), (size, size))
    mu_a = np.einsum('ijkl,kl->ij', wa, w)
    mu_b = np.einsum('ijkl,kl->ij', wb, w)
    da = wa - mu_a[:, :, None, None]
    db = wb - mu_b[:, :, None, None]
    var_a = np.einsum('ijkl,kl->ij', da * da, w)
    var_b = np.einsum('ijkl,kl->ij', db * db, w)
    cov = np.einsum('ijkl,kl->ij', da * db, w)
    c1, c2 = (k1 * peak) ** 2, (k2 * peak) ** 2
    return ((2 * mu_a * mu_b + c1) * (2 * cov + c2)
            / ((mu_a ** 2 + mu_b ** 2 + c1) * (var_a + var_b + c2)))


def mannos_sakrison(f):
    """Mannos & Sakrison 1974: A(f) = 2.6 (0.0192 + 0.114 f) exp(-(0.114 f)^1.1)."""
    return 2.6 * (0.0192 + 0.114 * f) * math.exp(-(0.114 * f) ** 1.1)


def mannos_sakrison_peak():
    """Frequency of the CSF's maximum by golden-section search (it is unimodal)."""
    lo, hi = 1.0, 30.0
    k = (math.sqrt(5) - 1) / 2
    while hi - lo > 1e-10:
        x1, x2 = hi - k * (hi - lo), lo + k * (hi - lo)
        if mannos_sakrison(x1) < mannos_sakrison(x2):
            lo = x1
        else:
            hi = x2
    return (lo + hi) / 2


CSF_PEAK_FREQUENCY = mannos_sakrison_peak()


def reference_csf(f):
    return mannos_sakrison(f) / mannos_sakrison(CSF_PEAK_FREQUENCY)


def reference_haar(image, level):
    """Level-`level` Haar coefficients straight from the original pixels: a level-j block of
    2^j x 2^j pixels has approximation = its mean, LH = (mean of left half - mean of right
    half) / 2, HL = (top half - bottom half) / 2, HH = (top-left + bottom-right - top-right -
    bottom-left quarter means) / 4. Returns (|LH| + |HL| + |HH|, approximation)."""
    b = 2 ** level
    h, w = image.shape[0] // b, image.shape[1] // b
    blocks = np.asarray(image, dtype=np.float64)[:h * b, :w * b].reshape(h, b, w, b)
    k = b // 2

    def mean(rows, cols):
        return blocks[:, rows][:, :, :, cols].mean(axis=(1, 3))
    top, bottom, left, right = slice(0, k), slice(k, b), slice(0, k), slice(k, b)
    lh = (mean(slice(0, b), left) - mean(slice(0, b), right)) / 2
    hl = (mean(top, slice(0, b)) - mean(bottom, slice(0, b))) / 2
    hh = (mean(top, left) + mean(bottom, right) - mean(top, right) - mean(bottom, left)) / 4
    return np.abs(lh) + np.abs(hl) + np.abs(hh), blocks.mean(axis=(1, 3))


def grating(period, contrast, mean=100.0, shape=(64, 256), bars='vertical'):
    """A sinusoidal grating of Michelson contrast `contrast` about `mean`, `period` pixels per
    cycle, sampled at pixel centres and phased so that every block of `period` pixels starting
    at a multiple of `period` holds one cycle, its positive lobe first. 'vertical' bars vary
    along x (Haar LH), 'horizontal' ones along y (HL)."""
    n = shape[1] if bars == 'vertical' else shape[0]
    profile = mean * (1.0 + contrast * np.sin(2 * np.pi * (np.arange(n) + 0.5) / period))
    if bars == 'vertical':
        return np.tile(profile, (shape[0], 1))
    return np.tile(profile[:, None], (1, shape[1]))


def aligned_haar_gain(period):
    """|LH| / (contrast * mean) of a grating() at the level j with 2^j = period: the left half
    of each block holds the positive lobe, n = period / 2 samples sin(pi (k + 1/2) / n), whose
    mean is 1 / (n sin(pi / (2 n))); the right half holds the opposite; LH is half the
    difference of the two means. (1 for period 2, falling to 2 / pi.)"""
    n = period // 2
    return 1.0 / (n * math.sin(math.pi / (2 * n)))


def predicted_threshold_contrast(period, ppd, threshold=0.02):
    """The contrast at which the aligned level's CSF-weighted contrast reaches the threshold
    (the level's mean is the grating's mean: a block holds whole cycles)."""
    return threshold / (reference_csf(ppd / period) * aligned_haar_gain(period))


# ---------------------------------------------------------------------------------------------

def image_pairs():
    """(name, a, b): random, noisy, structured, shifted, rescaled, non-square and odd sizes."""
    rng = np.random.default_rng(12)
    pairs = []
    a = rng.integers(0, 256, size=(37, 53)).astype(np.float64)
    pairs.append(('uniform noise + gaussian noise',
                  a, np.clip(a + rng.normal(0, 25, a.shape), 0, 255)))
    pairs.append(('two independent noises', rng.uniform(0, 255, (40, 40)),
                  rng.uniform(0, 255, (40, 40))))
    yy, xx = np.indices((48, 64))
    ramp = 2.0 * xx + 1.5 * yy + np.where(xx > 30, 60.0, 0.0)
    blurred = ramp.copy()
    blurred[1:-1, 1:-1] = sum(ramp[1 + dy:ramp.shape[0] - 1 + dy, 1 + dx:ramp.shape[1] - 1 + dx]
                              for dy in (-1, 0, 1) for dx in (-1, 0, 1)) / 9.0
    pairs.append(('ramp with an edge + box blur', ramp, blurred))
    checker = 40.0 + 150.0 * (((yy // 3) + (xx // 5)) % 2)
    pairs.append(('checkerboard + one pixel shift', checker, np.roll(checker, 1, axis=1)))
    pairs.append(('constant + texture', np.full((24, 30), 90.0),
                  90.0 + 30 * np.sin(np.indices((24, 30))[1] * 0.9)))
    pairs.append(('contrast and brightness change', a, 0.5 * a + 60.0))
    pairs.append(('dark low-variance image', rng.uniform(0, 4, (31, 29)),
                  rng.uniform(0, 4, (31, 29))))
    return pairs


class TestAgainstReferences(unittest.TestCase):
    def test_ssim_against_direct_windows(self):
        for name, a, b in image_pairs():
            with self.subTest(name):
                self.assertAlmostEqual(m.ssim(a, b), float(reference_ssim_map(a, b).mean()),
                                       delta=1e-9)

    def test_psnr_formula(self):
        for name, a, b in image_pairs():
            with self.subTest(name):
                mse = float(np.mean((a - b) ** 2))
                self.assertAlmostEqual(m.psnr(a, b), 20 * math.log10(255.0) - 10 * math.log10(mse),
                                       delta=1e-9)

    @unittest.skipIf(SKIMAGE_MISSING, SKIMAGE_MISSING)
    def test_against_skimage(self):
        for name, a, b in image_pairs():
            with self.subTest(name):
                self.assertAlmostEqual(m.psnr(a, b), peak_signal_noise_ratio(a, b, data_range=255),
                                       delta=1e-9)
                mssim, smap = structural_similarity(
                    a, b, win_size=11, gaussian_weights=True, sigma=1.5,
                    use_sample_covariance=False, data_range=255, K1=0.01, K2=0.03, full=True)
                self.assertAlmostEqual(m.ssim(a, b), mssim, delta=1e-9)
                # skimage pads, filters, then averages the map cropped by (11 - 1) / 2 on each
                # side: exactly the windows lying wholly inside, our 'valid' mean
                crop = smap[5:-5, 5:-5]
                self.assertAlmostEqual(float(crop.mean()), mssim, delta=1e-12)
                np.testing.assert_allclose(crop, reference_ssim_map(a, b), rtol=0, atol=1e-9)

    def test_luminance_rec709(self):
        rgb = np.array([[[255, 0, 0], [0, 255, 0], [0, 0, 255], [255, 255, 255], [0, 0, 0]]],
                       dtype=np.uint8)
        np.testing.assert_allclose(m.luminance(rgb),
                                   [[0.2126 * 255, 0.7152 * 255, 0.0722 * 255, 255.0, 0.0]],
                                   rtol=1e-12, atol=1e-12)

    def test_haar_by_hand(self):
        image = np.array([[8, 0, 2, 2],
                          [0, 0, 2, 2],
                          [1, 3, 5, 5],
                          [1, 3, 1, 1]], dtype=np.float64)
        (l1, d1, a1), (l2, d2, a2) = m.haar_details(image, 2, with_mean=True)
        self.assertEqual((l1, l2), (1, 2))
        # level 1: LH = HL = HH = 2 | flat | LH = -1 | HL = 2
        np.testing.assert_array_equal(d1, [[6.0, 0.0], [1.0, 2.0]])
        np.testing.assert_array_equal(a1, [[2.0, 2.0], [2.0, 3.0]])
        # level 2 on the approximation: LH = HL = -1/4, HH = 1/4
        np.testing.assert_array_equal(d2, [[0.75]])
        np.testing.assert_array_equal(a2, [[2.25]])
        # without the mean: the same details
        self.assertEqual([lv for lv, _ in m.haar_details(image, 2)], [1, 2])

    def test_haar_against_block_means(self):
        rng = np.random.default_rng(5)
        image = rng.uniform(0, 255, (64, 96))
        for level, detail, mean in m.haar_details(image, 4, with_mean=True):
            ref_detail, ref_mean = reference_haar(image, level)
            np.testing.assert_allclose(detail, ref_detail, rtol=0, atol=1e-9)
            np.testing.assert_allclose(mean, ref_mean, rtol=0, atol=1e-9)

    def test_csf_is_mannos_sakrison_normalised(self):
        self.assertTrue(7.8 < CSF_PEAK_FREQUENCY < 8.0, CSF_PEAK_FREQUENCY)
        for f in (0.25, 0.5, 1, 2, 4, CSF_PEAK_FREQUENCY, 8, 12, 16, 32, 45):
            self.assertAlmostEqual(float(m.csf(f)) / reference_csf(f), 1.0, delta=1e-6, msg=f)
        np.testing.assert_allclose(m.csf(np.array([2.0, 16.0])),
                                   [reference_csf(2.0), reference_csf(16.0)], rtol=1e-6)

    def test_pixels_per_degree(self):
        # the mean over the field of view: image height / vertical view angle
        self.assertEqual(m.pixels_per_degree(30.0, 480), 16.0)
        self.assertEqual(m.pixels_per_degree(20.0, 640), 32.0)


class TestPerceptualGratings(unittest.TestCase):
    def visibility(self, image, ppd, **kwargs):
        pm, vps, tps = m.perceptual_metric(image, 0.0, ppd, **kwargs)
        self.assertEqual(tps, image.size)  # every pixel differs from the black background
        return vps

    def boundary(self, period, ppd, bars='vertical', mean=100.0, **kwargs):
        """The contrast where the grating's first pixel becomes visible, by bisection."""
        lo, hi = 0.0, 0.9
        while hi - lo > 1e-9:
            c = (lo + hi) / 2
            if self.visibility(grating(period, c, mean, bars=bars), ppd, **kwargs) > 0:
                hi = c
            else:
                lo = c
        return hi

    def test_grating_haar_response_is_analytic(self):
        contrast, mean = 0.1, 100.0
        for period in (4, 8, 16, 32):
            j = int(math.log2(period))
            for bars in ('vertical', 'horizontal'):
                image = grating(period, contrast, mean, bars=bars)
                for level, detail, approx in m.haar_details(image, 6, with_mean=True):
                    ref_detail, ref_mean = reference_haar(image, level)
                    np.testing.assert_allclose(detail, ref_detail, rtol=0, atol=1e-9)
                    np.testing.assert_allclose(approx, ref_mean, rtol=0, atol=1e-9)
                    if level == j:
                        np.testing.assert_allclose(
                            detail, contrast * mean * aligned_haar_gain(period), rtol=1e-12)
                    if level >= j:  # blocks of whole cycles
                        np.testing.assert_allclose(approx, mean, rtol=1e-12)
                    if level == j - 1:  # half a cycle, symmetric about the block's centre
                        np.testing.assert_allclose(detail, 0.0, atol=1e-9)

    def check_boundaries(self, cases, **kwargs):
        threshold = kwargs.get('threshold', 0.02)
        for period, ppd, bars in cases:
            f = ppd / period
            with self.subTest(period=period, ppd=ppd, cycles_per_degree=f, bars=bars):
                predicted = predicted_threshold_contrast(period, ppd, threshold)
                # set-up: just below the prediction no other level reaches the threshold
                image = grating(period, predicted * 0.999, bars=bars)
                for level in range(1, kwargs.get('levels', 4) + 1):
                    if level != int(math.log2(period)):
                        detail, mean = reference_haar(image, level)
                        weighted = detail * reference_csf(ppd / 2 ** level) / mean
                        self.assertLess(weighted.max(), 0.95 * threshold, level)
                found = self.boundary(period, ppd, bars=bars, **kwargs)
                # the boundary tracks 1 / CSF(f)
                self.assertAlmostEqual(found / predicted, 1.0, delta=1e-6)
                self.assertAlmostEqual(found * reference_csf(f) * aligned_haar_gain(period),
                                       threshold, delta=1e-7)
                # the whole grating appears at once: nothing 1 % below, everything 1 % above
                self.assertEqual(self.visibility(grating(period, predicted * 0.99, bars=bars),
                                                 ppd, **kwargs), 0)
                above = grating(period, predicted * 1.01, bars=bars)
                self.assertEqual(self.visibility(above, ppd, **kwargs), above.size)

    def test_boundary_over_ppd(self):
        # one grating of 8 pixels (Haar level 3) at 2, 4, 8 and 16 cycles per degree; the
        # default levels and threshold
        ppds = [m.pixels_per_degree(30.0, h) for h in (480, 960, 1920, 3840)]
        self.assertEqual(ppds, [16.0, 32.0, 64.0, 128.0])
        self.check_boundaries([(8, ppd, 'vertical') for ppd in ppds])

    def test_boundary_over_levels(self):
        # 64 pixels per degree, periods 32, 16, 8 and 4 pixels (Haar levels 5 to 2): 2, 4, 8
        # and 16 cycles per degree, both orientations, another threshold
        cases = [(p, 64.0, bars) for p in (32, 16, 8, 4) for bars in ('vertical', 'horizontal')]
        self.check_boundaries(cases, levels=5, threshold=0.03)

    def test_default_levels_reach_level_4(self):
        # a 16-pixel grating is seen through level 4, which the default 4 levels include
        predicted = predicted_threshold_contrast(16, 64.0)
        above = grating(16, predicted * 1.01)
        self.assertEqual(self.visibility(above, 64.0), above.size)

    def test_octave(self):
        # 8 pixels at 64 pixels per degree is 8 cycles/degree, the CSF's peak: a contrast 10 %
        # above its threshold is visible, and would not be with the frequency one octave off
        # either way (4 or 16 cycles/degree)
        c = 1.1 * predicted_threshold_contrast(8, 64.0)
        self.assertLess(c, predicted_threshold_contrast(8, 32.0))
        self.assertLess(c, predicted_threshold_contrast(8, 128.0))
        image = grating(8, c)
        self.assertEqual(self.visibility(image, 64.0), image.size)
        # and 16 cycles/degree (4 pixels): 10 % below its threshold, invisible, though
        # visible at 8 cycles/degree (one octave coarser)
        c = 0.9 * predicted_threshold_contrast(4, 64.0)
        self.assertGreater(c, predicted_threshold_contrast(4, 32.0))
        self.assertEqual(self.visibility(grating(4, c), 64.0), 0)

    def test_doubling_ppd_moves_the_boundary(self):
        # an 8-pixel grating at 16 pixels per degree (2 cpd) needs more contrast than at 32
        # (4 cpd): in between, invisible at 16, wholly visible at 32 (the contrast comes from
        # the nominal 16 and 32, so a wrong pixels_per_degree moves the outcome)
        low, high = m.pixels_per_degree(30.0, 480), m.pixels_per_degree(30.0, 960)
        c = math.sqrt(predicted_threshold_contrast(8, 16.0) * predicted_threshold_contrast(8, 32.0))
        image = grating(8, c)
        self.assertEqual(self.visibility(image, low), 0)
        self.assertEqual(self.visibility(image, high), image.size)

    def test_contrast_not_luminance(self):
        # the same contrast at mean luminance 5, 50 or 200 is equally visible (Weber)
        predicted = predicted_threshold_contrast(8, 64.0)
        for mean in (5.0, 50.0, 200.0):
            with self.subTest(mean=mean):
                below = grating(8, predicted * 0.99, mean)
                above = grating(8, predicted * 1.01, mean)
                self.assertEqual(self.visibility(below, 64.0), 0)
                self.assertEqual(self.visibility(above, 64.0), above.size)


class TestPerceptualOutline(unittest.TestCase):
    def test_flat_objects_have_no_visible_pixels(self):
        # the outline of a flat object against the background is not detail, at any level
        # and even with a zero threshold (a zero contrast never exceeds it)
        yy, xx = np.indices((256, 256))
        disc = ((yy - 127.3) ** 2 + (xx - 121.6) ** 2) < 99.5 ** 2
        square = (yy >= 13) & (yy < 201) & (xx >= 29) & (xx < 190)
        for name, mask in (('disc', disc), ('square', square)):
            for value in (128.0, 3.0):
                image = np.where(mask, value, 0.0)
                for levels in (1, 4, 6):
                    for threshold in (0.02, 0.0):
                        with self.subTest(name, value=value, levels=levels, threshold=threshold):
                            self.assertEqual(
                                m.perceptual_metric(image, 0.0, 64.0, levels, threshold),
                                (0.0, 0, int(mask.sum())))

    def test_dim_object_counts(self):
        # an object one grey level above the background is made of object pixels
        image = np.zeros((32, 32))
        image[5:20, 7:30] = 1.0
        self.assertEqual(m.perceptual_metric(image, 0.0, 64.0)[2], 15 * 23)

    def test_textured_patch_in_flat_object(self):
        # a flat square (not aligned to the Haar blocks) holding a visible grating patch on
        # [64, 192)^2, aligned to 16: exactly the patch is visible, not the square's outline
        image = np.zeros((256, 256))
        image[13:243, 11:245] = 100.0
        image[64:192, 64:192] = grating(8, 0.2, 100.0, shape=(128, 128))
        pm, vps, tps = m.perceptual_metric(image, 0.0, 64.0)
        self.assertEqual(tps, 230 * 234)
        self.assertEqual(vps, 128 * 128)


if __name__ == '__main__':
    unittest.main()
