"""``radscene materials``: list, show and plot the built-in materials; browse spectral libraries.

Commands
--------
``list [--category C] [--search TEXT]``
    The built-in materials with their category, reflectance at 0.55 um and emissivity at 10 um.
``show NAME [--wavelength W ...]``
    Everything about one material: description, sources, spectra at a few wavelengths, thermal
    properties (layers, solar absorptance, long-wave emissivity).
``plot NAME [-o DIR] [--incidence 0 --incidence 30 ...] [--wavelength W]``
    ``DIR/NAME_spectrum.png`` (ρ, ρ_s, τ, ε over 0.4-20 um) and ``DIR/NAME_brdf.png`` (polar
    plots of the material's BRDF, Lambert + Phong lobe, at the incidence angles).
``earthlib [--cls C] [--name PATTERN] [--limit N]``
    Search earthlib's 7261 spectra (optional dependency).
``read PATH [--format F]``
    List the spectra of a library file or folder (ECOSTRESS/ASTER, USGS splib07, ENVI .sli).

Bad input raises :class:`~radscene.errors.ConfigError`; ``radscene``'s CLI prints it on one line
and exits with status 2. Registered by :mod:`radscene.cli` as ``radscene materials``
(``add_subcommands(app, "materials", ...)``).
"""

from __future__ import annotations

from pathlib import Path
from typing import Annotated

import numpy as np
import typer
from rich.console import Console
from rich.table import Table

from radscene.errors import ConfigError

__all__ = ["app"]

app = typer.Typer(
    name="materials",
    help="Built-in materials and spectral libraries.",
    no_args_is_help=True,
    add_completion=False,
    pretty_exceptions_enable=False,
)
console = Console(width=120)

#: Wavelengths shown by ``show`` unless others are given [um].
SHOW_WAVELENGTHS = (0.45, 0.55, 0.65, 0.85, 1.65, 2.2, 3.8, 4.5, 8.5, 10.0, 12.0)


@app.command("list")
def list_command(
    category: Annotated[str | None, typer.Option("--category", help="Only this category.")] = None,
    search: Annotated[
        str | None, typer.Option("--search", help="Only names or descriptions containing this.")
    ] = None,
):
    """List the built-in materials."""
    from radscene.materials.library import get_material, library_info, list_materials

    info = library_info()["materials"]
    table = Table(title="radscene built-in materials (0.4-20 µm)")
    for col in ("name", "category", "rho(0.55 µm)", "eps(10 µm)", "description"):
        table.add_column(col)
    shown = 0
    for name in list_materials(category):
        entry = info[name]
        if search and search.lower() not in (name + " " + entry.get("description", "")).lower():
            continue
        m = get_material(name)
        table.add_row(name, entry.get("category", ""), f"{float(m.reflectance(0.55)):.3f}",
                      f"{float(m.emissivity(10.0)):.3f}", entry.get("description", "").strip())
        shown += 1
    console.print(table)
    console.print(f"{shown} material(s)")


def _wavelengths(values, key="wavelength"):
    wl = np.asarray(values if values else SHOW_WAVELENGTHS, dtype=float)
    if np.any(~np.isfinite(wl)) or np.any(wl <= 0):
        raise ConfigError("wavelengths must be finite and > 0 [µm]", key=key)
    return wl


@app.command()
def show(
    name: Annotated[str, typer.Argument(help="Material name (see `radscene materials list`).")],
    wavelength: Annotated[
        list[float] | None,
        typer.Option("--wavelength", "-w", help="Wavelength [µm]; repeatable."),
    ] = None,
):
    """Show a material: sources, spectra and thermal properties."""
    from radscene.materials.library import get_material, library_info
    from radscene.materials.thermal import get_thermal_properties

    m = get_material(name)
    entry = library_info()["materials"][m.name]
    console.print(f"[bold]{m.name}[/] ({m.category}) - {m.description.strip()}")
    lo, hi = m.wavelength_range
    console.print(f"range: {lo:g}-{hi:g} µm (no extrapolation); file: {entry['file']}; "
                  f"specular exponent: {m.specular_exponent:g}")
    console.print(f"source: {m.source}", soft_wrap=False)
    wl = _wavelengths(wavelength)
    comps = m.components(wl)
    table = Table(title="spectra [-]")
    table.add_column("wavelength [µm]")
    for label in ("diffuse_reflectance", "specular_reflectance", "transmittance", "emissivity"):
        table.add_column(label)
    for i, w in enumerate(wl):
        table.add_row(f"{w:g}", *(f"{comps[k][i]:.4f}" for k in
                                  ("diffuse_reflectance", "specular_reflectance", "transmittance", "emissivity")))
    console.print(table)
    tp = get_thermal_properties(m.name)
    console.print(f"solar absorptance (ASTM G173 global, 0.4-4 µm): {tp.solar_absorptance:.3f}; "
                  f"long-wave emissivity (300 K, 3-20 µm): {tp.longwave_emissivity:.3f}")
    layers = Table(title=f"thermal layers (top first; below: {tp.bottom})")
    for col in ("layer", "thickness [m]", "k [W m-1 K-1]", "rho [kg m-3]", "c [J kg-1 K-1]", "source"):
        layers.add_column(col)
    for layer in tp.layers:
        layers.add_row(layer.name, "semi-infinite" if layer.thickness is None else f"{layer.thickness:g}",
                       f"{layer.conductivity:g}", f"{layer.density:g}", f"{layer.specific_heat:g}",
                       layer.source)
    console.print(layers)
    if tp.canopy:
        console.print(f"canopy: LAI {tp.canopy['lai']:g}, leaf heat capacity "
                      f"{tp.canopy['areal_heat_capacity']:g} J m-2 K-1 ({tp.canopy['source']})")
    if tp.moisture_availability:
        console.print(f"moisture availability (evaporation, beta): {tp.moisture_availability:g}")
    if tp.notes:
        console.print(f"notes: {tp.notes}")


