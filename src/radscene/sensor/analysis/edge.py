"""MTF measured from an image of a slanted edge (ISO 12233-style e-SFR).

The edge's position is found in every row (the centroid of the row's derivative, refined
with a Hamming window), a straight line is fitted through them, every pixel is projected on
the edge normal, and the projections are binned ``oversampling`` times finer than the pixel
pitch into an edge spread function (ESF). Its derivative (the line spread function, LSF,
Hamming-windowed about its centroid) is Fourier transformed; the modulus, normalised at zero
frequency and divided by the transfer functions of the central difference and of the binning,
is the MTF along the edge normal.

References
----------
ISO 12233:2017, *Photography — Electronic still picture imaging — Resolution and spatial
frequency responses*, Annex D.
P. D. Burns, "Slanted-edge MTF for digital camera and scanner analysis", Proc. IS&T PICS
Conf., 135-138 (2000).
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np

from radscene.errors import ConfigError

__all__ = ["EdgeMTF", "slanted_edge_mtf"]


@dataclass(frozen=True)
class EdgeMTF:
    """Result of :func:`slanted_edge_mtf`.

    Attributes
    ----------
    frequency : numpy.ndarray
        Spatial frequency along the edge normal [cycles pixel-1], 0 to 1.
    mtf : numpy.ndarray
        MTF [-], 1 at zero frequency.
    angle : float
        Angle of the edge from the image columns (vertical edge) or rows [deg].
    orientation : str
        ``"vertical"`` (the edge crosses the rows) or ``"horizontal"``.
    esf_position, esf, lsf : numpy.ndarray
        Bin centres along the normal [pixel], the edge and line spread functions [input unit].
    """

    frequency: np.ndarray
    mtf: np.ndarray
    angle: float
    orientation: str
    esf_position: np.ndarray
    esf: np.ndarray
    lsf: np.ndarray

    def __call__(self, frequency):
        """MTF interpolated at `frequency` [cycles pixel-1]."""
        return np.interp(frequency, self.frequency, self.mtf)


def _row_centroids(image, centre=None, width=None):
    """Centroid of |d/dx| in each row [pixel], optionally Hamming-windowed about `centre`."""
    d = np.abs(np.diff(image, axis=1))  # derivative at the pixel edges x = 1, 2, ...
    x = np.arange(1, image.shape[1], dtype=float)
    if centre is not None:
        u = (x[None, :] - centre[:, None]) / width
        d = d * np.where(np.abs(u) <= 1.0, 0.54 + 0.46 * np.cos(np.pi * u), 0.0)
    total = d.sum(axis=1)
    if np.any(total <= 0):
        raise ConfigError("a row without any edge contrast; crop the image to the edge region",
                          key="image")
    return (d * x).sum(axis=1) / total


def slanted_edge_mtf(image, oversampling: int = 4) -> EdgeMTF:
    """Measure the MTF from an image of a straight edge tilted a few degrees.

    Parameters
    ----------
    image : array_like
        2-D region of interest holding one edge, linear in radiance (any unit). The edge
        should cross every row (or every column), 2° to 20° from the columns (rows), with a
        few pixels of flat field on either side.
    oversampling : int
        ESF bins per pixel (4 as ISO 12233).

    Returns
    -------
    EdgeMTF

    Raises
    ------
    ConfigError
        Not a 2-D image, no contrast in a row, or an edge too close to 0° or 45°.
    """
    a = np.asarray(image, dtype=float)
    if a.ndim != 2 or min(a.shape) < 8:
        raise ConfigError(f"needs a 2-D image of at least 8 x 8 pixels; got shape {a.shape}",
                          key="image")
    if isinstance(oversampling, bool) or not isinstance(oversampling, int) or oversampling < 1:
        raise ConfigError(f"must be an integer >= 1; got {oversampling!r}", key="oversampling")
    gx = np.abs(np.diff(a, axis=1)).sum()
    gy = np.abs(np.diff(a, axis=0)).sum()
    orientation = "vertical" if gx >= gy else "horizontal"
    if orientation == "horizontal":
        a = a.T
    rows = np.arange(a.shape[0], dtype=float) + 0.5
    centre = _row_centroids(a)
    fit = np.polyfit(rows, centre, 1)
    for _ in range(2):  # refine with a window about the fitted line
        centre = _row_centroids(a, np.polyval(fit, rows), width=max(8.0, a.shape[1] / 4))
        fit = np.polyfit(rows, centre, 1)
    slope, intercept = fit
    angle = float(np.degrees(np.arctan(slope)))
    if abs(angle) < 1.0 or abs(angle) > 40.0:
        raise ConfigError(f"the edge is {abs(angle):.2f} deg from the pixel grid; 2 to 20 deg "
                          "gives a well-sampled edge spread function", key="image")
    xs = np.arange(a.shape[1], dtype=float) + 0.5
    dist = (xs[None, :] - (intercept + slope * rows[:, None])) / np.hypot(1.0, slope)
    step = 1.0 / oversampling
    lo = np.floor(dist.min() / step).astype(int)
    idx = (np.floor(dist / step).astype(int) - lo).ravel()
    n = int(idx.max()) + 1
    count = np.bincount(idx, minlength=n)
    total = np.bincount(idx, weights=a.ravel(), minlength=n)
    pos = (np.arange(n) + lo + 0.5) * step
    filled = count > 0
    esf = np.interp(pos, pos[filled], total[filled] / count[filled])
    # only the distances that every row covers
    line = intercept + slope * rows
    first = (0.5 - line.min()) / np.hypot(1.0, slope)
    last = (a.shape[1] - 0.5 - line.max()) / np.hypot(1.0, slope)
    keep = (pos >= first) & (pos <= last)
    if keep.sum() < 4 * oversampling:
        raise ConfigError("too few pixels on either side of the edge; widen the region",
                          key="image")
    pos, esf = pos[keep], esf[keep]
    lsf = np.zeros_like(esf)
    lsf[1:-1] = 0.5 * (esf[2:] - esf[:-2])
    centroid = np.sum(pos * np.abs(lsf)) / np.sum(np.abs(lsf))
    span = max(np.abs(pos - centroid).max(), step)
    lsf = lsf * (0.54 + 0.46 * np.cos(np.pi * np.clip((pos - centroid) / span, -1.0, 1.0)))
    spectrum = np.abs(np.fft.rfft(lsf))
    freq = np.fft.rfftfreq(lsf.size, d=step)
    mtf = spectrum / spectrum[0]
    arg = 2.0 * np.pi * freq * step
    with np.errstate(invalid="ignore", divide="ignore"):
        derivative = np.where(arg > 0, np.sin(arg) / arg, 1.0)
    correction = derivative * np.sinc(freq * step)
    sel = freq <= 1.0 + 1e-12
    return EdgeMTF(frequency=freq[sel], mtf=mtf[sel] / correction[sel], angle=angle,
                   orientation=orientation, esf_position=pos, esf=esf, lsf=lsf)
