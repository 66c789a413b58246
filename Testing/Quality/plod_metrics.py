"""Image metrics for PerceptualLOD's measurements: PSNR, SSIM and Zhu et al.'s perceptual
metric PM = VPs / TPs. numpy only; images are 2-D luminance arrays in [0, 255] (see luminance()).

Choices (documented here because the papers leave them open):
- PSNR: 10 log10(255^2 / MSE) on 8-bit luminance (Rec. 709 weights); identical images give inf.
- SSIM: Wang et al. 2004 with an 11x11 Gaussian window (sigma 1.5), K1 = 0.01, K2 = 0.03,
  L = 255, computed on the 'valid' part of the image (no padding), mean over the windows.
- PM (Zhu et al.): a Haar wavelet decomposition of the luminance over `levels` levels; the
  detail coefficients of level j (j = 1 finest) carry spatial frequency f_j = p / 2^j cycles per
  degree, p being the pixels per degree of the display (from the view angle and image height);
  each level's coefficient magnitudes are weighted by the Mannos-Sakrison contrast sensitivity
  A(f) = 2.6 (0.0192 + 0.114 f) exp(-(0.114 f)^1.1), normalised to its peak; the weighted
  magnitude is divided by the local mean luminance (the level's approximation), which makes it a
  contrast, as the CSF is defined; a pixel is a visible detail pixel (VP) when that weighted
  contrast at any level, brought back to the pixel grid, exceeds `threshold` (default 2%, a
  usual contrast detection threshold). TPs are the object's pixels (different from the
  background). PM = VPs / TPs. Only coefficients whose whole 2^j block lies inside the object
  count: the outline against the background is not detail of the surface, and would otherwise
  mark every pixel of a small object as visible. (A fixed grey-level threshold made every shaded
  pixel visible at the coarse levels: smooth shading gradients are not detail.)
"""
import math

import numpy as np


def luminance(rgb):
    """8-bit RGB (h, w, 3) to luminance (h, w) float."""
    rgb = np.asarray(rgb, dtype=np.float64)
    return 0.2126 * rgb[..., 0] + 0.7152 * rgb[..., 1] + 0.0722 * rgb[..., 2]


def erode(mask, r):
    """Binary erosion by a (2r+1)^2 square (outside the image counts as background)."""
    m = mask.copy()
    for axis in (0, 1):
        out = m.copy()
        for s in range(1, r + 1):
            for sign in (1, -1):
                shifted = np.zeros_like(m)
                if axis == 0:
                    if sign > 0:
                        shifted[s:] = m[:-s]
                    else:
                        shifted[:-s] = m[s:]
                else:
                    if sign > 0:
                        shifted[:, s:] = m[:, :-s]
                    else:
                        shifted[:, :-s] = m[:, s:]
                out &= shifted
        m = out
    return m


def psnr(a, b, peak=255.0):
    a = np.asarray(a, dtype=np.float64)
    b = np.asarray(b, dtype=np.float64)
    mse = np.mean((a - b) ** 2)
    return math.inf if mse == 0 else 10.0 * math.log10(peak * peak / mse)


def _gaussian_window(size=11, sigma=1.5):
    x = np.arange(size) - (size - 1) / 2.0
    g = np.exp(-(x * x) / (2 * sigma * sigma))
    g /= g.sum()
    return g


def _filter_valid(image, g):
    """Separable 'valid' correlation of a 2-D image with the 1-D kernel g on both axes
    (a weighted sum of shifted slices: vectorised, about 10 ms for 640x480)."""
    n = len(g)
    h, w = image.shape
    rows = sum(g[k] * image[:, k:w - n + 1 + k] for k in range(n))
    return sum(g[k] * rows[k:h - n + 1 + k, :] for k in range(n))


