"""Toolholder with orientation capability (SINUMERIK ``$TC_CARR``): data, forward and inverse.

* :mod:`.carrier` — the ``$TC_CARRn[m]`` data block, from and to assignments;
* :mod:`.carrier_toml` — the data block as a TOML carrier file;
* :mod:`.forward` — tool length vector, table offset and tool direction for given angles;
* :mod:`.inverse` — closed-form solutions for a requested orientation;
* :mod:`.selection` — the selection rules (360° shift, Hirth grid, order, software limits,
  ``$P_TCANG``);
* :mod:`.orientation` — TCOFR/TCOFRZ/Y/X and TCOABS: the angles a holder activation uses;
* :mod:`.program` — TCARR / TCOABS / TCOFR in a part program (plan JSON key ``"toolholder"``).

The ``trcopt orient`` subcommand is :mod:`trcopt.cli.orient`.

Angles in degrees, lengths in mm throughout.

Readings of ``spec/toolholder.md`` where it is silent or ambiguous (its R-numbers in brackets):

* rotations are right-handed about the normalised axis vector; zero vector = axis absent;
  geometric angle ``θ = α − offset`` with offset ``$TC_CARR24/25`` (+ fine 64/65) [R2];
* fine offsets (index k + 40) are added unless ``fine_offsets_enabled = false`` [R1];
* G19 initial tool direction +X [R3]; TCOFRX/Y align tool x/y with frame x/y [R6];
* l1 is ignored for type P and l4 for type T, with a warning; open chains are allowed and act as
  a constant offset, with a warning ``TH-CHAIN-OPEN`` [R4, R5];
* no Siemens numbers were found except 14153, so the other errors carry project codes:
  ``TH-UNREACHABLE``, ``TH-NO-VALID-SOLUTION``, ``TH-LIMIT``, ``TH-UNDEFINED-PARAM``,
  ``TH-VALUE``, ``TH-UNKNOWN-HOLDER`` [R7]; one axis and an unreachable direction is an error,
  never an approximation [R8];
* processing order: shift toward the specified angle → Hirth → order → limits [R9]; Hirth rounds
  to the nearest grid value, ties toward the specified angle [R10]; "closest" is the L1 distance
  of the two angles, ties by |α1 − ref1|, then lexicographic [R11]; of several ±k·360°
  candidates inside the limits the one nearest the specified angle is kept, an angle already
  inside is never moved [R12]; ``$P_TCANG[0]``, ``$P_TCSOL``, ``$P_TCDIFF`` follow the spec's
  project convention (NaN for a missing second pair; ``null`` in JSON) [R13];
* free angles (axis parallel to the vector it turns; parallel axes, where only a combination is
  fixed) take the specified angle and are not shifted; a missing axis keeps its specified angle;
* TCOABS angles are limit-checked (±k·360°) but not Hirth-rounded (they are given positions);
* the cone tolerance ``CONE_EPS = 1e-9`` lets a direction that misses the reachable set by less
  than that count as the boundary (one solution); two solutions closer than rounding
  (``γ²|a×b|² ≤ 1e-15``) are reported as one;
* known limitation: an axis within ~1e-8 rad of (but not exactly) parallel to the vector it
  turns loses precision in floating point (residual of the order of that angle);
* ``trcopt orient`` reports the tool vector for the spec's reference milling tool L1 = 100 mm
  unless ``--tool-length`` is given; :func:`evaluate_toolholder` uses the tool lengths it is
  given (default zero: the holder's own contribution);
* in a program, group 42 starts as TCOABS; TCOFR reads the programmed ROT/AROT rotation at
  selection time (identity when none: the tool stays along +Z); later frame changes do not move
  the holder [REQ-TH-14]; words of one block act together (TCARR after the modal words);
  alarm 14153 is raised when ``TCARR=m`` selects the block, with that block's line and number.
"""

from __future__ import annotations

from trcopt.kinematics.carrier import (
    ALARM_KINEMATIC_TYPE,
    Carrier,
    KinematicType,
    carrier_from_assignments,
)
from trcopt.kinematics.carrier_toml import carrier_from_toml_dict, load_carrier_toml
from trcopt.kinematics.forward import (
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
from trcopt.kinematics.inverse import AnglePair, InverseResult, SolutionKind, inverse_solutions
from trcopt.kinematics.orientation import frame_matrix, reference_angles, solve_orientation, tcoabs_angles
from trcopt.kinematics.program import evaluate_toolholder, scan_program
from trcopt.kinematics.selection import Selection, fit_limits, hirth_round, select_solution, shift_toward
from trcopt.modes import OrientationWord, ToolFamily, WearMode

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
