"""Polar plots of a BRDF: the reflectance factor over the view hemisphere at a few sun angles.

Each polar panel shows BRF = π f [-] as colour, radius = view zenith θ_o [deg] (to 85°),
angle = view azimuth clockwise from north (up) with the sun at azimuth 0 (north, marked by a
star, which is also where the hot spot lies; the specular direction is at azimuth 180°). The
last panel is the principal plane: BRF against the signed view zenith (positive on the sun's
side, backscatter).
"""

from __future__ import annotations

from pathlib import Path

import numpy as np

from radscene.errors import ConfigError

__all__ = ["plot_brdf"]

#: Largest view zenith drawn [deg]: many models rise steeply at grazing view (RPV, Ross-Li).
MAX_VIEW_ZENITH = 85.0
#: Colour scale of each polar panel up to this percentile of its values (glints and grazing
#: peaks would otherwise wash out the rest); the colour bar marks the clipped top.
COLOUR_PERCENTILE = 99.5


def plot_brdf(model, incidence_angles, path, wavelength=None, *, title: str | None = None,
              resolution: int = 91, dpi: int = 110) -> Path:
    """Polar plots of ``model`` at each incidence angle, saved as a PNG file.

    Parameters
    ----------
    model : BRDF or mapping
        A :class:`~radscene.materials.brdf.BRDF`, or a type-tagged mapping for
        :func:`~radscene.materials.brdf.make_brdf`.
    incidence_angles : float or sequence of float
        Sun zenith angles θ_i in [0, 90) [deg], one panel each (at most 6).
    path : path-like
        Output PNG file.
    wavelength : float, optional
        [um]; needed for models with tabulated parameters.
    title : str, optional
        Figure title; default names the model.
    resolution : int, optional
        View-zenith samples from 0 to 85° (azimuth gets 4× as many) [-].
    dpi : int, optional
        Resolution of the PNG [dots per inch].

    Returns
    -------
    pathlib.Path
        The PNG written.

    Raises
    ------
    ConfigError
        No angle, more than 6, or an angle outside [0, 90).
    """
    from matplotlib.figure import Figure

    from radscene.materials.brdf import make_brdf

    model = make_brdf(model)
    angles = np.atleast_1d(np.asarray(incidence_angles, dtype=float))
    if angles.ndim != 1 or angles.size == 0 or angles.size > 6:
        raise ConfigError(f"give 1 to 6 incidence angles [deg]; got {angles.size}",
                          key="incidence_angles")
    if np.any(~np.isfinite(angles) | (angles < 0.0) | (angles >= 90.0)):
        raise ConfigError(f"incidence angles must lie in [0, 90) deg; got {angles.tolist()}",
                          key="incidence_angles")
    n = angles.size
    zen = np.linspace(0.0, MAX_VIEW_ZENITH, resolution)
    azi = np.linspace(0.0, 360.0, 4 * resolution)
    zz, aa = np.meshgrid(zen, azi, indexing="ij")
    fig = Figure(figsize=(3.2 * (n + 1), 3.6), layout="constrained")
    wl_text = "" if wavelength is None else f" at {float(wavelength):g} µm"
    fig.suptitle(title or f"{type(model).__name__} BRDF{wl_text}: BRF = pi f")
    plane = fig.add_subplot(1, n + 1, n + 1)
    signed = np.linspace(-MAX_VIEW_ZENITH, MAX_VIEW_ZENITH, 2 * resolution - 1)
    for k, theta_i in enumerate(angles):
        brf = np.pi * model.f_angles(theta_i, zz, aa, wavelength)
        ax = fig.add_subplot(1, n + 1, k + 1, projection="polar")
        ax.set_theta_zero_location("N")
        ax.set_theta_direction(-1)
        top = float(np.nanpercentile(brf, COLOUR_PERCENTILE))
        mesh = ax.pcolormesh(np.radians(aa), zz, brf, shading="auto", cmap="viridis",
                             vmin=0.0, vmax=top if top > 0.0 else None)
        ax.plot([0.0], [theta_i], marker="*", color="orange", markersize=11, linestyle="none")
        ax.set_rmax(MAX_VIEW_ZENITH)
        ax.set_rticks([30, 60])
        ax.set_title(f"sun zenith {theta_i:g} deg", fontsize=9)
        fig.colorbar(mesh, ax=ax, shrink=0.7, pad=0.1, extend="max")
        # principal plane: positive view zenith on the sun's side (relative azimuth 0)
        line = np.pi * model.f_angles(theta_i, np.abs(signed),
                                      np.where(signed >= 0.0, 0.0, 180.0), wavelength)
        plane.plot(signed, line, label=f"{theta_i:g} deg")
    plane.set_xlabel("view zenith [deg]")
    plane.set_ylabel("BRF [-]")
    plane.set_title("principal plane (+: sun side)", fontsize=9)
    plane.legend(fontsize=7, title="sun zenith", title_fontsize=7)
    path = Path(path)
    fig.savefig(path, dpi=dpi, format="png")
    return path
