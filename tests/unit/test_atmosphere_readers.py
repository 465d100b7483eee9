"""Readers of MODTRAN tape7 and libRadtran uvspec output.

The MODTRAN files are synthetic (radscene has no MODTRAN) but laid out as MODTRAN 4/5 write
them: card images, column header(s), one sample a line, ``-9999.``. Their numbers are
chosen so that the unit conversions have exact answers: a radiance L_ν [W cm-2 sr-1 (cm-1)-1]
at ν [cm-1] is L_λ = L_ν ν² [W m-2 sr-1 um-1] (1e4 for cm-2 → m-2, ν²/1e4 for per cm-1 →
per um). The libRadtran output is typed in from case libradtran_rossli_* (libRadtran
examples/UVSPEC_BRDF_ROSSLI.OUT, ashiklom/libradtran@208f5465; empty atmosphere, 400 nm,
sza 30, output_quantity transmittance).
"""

from __future__ import annotations

import numpy as np
import pytest

from radscene.atmosphere.readers import parse_uvspec_input, read_modtran_tape7, read_uvspec
from radscene.errors import ConfigError

REL = 1e-12  # the conversions are exact up to rounding

TAPE7_RADIANCE = """\
TMF 2    2    2    1    0    0    0    0    0    0    1    1    0   0.000   0.10
TFF  8   0   365.000                    0    F F F         F      0.000         0      0.000
    1    0    0    0    0    0    23.000     0.000     0.000     0.000     0.000
     3.000     0.000   180.000     0.000     0.000     0.000    0          0.000
    1    0  180    0
    45.000    30.000     0.000     0.000    12.000     0.000     0.000     0.000
    1000.0    1010.0       5.0       5.0
  FREQ TOT_TRANS PTH_THRML THRML_SCT SURF_EMIS  SOL_SCAT SING_SCAT GRND_RFLT DRCT_RFLT TOTAL_RAD  REF_SOL  SOL@OBS   DEPTH DIR_EM    TOA_SUN BBODY_T[K]
 1000.  0.8000 5.000E-06 1.000E-07 4.000E-06 2.000E-09 1.500E-09 3.000E-08 2.000E-08 9.130E-06 1.00E-01 2.00E-01  0.223  0.800 1.000E-08   280.00
 1005.  0.8100 4.900E-06 1.000E-07 4.100E-06 2.000E-09 1.500E-09 3.000E-08 2.000E-08 9.130E-06 1.00E-01 2.00E-01  0.211  0.810 1.000E-08   280.00
 1010.  0.8200 4.800E-06 1.000E-07 4.200E-06 2.000E-09 1.500E-09 3.000E-08 2.000E-08 9.130E-06 1.00E-01 2.00E-01  0.198  0.820 1.000E-08   280.00
 -9999.
"""

# MODTRAN 4 writes the two-word names with a space
TAPE7_MODTRAN4 = TAPE7_RADIANCE.replace(
    "  FREQ TOT_TRANS PTH_THRML THRML_SCT SURF_EMIS  SOL_SCAT SING_SCAT GRND_RFLT DRCT_RFLT "
    "TOTAL_RAD  REF_SOL  SOL@OBS",
    "  FREQ TOT TRANS PTH THRML THRML SCT SURF EMIS  SOL SCAT SING SCAT GRND RFLT DRCT RFLT "
    "TOTAL RAD  REF SOL  SOL@OBS")

# IEMSCT 1: the solar columns keep their headers but carry no numbers
TAPE7_THERMAL = """\
TMF 2    2    1    0    0    0    0    0    0    0    1    1    0 300.000   0.00
  FREQ TOT_TRANS PTH_THRML THRML_SCT SURF_EMIS  SOL_SCAT SING_SCAT GRND_RFLT DRCT_RFLT TOTAL_RAD  REF_SOL  SOL@OBS   DEPTH DIR_EM    TOA_SUN BBODY_T[K]
 1000.  0.8000 5.000E-06 1.000E-07 4.000E-06                     3.000E-08           9.130E-06                     0.223  0.800             280.00
 1005.  0.8100 4.900E-06 1.000E-07 4.100E-06                     3.000E-08           9.130E-06                     0.211  0.810             280.00
 -9999.
"""

