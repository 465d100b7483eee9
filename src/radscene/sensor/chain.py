"""The sensor: a configured chain from the renderer's radiance Dataset to a signal Dataset.

Top-level configuration (``make_sensor`` / YAML)::

    name: mwir_camera
    type: staring                 # registered sensor types: radscene.sensor.SENSOR_TYPES
    oversample: 4                 # rendered samples per detector pitch
    fixed_pattern_seed: 0         # PRNU / DSNU maps (a property of the sensor)
    optics: {...}                 # radscene.sensor.optics
    detector: {type: photon, ...} # radscene.sensor.detector (registry DETECTORS)
    electronics: {...}            # radscene.sensor.electronics
    motion: {jitter: 5 urad, smear: [0.3, 0]}   # rms [angle]; [pitches] per integration
    processing: {dcs: {...}, nuc: {...}, agc: {...}}
    bands:                        # per-band overrides, merged into the above
      lwir: {response: {type: rectangular, wavelength_min: 8, wavelength_max: 12},
             detector: {quantum_efficiency: 0.5}}
      red: {response: {type: library, sensor: landsat8_oli, band: B4}}  # bundled SRF library

Every band is recorded on one detector grid, the base channel's (``oversample`` rendered
samples per base pitch). A band may have its own optics and pitch, hence its own IFOV (a
coarser thermal focal plane): its footprint, optics and smear enter its OTF at their true
size and it is sampled on that grid, as a resampled product is (:meth:`Sensor.grid_pitch`).

The signal Dataset (:meth:`Sensor.apply`) has dims ``frame``, ``band``, ``y``, ``x`` (the
detector grid) and holds:

=====================  ==================  =============  =========================================
variable               dims                unit           meaning
=====================  ==================  =============  =========================================
dn                     frame, band, y, x   DN             output after the enabled processing
dn_raw                 frame, band, y, x   DN             ADC output (uint16 / uint32)
radiance_optics        band, y, x          W m-2 sr-1     radiance ⊗ PSF at the detector centres
flux_scene             band, y, x          W              scene flux on the detector (eq. 7)
flux_<term>            band                W              optics, mounting, heated_dome, heated_air
flux_detector          band, y, x          W              total flux, eq. 7
responsivity           band                A/W or V/W     effective responsivity of the scene term
gain_nonuniformity     band, y, x          1              ΔR of eq. 6 (PRNU)
leakage                band, y, x          A or V         I_leak of eq. 6 (dark current with DSNU)
detector_signal        band, y, x          A or V         eq. 6: detector current (bolometer voltage)
signal_mean            band, y, x          e- or V        expected signal after DCS, before noise
noise_rms              band, y, x          e- or V        analytic temporal noise, quantisation incl.
saturated              frame, band, y, x   bool           full well or ADC clipping
=====================  ==================  =============  =========================================

plus the processing truth (:mod:`radscene.sensor.processing`) and every variable of the
radiance Dataset on the detector grid: block means of the ``k x k`` samples of a detector
(``radiance`` and the terms: the ideal, unblurred detector), the centre sample for integer
label maps (``object_id``, ``material_id``).
"""

from __future__ import annotations

import copy
import datetime as _dt
from collections.abc import Mapping

import numpy as np
import xarray as xr

from radscene.errors import ConfigError, did_you_mean
from radscene.sensor import _parse as P
from radscene.sensor import sampling
from radscene.sensor.channel import (
    RADIAL_TABLE_SIZE,
    Channel,
    Motion,
    as_response,
    default_response,
    fixed_pattern_rng,
)
from radscene.sensor.electronics import Electronics
from radscene.sensor.flux import BACKGROUND_TERMS, SCENE_WEIGHTING
from radscene.sensor.processing import apply_nuc, make_processing, two_point_nuc_coefficients

__all__ = ["Sensor", "DETECTORS"]

_TOP_KEYS = ("name", "type", "description", "oversample", "fixed_pattern_seed", "optics",
             "detector", "electronics", "motion", "processing", "scene_weighting", "bands")