@app.command()
def plot(
    name: Annotated[str, typer.Argument(help="Material name.")],
    output: Annotated[Path, typer.Option("-o", "--output", help="Output folder.")] = Path("."),
    incidence: Annotated[
        list[float] | None,
        typer.Option("--incidence", "-i",
                     help="Sun zenith [deg] of a BRDF panel; repeatable (default 0, 30, 60)."),
    ] = None,
    wavelength: Annotated[
        float, typer.Option("--wavelength", "-w", help="Wavelength of the BRDF plot [µm].")
    ] = 0.55,
):
    """Write NAME_spectrum.png and NAME_brdf.png into OUTPUT."""
    from radscene.materials.library import get_material
    from radscene.materials.plot import plot_material_brdf, plot_material_spectrum

    m = get_material(name)
    angles = list(incidence) if incidence else [0.0, 30.0, 60.0]
    if not 1 <= len(angles) <= 6 or any(not (0.0 <= a < 90.0) for a in angles):
        raise ConfigError(
            f"give 1 to 6 incidence angles; incidence angles must lie in [0, 90) deg; got {angles}",
            key="incidence",
        )
    if not output.exists():
        output.mkdir(parents=True)
    elif not output.is_dir():
        raise ConfigError(f"{output} exists and is not a folder", key="output")
    spectrum = plot_material_spectrum(m, output / f"{m.name}_spectrum.png")
    brdf_png = plot_material_brdf(m, angles, output / f"{m.name}_brdf.png", wavelength=wavelength)
    console.print(f"wrote {spectrum}")
    console.print(f"wrote {brdf_png}")


@app.command("earthlib")
def earthlib_command(
    cls: Annotated[
        str | None, typer.Option("--cls", help="Class at any level (e.g. soil, road, bark).")
    ] = None,
    name: Annotated[str | None, typer.Option("--name", help="Name pattern (glob or substring).")] = None,
    limit: Annotated[int, typer.Option("--limit", help="Show at most this many.")] = 20,
):
    """Search earthlib's 7261 VSWIR spectra by class and name."""
    from radscene.materials.libraries import earthlib_library

    fields = {"cls": cls} if cls else {}
    hits = earthlib_library().search(name=name, **fields)
    table = Table(title=f"earthlib: {len(hits)} spectra match")
    for col in ("index", "name", "class", "source"):
        table.add_column(col)
    for s in list(hits)[: max(limit, 0)]:
        md = s.metadata
        table.add_row(md["index"], s.name, "/".join(md.get(f"level_{k}", "") for k in range(1, 5)),
                      f"{md.get('source', '')} / {md.get('notes', '')}")
    console.print(table)


@app.command("read")
def read_command(
    path: Annotated[Path, typer.Argument(help="Library file or folder.")],
    format: Annotated[
        str | None,
        typer.Option("--format", help="ecostress, aster, usgs or envi (default: detect)."),
    ] = None,
):
    """List the spectra of a spectral-library file or folder."""
    from radscene.materials.libraries import read_library

    lib = read_library(path, format=format)
    table = Table(title=f"{path}: {len(lib)} spectra")
    for col in ("name", "quantity", "range [µm]", "samples", "source"):
        table.add_column(col)
    for s in lib:
        lo, hi = s.range
        table.add_row(s.name, s.quantity, f"{lo:g}-{hi:g}", str(s.wavelength.size), s.source)
    console.print(table)