TAPE7_TRANSMITTANCE = """\
TMF 2    2    0    0    0    0    0    0    0    0    1    1    0   0.000   0.00
  FREQ  COMBIN    H2O   UMIX     O3  TRACE     N2    H2O  MOLEC AER+CLD  HNO3 AER+CLD  -LOG    CO2     CO
  1/CM   TRANS  TRANS  TRANS  TRANS  TRANS   CONT   CONT   SCAT  TRANS  TRANS abTRNS COMBIN  TRANS  TRANS
18000.  0.6000 0.9900 0.9990 0.9600 1.0000 1.0000 1.0000 0.8800 0.7200 1.0000 0.0050 0.5108 1.0000 1.0000
18005.  0.6010 0.9910 0.9990 0.9600 1.0000 1.0000 1.0000 0.8801 0.7210 1.0000 0.0050 0.5092 1.0000 1.0000
 -9999.
"""

TAPE7_IRRADIANCE = """\
TMF 2    3    3    0    0    0    0    0    0    0    1    1    0   0.000   0.00
  FREQ   TRANS  SOL TR    SOLAR   DEPTH
 18000.  0.7000 4.000E-06 5.714E-06  0.357
 18005.  0.7010 4.006E-06 5.715E-06  0.355
 -9999.
"""


@pytest.fixture
def write(tmp_path):
    def _write(name, text):
        path = tmp_path / name
        path.write_text(text)
        return path
    return _write


def test_tape7_radiance_mode(write):
    ds = read_modtran_tape7(write("rad.tp7", TAPE7_RADIANCE))
    nu = np.array([1010.0, 1005.0, 1000.0])  # increasing wavelength
    assert ds.wavelength.values == pytest.approx(1e4 / nu, rel=REL)
    assert ds.wavenumber.values == pytest.approx(nu, rel=REL)
    assert ds.transmittance.values == pytest.approx([0.82, 0.81, 0.80], rel=REL)
    emitted = np.array([4.8e-6, 4.9e-6, 5.0e-6]) + 1e-7
    assert ds.path_thermal_radiance.values == pytest.approx(emitted * nu**2, rel=REL)
    assert ds.path_scattered_radiance.values == pytest.approx(2e-9 * nu**2, rel=REL)
    assert ds.path_radiance.values == pytest.approx((emitted + 2e-9) * nu**2, rel=REL)
    assert ds.total_radiance.values == pytest.approx(9.13e-6 * nu**2, rel=REL)
    assert ds.toa_irradiance.values == pytest.approx(1e-8 * nu**2, rel=REL)
    assert ds.path_radiance.attrs["units"] == "W m-2 sr-1 um-1"
    assert ds.attrs["iemsct"] == 2
    # 5e-6 W cm-2 sr-1 (cm-1)-1 at 10 um is 5 W m-2 sr-1 um-1
    assert float(ds.path_emitted_radiance.sel(wavelength=10.0)) == pytest.approx(5.0, rel=REL)


def test_tape7_modtran4_names_read_the_same(write):
    a = read_modtran_tape7(write("a.tp7", TAPE7_RADIANCE))
    b = read_modtran_tape7(write("b.tp7", TAPE7_MODTRAN4))
    for name in ("transmittance", "path_thermal_radiance", "path_scattered_radiance",
                 "ground_reflected_radiance", "total_radiance"):
        np.testing.assert_array_equal(a[name].values, b[name].values)


def test_tape7_thermal_mode_skips_the_empty_solar_columns(write):
    ds = read_modtran_tape7(write("th.tp7", TAPE7_THERMAL))
    nu = np.array([1005.0, 1000.0])
    assert ds.attrs["iemsct"] == 1
    assert ds.ground_reflected_radiance.values == pytest.approx(3e-8 * nu**2, rel=REL)
    assert ds.total_radiance.values == pytest.approx(9.13e-6 * nu**2, rel=REL)
    assert np.all(ds.path_scattered_radiance.values == 0.0)
    assert "toa_irradiance" not in ds


def test_tape7_transmittance_mode(write):
    ds = read_modtran_tape7(write("tr.tp7", TAPE7_TRANSMITTANCE))
    assert ds.transmittance.values == pytest.approx([0.601, 0.600], rel=REL)
    assert ds.h2o_transmittance.values == pytest.approx([0.991, 0.990], rel=REL)
    assert ds.h2o_continuum_transmittance.values == pytest.approx([1.0, 1.0], rel=REL)
    assert ds.rayleigh_transmittance.values == pytest.approx([0.8801, 0.88], rel=REL)
    assert ds.aerosol_cloud_transmittance.values == pytest.approx([0.721, 0.72], rel=REL)


