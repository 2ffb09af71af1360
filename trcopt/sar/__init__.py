"""Smooth approach and retraction: lead geometry (dialect-neutral) and the SINUMERIK SAR pre-pass.

``expand_sar`` turns SAR blocks (G147…G348) into ordinary canonical moves that the compensation
engine handles as if programmed; ``sar_points`` is the analytic construction of P0…P4 on its
own (for the optimiser and for tests).
"""

from .lead import (
    LeadShape,
    LeadSide,
    LeadSpec,
    RetractEnd,
    SarGeometry,
    Segmentation,
    lead_spec,
    sar_points,
    side_from_start_point,
)
from .siemens import PREPROCESSING_STOP, expand_sar

__all__ = [
    "LeadShape",
    "LeadSide",
    "LeadSpec",
    "RetractEnd",
    "SarGeometry",
    "Segmentation",
    "lead_spec",
    "sar_points",
    "side_from_start_point",
    "expand_sar",
    "PREPROCESSING_STOP",
]
