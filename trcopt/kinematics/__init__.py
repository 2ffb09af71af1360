"""Toolholder with orientation capability (SINUMERIK ``$TC_CARR``): data, forward and inverse.

* :mod:`.carrier` — the ``$TC_CARRn[m]`` data block, from assignments or TOML;
* :mod:`.forward` — tool length vector, table offset and tool direction for given angles;
* :mod:`.inverse` — closed-form solutions for a requested orientation and the selection rules
  (360° shift, Hirth grid, order, software limits, ``$P_TCANG``);
* :mod:`.program` — TCARR / TCOABS / TCOFR in a part program (plan JSON key ``"toolholder"``);
* :mod:`.cli` — the ``trcopt orient`` subcommand.

Angles in degrees, lengths in mm throughout.
"""

from __future__ import annotations

from .carrier import (
    ALARM_KINEMATIC_TYPE,
    Carrier,
    KinematicType,
    carrier_from_assignments,
    carrier_from_toml_dict,
    load_carrier_toml,
)
from .forward import (
    ToolFamily,
    WearMode,
    initial_direction,
    machine_position,
    part_rotations,
    relative_direction,
    resulting_tool_length,
    rotation,
    rpy_matrix,
    table_offset,
    tool_length_vector,
)
from .inverse import (
    AnglePair,
    InverseResult,
    OrientationWord,
    Selection,
    SolutionKind,
    fit_limits,
    frame_matrix,
    hirth_round,
    inverse_solutions,
    reference_angles,
    select_solution,
    shift_toward,
    solve_orientation,
    tcoabs_angles,
)
from .program import evaluate_toolholder, scan_program

__all__ = [
    "ALARM_KINEMATIC_TYPE",
    "AnglePair",
    "Carrier",
    "InverseResult",
    "KinematicType",
    "OrientationWord",
    "Selection",
    "SolutionKind",
    "ToolFamily",
    "WearMode",
    "carrier_from_assignments",
    "carrier_from_toml_dict",
    "evaluate_toolholder",
    "fit_limits",
    "frame_matrix",
    "hirth_round",
    "initial_direction",
    "inverse_solutions",
    "load_carrier_toml",
    "machine_position",
    "part_rotations",
    "reference_angles",
    "relative_direction",
    "resulting_tool_length",
    "rotation",
    "rpy_matrix",
    "scan_program",
    "select_solution",
    "shift_toward",
    "solve_orientation",
    "table_offset",
    "tcoabs_angles",
    "tool_length_vector",
]