def test_tape7_solar_irradiance_mode(write):
    ds = read_modtran_tape7(write("sun.tp7", TAPE7_IRRADIANCE))
    nu = np.array([18005.0, 18000.0])
    assert ds.sun_transmittance.values == pytest.approx([0.701, 0.700], rel=REL)
    assert ds.direct_solar_irradiance.values == pytest.approx(
        np.array([4.006e-6, 4.0e-6]) * nu**2, rel=REL)
    # 5.714e-6 W cm-2 (cm-1)-1 at 18000 cm-1 is 1851 W m-2 um-1, the sun at 0.556 um
    assert float(ds.toa_irradiance[-1]) == pytest.approx(1851.3, rel=1e-4)


def test_tape7_runs_and_units(write):
    path = write("two.tp7", TAPE7_TRANSMITTANCE + TAPE7_IRRADIANCE)
    assert read_modtran_tape7(path, run=1).attrs["iemsct"] == 3
    with pytest.raises(ConfigError, match="holds 2 run"):
        read_modtran_tape7(path, run=2)
    per_um = TAPE7_IRRADIANCE.replace("  FREQ ", "WAVLEN").replace("18000.", "0.5556") \
        .replace("18005.", "0.5554")
    ds = read_modtran_tape7(write("um.tp7", per_um), radiance_unit="W cm-2 sr-1 um-1")
    assert float(ds.toa_irradiance[-1]) == pytest.approx(5.714e-6 * 1e4, rel=REL)
    with pytest.raises(ConfigError, match="unknown radiance unit") as info:
        read_modtran_tape7(path, radiance_unit="photons")
    assert info.value.key == "radiance_unit"


@pytest.mark.parametrize("text, match", [
    ("TMF 2    2    0\n 1 2 3\n -9999.\n", "no column header"),
    ("garbage\n  FREQ TRANS\n 1 2\n -9999.\n", "cannot read IEMSCT"),
    (TAPE7_IRRADIANCE.replace(" 18000.  0.7000", " 18000.  abc"), "holds something other than numbers"),
    ("TMF 2    2    2\n  FREQ TOT_TRANS\n -9999.\n", "no spectral data"),
])
def test_tape7_bad_files(write, text, match):
    with pytest.raises(ConfigError, match=match):
        read_modtran_tape7(write("bad.tp7", text))
    with pytest.raises(ConfigError, match="no such file") as info:
        read_modtran_tape7(write("x", "") .with_name("missing.tp7"))
    assert info.value.key == "path"


# -- libRadtran -------------------------------------------------------------------------------
# libradtran_rossli_*: UVSPEC_BRDF_ROSSLI.OUT (phi 0 45 90; umu 0.1 0.2 0.5 1.0)
UVSPEC_ROSSLI = """\
  400.000  8.660254e-01  2.518698e-09  2.185727e-01  7.957747e-02  2.872363e-10  3.142996e-02
                                  0.000            45.000            90.000
 0.1000  4.495140910e-02   2.365683764e-02   2.954325266e-02   4.445107654e-02
 0.2000  5.999799818e-02   4.923018068e-02   5.207472667e-02   5.954786018e-02
 0.5000  6.848490983e-02   6.360895932e-02   6.475118548e-02   6.789097935e-02
 1.0000  7.364086062e-02   7.364086062e-02   7.364086062e-02   7.364086062e-02
"""
UVSPEC_ROSSLI_INPUT = """\
# Ross-Li BRDF, empty atmosphere (libRadtran examples/UVSPEC_BRDF_ROSSLI.INP, abridged)
sza 30.0                 # Solar zenith angle
wavelength 400.0 400.0   # Wavelengths considered
umu 0.1 0.2 0.5 1.0
phi 0 45 90
output_quantity transmittance
"""


def test_uvspec_radiance_table_with_its_input_file(write):
    ds = read_uvspec(write("rossli.out", UVSPEC_ROSSLI),
                     input_file=write("rossli.inp", UVSPEC_ROSSLI_INPUT))
    assert ds.wavelength.values.tolist() == [0.4]
    assert ds.radiance.dims == ("wavelength", "umu", "phi")
    assert ds.radiance.shape == (1, 4, 3)
    assert float(ds.radiance.sel(umu=0.5, phi=45.0)[0]) == pytest.approx(6.475118548e-02,
                                                                       rel=REL)
    assert ds.azimuthal_mean_radiance.values[0] == pytest.approx(
        [4.495140910e-02, 5.999799818e-02, 6.848490983e-02, 7.364086062e-02], rel=REL)
    assert ds.view_zenith.values == pytest.approx(np.degrees(np.arccos([0.1, 0.2, 0.5, 1.0])),
                                                  rel=REL)
    assert ds.radiance.attrs["units"] == "sr-1"  # normalised: transmittance output
    # an empty atmosphere transmits the sun fully: edir = cos(sza) E0
    assert float(ds.sun_transmittance[0]) == pytest.approx(1.0, rel=1e-6)