_BAND_KEYS = ("response", "scene_weighting", "optics", "detector", "electronics", "motion",
              "processing")


def _detectors():
    from radscene.sensor.detector import Microbolometer, PhotonDetector

    return {"photon": PhotonDetector, "ccd": PhotonDetector, "cmos": PhotonDetector,
            "cooled_ir": PhotonDetector, "microbolometer": Microbolometer}


#: Registry of detector types (case-insensitive); aliases share a class.
DETECTORS: dict[str, type] = _detectors()


def _merge(base: Mapping, override: Mapping) -> dict:
    """Deep merge; a mapping whose ``type`` differs from the base's replaces it whole."""
    out = copy.deepcopy(dict(base))
    for key, value in override.items():
        retyped = (isinstance(value, Mapping) and isinstance(out.get(key), Mapping)
                   and "type" in value
                   and str(value["type"]).lower() != str(out[key].get("type", "")).lower())
        if isinstance(value, Mapping) and isinstance(out.get(key), Mapping) and not retyped:
            out[key] = _merge(out[key], value)
        else:
            out[key] = copy.deepcopy(value)
    return out


def _build_channel(cfg: Mapping, key: str) -> Channel:
    from radscene.sensor.optics import Optics

    optics = Optics.from_config(cfg.get("optics") or {}, P.join(key, "optics"))
    dcfg = cfg.get("detector")
    dkey = P.join(key, "detector")
    if not isinstance(dcfg, Mapping):
        raise ConfigError(f"a detector mapping with a 'type' ({', '.join(DETECTORS)}) is required",
                          key=dkey)
    kind = str(dcfg.get("type", "photon")).lower()
    if kind not in DETECTORS:
        raise ConfigError(f"unknown detector type {dcfg.get('type')!r}; known: {', '.join(DETECTORS)}"
                          f"{did_you_mean(dcfg.get('type'), DETECTORS)}",
                          key=P.join(dkey, "type"))
    detector = DETECTORS[kind].from_config(dcfg, dkey)
    ecfg = cfg.get("electronics")
    if not isinstance(ecfg, Mapping):
        raise ConfigError("an electronics mapping with at least 'gain' is required",
                          key=P.join(key, "electronics"))
    electronics = Electronics.from_config(ecfg, P.join(key, "electronics"), detector.signal_unit)
    mcfg = cfg.get("motion") or {}
    mkey = P.join(key, "motion")
    P.check_keys(mcfg, ("jitter", "smear"), mkey)
    jitter = P.pair(mcfg, "jitter", "angle", mkey)
    if min(jitter) < 0:
        raise ConfigError(f"rms jitter must be >= 0; got {jitter}", key=P.join(mkey, "jitter"))
    motion = Motion(jitter=jitter, smear=P.pair(mcfg, "smear", "dimensionless", mkey))
    response = None
    if cfg.get("response") is not None:
        response = as_response(cfg["response"], key.split(".")[-1] if key else "band")
    weighting = cfg.get("scene_weighting", "auto")
    if str(weighting).lower() in SCENE_WEIGHTING:
        weighting = str(weighting).lower()
    else:
        try:
            weighting = P.quantity(cfg, "scene_weighting", "temperature", key, low=0.0,
                                   low_open=True)
        except ConfigError as err:
            raise ConfigError(f"{err.message}; or one of {', '.join(SCENE_WEIGHTING)}",
                              key=err.key) from None
    return Channel(optics, detector, electronics, motion,
                   make_processing(cfg.get("processing"), P.join(key, "processing")), response,
                   weighting)


