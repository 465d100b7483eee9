"""Image-quality analysis: slanted-edge MTF, 3-D noise, noise budget, SNR and NEΔT."""

from radscene.sensor.analysis.edge import EdgeMTF, slanted_edge_mtf
from radscene.sensor.analysis.noise3d import COMPONENTS, Noise3D, noise_3d, noise_3d_reference
from radscene.sensor.analysis.performance import NoiseBudget, netd, noise_budget, system_mtf

__all__ = [
    "EdgeMTF",
    "slanted_edge_mtf",
    "Noise3D",
    "COMPONENTS",
    "noise_3d",
    "noise_3d_reference",
    "NoiseBudget",
    "noise_budget",
    "netd",
    "system_mtf",
]