def test_uvspec_absolute_irradiances(write):
    text = ("  550.000  1.2e+03  4.0e+02  1.0e+02  3.0e+02  1.5e+02  4.0e+01\n"
            "  450.000  1.1e+03  5.0e+02  1.2e+02  2.8e+02  1.9e+02  5.0e+01\n")
    ds = read_uvspec(write("irr.out", text))
    assert ds.wavelength.values == pytest.approx([0.45, 0.55], rel=REL)
    # mW m-2 nm-1 is W m-2 um-1
    assert ds.direct_irradiance.values == pytest.approx([1100.0, 1200.0], rel=REL)
    assert ds.diffuse_down_irradiance.values == pytest.approx([500.0, 400.0], rel=REL)
    assert ds.diffuse_up_irradiance.attrs["units"] == "W m-2 um-1"
    scaled = read_uvspec(write("irr.out", text), unit_scale=1e3)  # W m-2 nm-1
    assert scaled.direct_irradiance.values == pytest.approx([1.1e6, 1.2e6], rel=REL)


def test_uvspec_umu_without_phi(write):
    text = ("  500.0  1.0 2.0 3.0 4.0 5.0 6.0\n"
            " -1.0000  7.0e+01\n"
            "  1.0000  2.0e+01\n")
    ds = read_uvspec(write("umu.out", text), umu=[-1.0, 1.0])
    assert ds.azimuthal_mean_radiance.values[0].tolist() == [70.0, 20.0]
    assert ds.view_zenith.values.tolist() == [180.0, 0.0]
    assert "radiance" not in ds


def test_parse_uvspec_input(write):
    settings = parse_uvspec_input(write("a.inp", UVSPEC_ROSSLI_INPUT + "zout sur toa\n"))
    assert settings == {"sza": 30.0, "umu": [0.1, 0.2, 0.5, 1.0], "phi": [0.0, 45.0, 90.0],
                        "output_quantity": "transmittance", "zout": ["sur", "toa"]}


@pytest.mark.parametrize("kwargs, match, key", [
    ({"umu": [0.1, 0.2, 0.5]}, "do not split into blocks", "path"),
    ({"umu": [0.1, 0.2, 0.5, 0.9], "phi": [0, 45, 90]}, "does not match umu", "path"),
    ({"umu": [0.1, 0.2, 0.5, 1.0], "phi": [0, 30, 90]}, "differs from phi", "path"),
    ({"umu": [0.1, 0.2, 0.5, 1.0], "phi": [0, 45, 90], "output_quantity": "brightness"},
     "unknown output_quantity", "output_quantity"),
    ({"phi": [0, 45, 90]}, "phi without umu", "umu"),
    ({"umu": [1.5, 0.2, 0.5, 1.0], "phi": [0, 45, 90]}, r"\[-1, 1\]", "umu"),
])
def test_uvspec_bad_settings(write, kwargs, match, key):
    with pytest.raises(ConfigError, match=match) as info:
        read_uvspec(write("rossli.out", UVSPEC_ROSSLI), **kwargs)
    assert info.value.key == key


def test_uvspec_output_user_is_refused(write):
    inp = write("u.inp", "output_user lambda uu\numu 1.0\n")
    with pytest.raises(ConfigError, match="output_user"):
        read_uvspec(write("u.out", "500 1.0\n"), input_file=inp)


def test_readers_share_the_engine_form(write):
    # the variables a renderer or the CLI reads exist under the same names and units
    ds = read_modtran_tape7(write("rad.tp7", TAPE7_RADIANCE))
    for name in ("transmittance", "path_thermal_radiance", "path_scattered_radiance",
                 "path_radiance"):
        assert ds[name].dims == ("wavelength",)
    assert ds.wavelength.attrs["units"] == "um"
    assert np.all(np.diff(ds.wavelength.values) > 0)