class Sensor:
    """A configured staring sensor (see the module docstring for the configuration).

    Build one with :func:`radscene.sensor.make_sensor` (a dict or YAML mapping) or
    :meth:`from_config`.

    Attributes
    ----------
    name : str
    oversample : int
        Rendered samples per detector pitch.
    base : Channel
        The channel every band uses unless ``bands`` overrides it.
    config : dict
        The configuration the sensor was built from.
    """

    kind = "staring"

    def __init__(self, config: Mapping, key: str = ""):
        P.check_keys(config, _TOP_KEYS, key)
        self.config = copy.deepcopy(dict(config))
        self.key = key
        self.name = str(config.get("name", "sensor"))
        self.oversample = P.integer(config, "oversample", key, 1, low=1)
        self.fixed_pattern_seed = P.integer(config, "fixed_pattern_seed", key, 0, low=0)
        self._base_cfg = {k: v for k, v in config.items() if k in _BAND_KEYS}
        self.base = _build_channel(self._base_cfg, key)
        bands = config.get("bands") or {}
        P.check_keys(bands, list(bands), P.join(key, "bands"))
        self._channels: dict[str, Channel] = {}
        for band, override in bands.items():
            bkey = P.join(key, f"bands.{band}")
            P.check_keys(override or {}, _BAND_KEYS, bkey)
            self._channels[str(band)] = _build_channel(_merge(self._base_cfg, override or {}), bkey)

    @classmethod
    def from_config(cls, config: Mapping, key: str = "") -> Sensor:
        """Build a sensor from a configuration mapping."""
        return cls(config, key)

    def __repr__(self) -> str:
        d = self.base.detector
        return (f"Sensor(name={self.name!r}, detector={d.kind}, pitch={d.pitch * 1e6:g} µm, "
                f"f={self.base.optics.focal_length * 1e3:g} mm, F/{self.base.optics.f_number:g}, "
                f"oversample={self.oversample})")

    def channel(self, band: str) -> Channel:
        """The channel of a band (its overrides merged), the base channel for other bands."""
        return self._channels.get(str(band), self.base)

    # -- geometry --------------------------------------------------------------------------
    def grid_pitch(self, band: str) -> float:
        """Spacing of the sensor's detector grid in a band's focal plane [m].

        Every band is recorded on one grid, the base channel's: ``oversample`` rendered
        samples per base pitch, one output sample per base IFOV. A band whose own IFOV
        (pitch / focal length) differs, e.g. a coarser thermal focal plane, keeps its own
        detector footprint, optics and smear in the OTF but is sampled on that grid, as a
        resampled product is: the grid spacing in its focal plane is
        ``base pitch × band focal length / base focal length``.
        """
        ch, base = self.channel(band), self.base
        if ch is base or (ch.detector.pitch == base.detector.pitch
                          and ch.optics.focal_length == base.optics.focal_length):
            return ch.detector.pitch
        return base.detector.pitch * ch.optics.focal_length / base.optics.focal_length

    @property
    def ifov(self) -> float:
        """Instantaneous field of view of one detector pitch, 2 atan(p / 2f) [deg]."""
        return float(np.degrees(2.0 * np.arctan(0.5 * self.base.detector.pitch
                                                / self.base.optics.focal_length)))

    def ground_sample_distance(self, distance) -> np.ndarray:
        """Detector pitch projected at `distance` [m] on a surface normal to the view [m]."""
        return np.asarray(distance, dtype=float) * self.base.detector.pitch / self.base.optics.focal_length

    def observer_geometry(self, shape=None) -> dict:
        """Render settings that put ``oversample`` samples on every detector pitch.

        Parameters
        ----------
        shape : tuple of int, optional
            Detector array (rows, columns); default ``detector.shape``.

        Returns
        -------
        dict
            ``shape`` [samples] of the radiance image and ``fov`` [deg], the horizontal full
            field of view of a perspective observer; ``gsd_per_distance`` [m m-1], the
            sample spacing per metre of distance for an orthographic one.
        """
        det, f = self.base.detector, self.base.optics.focal_length
        shape = shape or det.shape
        if shape is None:
            raise ConfigError("give the array shape (rows, columns) or set detector.shape",
                              key="detector.shape")
        k = self.oversample
        ny, nx = shape
        return {"shape": (ny * k, nx * k),
                "fov": float(np.degrees(2.0 * np.arctan(0.5 * nx * det.pitch / f))),
                "gsd_per_distance": det.pitch / f / k}

    # -- the chain -------------------------------------------------------------------------
    def apply(self, radiance, *, frames: int = 1, seed=None, oversample: int | None = None,
              responses: Mapping | None = None, workers: int | None = None) -> xr.Dataset:
        """Turn an oversampled radiance Dataset into the signal Dataset.

        Parameters
        ----------
        radiance : xarray.Dataset or xarray.DataArray
            The renderer's output (``radiance(band, y, x)`` [W m-2 sr-1]) or that variable.
        frames : int
            Frames to record (independent temporal noise, 1/f correlated along the stream).
        seed : int or numpy.random.Generator, optional
            Temporal noise seed.
        oversample : int, optional
            Rendered samples per detector pitch; default the sensor's ``oversample``.
        responses : mapping, optional
            ``{band: SpectralResponse or response dict}``; else ``bands.<b>.response``, else a
            rectangular band of the Dataset's ``wavelength_center`` and ``equivalent_width``.
        workers : int, optional
            FFT threads (default all cores).

        Returns
        -------
        xarray.Dataset
            See the module docstring.
        """
        ds = radiance.to_dataset(name="radiance") if isinstance(radiance, xr.DataArray) else radiance
        if not isinstance(ds, xr.Dataset) or "radiance" not in ds:
            raise ConfigError("expected the renderer's Dataset with a 'radiance' variable",
                              key="radiance")
        rad = ds["radiance"]
        if rad.dims != ("band", "y", "x"):
            raise ConfigError(f"must have dims (band, y, x); got {rad.dims}", key="radiance")
        if isinstance(frames, bool) or not isinstance(frames, int | np.integer) or frames < 1:
            raise ConfigError(f"must be an integer >= 1; got {frames!r}", key="frames")
        k = self.oversample if oversample is None else oversample
        shape = sampling.detector_grid_shape(rad.shape, k)
        rng = seed if isinstance(seed, np.random.Generator) else np.random.default_rng(seed)
        responses = dict(responses or {})
        bands = [str(b) for b in rad["band"].values]
        per_band = []
        grids: dict = {}
        for band in bands:
            ch = self.channel(band)
            if ch.detector.shape is not None and tuple(ch.detector.shape) != shape:
                raise ConfigError(
                    f"the radiance image ({rad.shape[1]} x {rad.shape[2]} samples at {k} per "
                    f"pitch) makes a {shape[0]} x {shape[1]} array; the detector is "
                    f"{ch.detector.shape[0]} x {ch.detector.shape[1]}",
                    key=f"bands.{band}.detector.shape" if band in self._channels else "detector.shape")
            if band in responses:
                response = as_response(responses[band], band)
            else:
                response = ch.response or default_response(ds, band)
            radiometry = ch.radiometry(response, key=f"bands.{band}.response")
            grid_pitch = self.grid_pitch(band)
            otf = _half_grid_otf(ch, radiometry, rad.shape[1:], k, grids, grid_pitch)
            fine = rad.sel(band=band).values
            if not np.isfinite(fine).all():
                raise ConfigError(f"band {band!r} holds NaN or infinite radiance; the optics "
                                  "would spread it over the whole image", key="radiance")
            radiance_optics = sampling.apply_otf(fine, otf, k, workers)
            per_band.append(_run_band(ch, radiometry, radiance_optics, frames, rng,
                                      fixed_pattern_rng(self.fixed_pattern_seed, band),
                                      grid_pitch))
        return _signal_dataset(self, ds, bands, per_band, k, frames, seed)