def ssim(a, b, peak=255.0, k1=0.01, k2=0.03):
    a = np.asarray(a, dtype=np.float64)
    b = np.asarray(b, dtype=np.float64)
    g = _gaussian_window()
    c1, c2 = (k1 * peak) ** 2, (k2 * peak) ** 2
    mu_a, mu_b = _filter_valid(a, g), _filter_valid(b, g)
    saa = _filter_valid(a * a, g) - mu_a * mu_a
    sbb = _filter_valid(b * b, g) - mu_b * mu_b
    sab = _filter_valid(a * b, g) - mu_a * mu_b
    num = (2 * mu_a * mu_b + c1) * (2 * sab + c2)
    den = (mu_a * mu_a + mu_b * mu_b + c1) * (saa + sbb + c2)
    return float(np.mean(num / den))


def csf(f):
    """Mannos-Sakrison contrast sensitivity at f cycles per degree, peak normalised to 1."""
    def raw(x):
        return 2.6 * (0.0192 + 0.114 * x) * np.exp(-(0.114 * x) ** 1.1)
    peak = raw(np.linspace(0.01, 60, 6000)).max()
    return raw(np.asarray(f, dtype=np.float64)) / peak


def haar_details(image, levels, with_mean=False):
    """Haar decomposition: a list of (level, |LH|+|HL|+|HH| per coefficient) from finest
    (with the level's approximation as a third item when with_mean)."""
    a = np.asarray(image, dtype=np.float64)
    out = []
    for level in range(1, levels + 1):
        h, w = (a.shape[0] // 2) * 2, (a.shape[1] // 2) * 2
        if h < 2 or w < 2:
            break
        a = a[:h, :w]
        p, q = a[0::2, 0::2], a[0::2, 1::2]
        r, s = a[1::2, 0::2], a[1::2, 1::2]
        approx = (p + q + r + s) / 4.0
        lh = (p - q + r - s) / 4.0
        hl = (p + q - r - s) / 4.0
        hh = (p - q - r + s) / 4.0
        detail = np.abs(lh) + np.abs(hl) + np.abs(hh)
        out.append((level, detail, approx) if with_mean else (level, detail))
        a = approx
    return out


def perceptual_metric(image, background, pixels_per_degree, levels=4, threshold=0.02):
    """Zhu et al.'s PM = VPs / TPs of a luminance image. Returns (pm, vps, tps)."""
    image = np.asarray(image, dtype=np.float64)
    obj = np.abs(image - background) > 0.5
    tps = int(obj.sum())
    if tps == 0:
        return 0.0, 0, 0
    visible = np.zeros(image.shape, dtype=bool)
    inside = obj.astype(np.float64)
    for level, detail, mean in haar_details(image, levels, with_mean=True):
        f = pixels_per_degree / 2.0 ** level  # cycles per degree of this level
        weighted = detail * csf(f) / np.maximum(mean, 1.0)
        # blocks wholly inside the object (the mask's Haar approximation equals 1)
        h, w = (inside.shape[0] // 2) * 2, (inside.shape[1] // 2) * 2
        inside = inside[:h, :w]
        inside = (inside[0::2, 0::2] + inside[0::2, 1::2] + inside[1::2, 0::2] + inside[1::2, 1::2]) / 4.0
        full = inside[:weighted.shape[0], :weighted.shape[1]] >= 1.0
        up = np.kron((weighted > threshold) & full, np.ones((2 ** level, 2 ** level), dtype=bool))
        h, w = min(up.shape[0], image.shape[0]), min(up.shape[1], image.shape[1])
        visible[:h, :w] |= up[:h, :w]
    vps = int((visible & obj).sum())
    return vps / tps, vps, tps


def pixels_per_degree(view_angle_degrees, image_height):
    """Pixels per degree of a view whose vertical angle spans image_height pixels: the mean over
    the field of view. (At the centre of a perspective image it is (h / 2) / tan(angle / 2) *
    pi / 180, 2.3% less at 30 degrees; the edges have fewer still.)"""
    return image_height / view_angle_degrees
