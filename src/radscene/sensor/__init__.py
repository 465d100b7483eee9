"""The sensor: optics, detector, noise, electronics, processing, and image-quality analysis.

The renderer draws the at-aperture radiance on a grid ``oversample`` times finer than the
detector; a :class:`Sensor` turns it into digital numbers, with the truth carried along::

    from radscene.sensor import make_sensor, load_sensor
    sensor = load_sensor("mwir_cooled")            # a bundled example, or a YAML path
    signal = sensor.apply(images, frames=4, seed=1)   # images: radscene.render(...) output
    signal["dn"]                                    # (frame, band, y, x) [DN]

Analysis: :func:`slanted_edge_mtf`, :func:`noise_3d`, :func:`noise_budget`, :func:`netd`.
"""

from radscene.sensor.analysis import (
    EdgeMTF,
    Noise3D,
    NoiseBudget,
    netd,
    noise_3d,
    noise_budget,
    slanted_edge_mtf,
    system_mtf,
)
from radscene.sensor.chain import DETECTORS, Sensor
from radscene.sensor.channel import Channel, Motion
from radscene.sensor.config import (
    SENSOR_TYPES,
    example_sensor_path,
    example_sensors,
    load_sensor,
    make_sensor,
)
from radscene.sensor.detector import Microbolometer, PhotonDetector
from radscene.sensor.electronics import Electronics
from radscene.sensor.optics import Dome, HeatedAir, Optics
from radscene.sensor.processing import AGC, DCS, NUC, PROCESSING

__all__ = [
    "Sensor",
    "Channel",
    "Motion",
    "Optics",
    "Dome",
    "HeatedAir",
    "PhotonDetector",
    "Microbolometer",
    "Electronics",
    "DCS",
    "NUC",
    "AGC",
    "PROCESSING",
    "DETECTORS",
    "SENSOR_TYPES",
    "make_sensor",
    "load_sensor",
    "example_sensors",
    "example_sensor_path",
    "slanted_edge_mtf",
    "EdgeMTF",
    "noise_3d",
    "Noise3D",
    "noise_budget",
    "NoiseBudget",
    "netd",
    "system_mtf",
]