def _half_grid_otf(ch: Channel, radiometry, shape, k, cache, grid_pitch=None) -> np.ndarray:
    """System OTF on the rfft half grid of the fine image (float32); the rows fy >= 0 only
    unless a diagonal smear makes it uneven in fy. ``grid_pitch`` [m] is the spacing of the
    detector grid in the channel's focal plane (:meth:`Sensor.grid_pitch`; default the
    channel's pitch).

    The geometric part (footprint × jitter × smear) is evaluated once per set of parameters,
    separably where it can be; the radial aberration part is a table on a uniform grid of
    radial frequency, read by linear interpolation with indices shared by all bands.
    """
    det, opt = ch.detector, ch.optics
    spacing = (det.pitch if grid_pitch is None else grid_pitch) / k  # focal-plane sample spacing [m]
    sx, sy = (np.radians(j) * opt.focal_length for j in ch.motion.jitter)
    dx, dy = (s * det.pitch for s in ch.motion.smear)
    fy, fx = sampling.rfft_frequencies(shape)
    if not (dx and dy):  # the OTF is even in fy alone: the rows fy >= 0 suffice
        fy = np.abs(fy[: shape[0] // 2 + 1])
    fy, fx = fy / spacing, fx / spacing  # [cycles m-1]
    gkey = ("radial", shape, spacing, fy.shape)
    if gkey not in cache:
        rho = np.hypot(fy.astype(np.float32), fx.astype(np.float32))
        top = float(rho.max()) * (1 + 1e-6)
        pos = rho * np.float32((RADIAL_TABLE_SIZE - 1) / top)
        index = pos.astype(np.int32)
        pos -= index
        cache[gkey] = (np.linspace(0.0, top, RADIAL_TABLE_SIZE), index, pos)
    table_f, index, frac = cache[gkey]
    ckey = ("geometric", shape, spacing, det.active_width, sx, sy, dx, dy)
    if ckey not in cache:
        hx = np.sinc(det.active_width * fx) * np.exp(-2.0 * np.pi**2 * (sx * fx) ** 2)
        hy = np.sinc(det.active_width * fy) * np.exp(-2.0 * np.pi**2 * (sy * fy) ** 2)
        geo = hy.astype(np.float32) * hx.astype(np.float32)
        if dx or dy:
            arg = (dy * fy).astype(np.float32) + (dx * fx).astype(np.float32)
            arg *= np.float32(np.pi)
            with np.errstate(invalid="ignore", divide="ignore"):
                smear = np.where(arg == 0, np.float32(1.0), np.sin(arg) / arg)
            geo *= smear
        cache[ckey] = geo
    table = opt.polychromatic_otf(table_f, radiometry.nodes, radiometry.otf_weights)
    table = np.append(table, table[-1]).astype(np.float32)
    step = np.diff(table)
    otf = table[index]
    otf += frac * step[index]
    otf *= cache[ckey]
    return otf


def _run_band(ch: Channel, radiometry, radiance_optics, frames, rng, fp_rng,
              grid_pitch=None) -> dict:
    det, elec = ch.detector, ch.electronics
    shape = radiance_optics.shape
    illumination = ch.relative_illumination_map(shape, grid_pitch)
    gain_map = det.gain_map(shape, fp_rng)
    offset_map = det.offset_map(shape, fp_rng)
    leakage = det.leakage(radiometry.band_integral)
    rate = ch.mean_rate(radiometry, radiance_optics, illumination, gain_map, offset_map, leakage)
    flux_scene = radiance_optics * np.float32(radiometry.scene_flux_factor)
    flux_scene *= illumination
    out = {
        "radiance_optics": radiance_optics,
        "flux_scene": flux_scene,
        "responsivity": radiometry.responsivity,
        "gain_nonuniformity": gain_map,
        "leakage": offset_map + np.float32(leakage),
        "detector_signal": rate,
        **{f"flux_{t}": radiometry.background_flux[t] for t in BACKGROUND_TERMS},
    }
    out["flux_detector"] = flux_scene + np.float32(sum(radiometry.background_flux.values()))
    skim = np.float32(0.0)
    pedestal = 0.0
    stages = ch.processing
    if "dcs" in stages:
        dcs = stages["dcs"]
        shutter = ((radiometry.shutter_rate(dcs.shutter_temperature)
                    + radiometry.background_rate["mounting"]) * gain_map + leakage + offset_map)
        signal, _ = ch.expose(shutter, 0.0, 0.0, 1, rng, average=dcs.frames)
        pedestal_dn = dcs.pedestal if dcs.pedestal is not None else 0.25 * elec.max_dn
        pedestal = pedestal_dn * elec.gain
        skim = signal[0]
        out["dcs_background"] = skim - np.float32(pedestal)
    mean_signal = det.to_signal(rate)
    out["signal_mean"] = mean_signal - skim + np.float32(pedestal)
    out["noise_rms"] = np.sqrt(ch.temporal_variance(mean_signal, frames, shape)).astype(np.float32)
    signal, well_full = ch.expose(rate, skim, pedestal, frames, rng)
    dn_raw, adc_clip = elec.digitize(signal)
    out["dn_raw"] = dn_raw
    out["saturated"] = well_full | adc_clip
    dn = dn_raw.astype(np.float32)
    if "nuc" in stages:
        nuc = stages["nuc"]
        levels = []
        for kind, value in (nuc.low, nuc.high):
            level = value if kind == "radiance" else radiometry.blackbody_radiance(value)
            ref_rate = ch.mean_rate(radiometry, np.full(shape, level, dtype=np.float32),
                                    illumination, gain_map, offset_map, leakage)
            ref_signal, _ = ch.expose(ref_rate, skim, pedestal, 1, rng, average=nuc.frames)
            levels.append(np.clip(ref_signal[0] / elec.gain + elec.offset, 0.0, elec.max_dn))
        gain, offset, bad = two_point_nuc_coefficients(*levels)
        dn = apply_nuc(dn, gain, offset)
        out.update(nuc_gain=gain.astype(np.float32), nuc_offset=offset.astype(np.float32),
                   nuc_bad_pixel=bad)
    if "agc" in stages:
        dn, agc_gain, agc_offset = stages["agc"](dn)
        out.update(agc_gain=agc_gain, agc_offset=agc_offset)
    out["dn"] = dn
    return out


_ATTRS = {
    "dn": ("DN", "digital numbers after the enabled processing stages"),
    "dn_raw": ("DN", "analogue-to-digital converter output"),
    "radiance_optics": ("W m-2 sr-1", "band radiance filtered by the system OTF at the detector centres"),
    "flux_scene": ("W", "scene flux on the detector (Willers et al. 2011 eq. 7)"),
    "flux_optics": ("W", "self-emission of the optics and the obscuration on the detector"),
    "flux_mounting": ("W", "emission of the optics mounting on the detector"),
    "flux_heated_dome": ("W", "emission of the heated dome on the detector"),
    "flux_heated_air": ("W", "emission of the heated air in front of the dome on the detector"),
    "flux_detector": ("W", "total flux on the detector (eq. 7)"),
    "gain_nonuniformity": ("1", "per-detector responsivity factor Delta R (PRNU), eq. 6"),
    "saturated": ("1", "the full well or the ADC clipped the sample"),
    "nuc_gain": ("1", "two-point NUC gain"),
    "nuc_offset": ("DN", "two-point NUC offset"),
    "nuc_bad_pixel": ("1", "NUC references did not differ: pixel replaced by the mean level"),
    "agc_gain": ("1", "AGC output DN per input DN"),
    "agc_offset": ("DN", "AGC input level mapped to 0"),
}


def _signal_dataset(sensor, ds, bands, per_band, k, frames, seed) -> xr.Dataset:
    base = sensor.base
    det = base.detector
    unit_sig, unit_rate = det.signal_unit, det.rate_unit
    units = {"responsivity": f"{unit_rate} W-1", "leakage": unit_rate, "detector_signal": unit_rate,
             "signal_mean": unit_sig, "noise_rms": unit_sig, "dcs_background": unit_sig}
    long = {"responsivity": "effective responsivity of the scene term",
            "leakage": "leakage I_leak of eq. 6 (dark current with DSNU, or bolometer offset)",
            "detector_signal": "detector current of eq. 6 (bolometer: output voltage)",
            "signal_mean": "expected signal after DCS, before noise",
            "noise_rms": "analytic temporal noise, quantisation included",
            "dcs_background": "signal subtracted by DCS, net of the pedestal"}
    names = [n for n in per_band[0] if all(n in pb for pb in per_band)]
    data = {}
    for name in names:
        stacked = np.stack([np.asarray(pb[name]) for pb in per_band], axis=0)
        if stacked.ndim == 4:  # band, frame, y, x -> frame, band, y, x
            stacked = np.moveaxis(stacked, 0, 1)
            dims = ("frame", "band", "y", "x")
        elif stacked.ndim == 3:
            dims = ("band", "y", "x")
        elif stacked.ndim == 2:  # band, frame
            stacked, dims = stacked.T, ("frame", "band")
        else:
            dims = ("band",)
        unit, meaning = _ATTRS.get(name, (units.get(name, "1"), long.get(name, name)))
        attrs = {"units": units.get(name, unit), "long_name": long.get(name, meaning)}
        if stacked.dtype == np.float64 and stacked.ndim >= 3:
            stacked = stacked.astype(np.float32)
        data[name] = (dims, stacked, attrs)
    truth = _carry_truth(ds, k)
    coords = {"frame": ("frame", np.arange(frames)), "band": ("band", bands),
              "signal_unit": ("band", [sensor.channel(b).detector.signal_unit for b in bands],
                              {"long_name": "unit of the detector signal of each band"})}
    for name in ("wavelength_center", "wavelength_min", "wavelength_max", "equivalent_width"):
        if name in ds.coords:
            coords[name] = ("band", ds[name].values, dict(ds[name].attrs))
    coords.update(_grid_coords(ds, k, per_band[0]["dn"].shape[-2:]))
    out = xr.Dataset({**truth, **data}, coords=coords)
    out = out.set_coords([n for n in _GEOLOCATION if n in out.data_vars])
    opt = base.optics
    out.attrs = {
        "Conventions": "CF-1.10",
        "title": f"radscene sensor {sensor.name!r} applied to {ds.attrs.get('title', 'a radiance image')}",
        "history": (ds.attrs.get("history", "") + "\n" if ds.attrs.get("history") else "")
        + f"{_dt.datetime.now(_dt.UTC).isoformat(timespec='seconds')} sensor {sensor.name!r} applied",
        "sensor": sensor.name,
        "sensor_type": sensor.kind,
        "detector_type": det.kind,
        "signal_unit": unit_sig,
        "oversample": k,
        "frames": frames,
        "seed": "none" if seed is None or isinstance(seed, np.random.Generator) else str(seed),
        "fixed_pattern_seed": sensor.fixed_pattern_seed,
        "ifov_deg": sensor.ifov,
        "focal_length_m": opt.focal_length,
        "f_number": opt.f_number,
        "pitch_m": det.pitch,
        "integration_time_s": det.integration_time,
        "processing": " ".join(base.processing) or "none",
        **{f"render_{a}": v for a, v in ds.attrs.items()
           if a in ("scene", "observer", "observer_type", "time", "sun_zenith_deg",
                    "sun_azimuth_deg", "atmosphere")},
    }
    return out


#: The render's auxiliary coordinates carried to the detector grid (as coordinates there too).
_GEOLOCATION = ("latitude", "longitude", "height")


def _carry_truth(ds: xr.Dataset, k: int) -> dict:
    out = {}
    carried = [*ds.data_vars.items(), *((n, ds.coords[n]) for n in _GEOLOCATION if n in ds.coords)]
    for name, var in carried:
        if var.dims[-2:] != ("y", "x"):
            out[name] = var.variable.copy()
            continue
        values = var.values
        if values.dtype.kind in "iub":
            reduced = sampling.block_centre(values, k)
        else:
            reduced = sampling.block_mean(values, k).astype(values.dtype, copy=False)
        out[name] = (var.dims, reduced, dict(var.attrs))
    return out


def _grid_coords(ds, k, shape) -> dict:
    my, mx = shape
    coords = {}
    for axis, n in (("y", my), ("x", mx)):
        c = ds.coords.get(axis)
        if c is not None and c.attrs.get("units") == "m":
            coords[axis] = (axis, np.asarray(c.values, float).reshape(n, k).mean(axis=1),
                            dict(c.attrs))
        else:
            coords[axis] = (axis, np.arange(n), {"long_name": f"detector {'row' if axis == 'y' else 'column'}"})
    return coords
