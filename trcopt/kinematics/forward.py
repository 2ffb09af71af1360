"""Forward kinematics of a toolholder with orientation capability (spec §3, §4).

Given the two axis positions α1, α2 [deg] this module computes the rotations of the tool and of
the part, the resulting tool length vector ``L_res`` (tool tip → holder reference point, F1), the
table offset Δ (F2) and the tool direction relative to the workpiece (F3). Conventions:

* rotations are right-handed about the normalised axis vector (a positive angle turns clockwise
  seen from behind the arrow); a zero axis vector is an absent axis (identity);
* the geometric angle of axis i is ``θi = αi − offset_i`` (``$TC_CARR24/25`` + fine offsets);
* plane changes G17–G19 permute only the tool's length components (:func:`tool_length_vector`);
  the holder vectors are never permuted.
"""

from __future__ import annotations

import math
from collections.abc import Sequence

import numpy as np

from trcopt.geometry.plane import Plane
from trcopt.kinematics.carrier import Carrier, KinematicType
from trcopt.modes import ToolFamily, WearMode, parse_enum

__all__ = [
    "rotation",
    "rpy_matrix",
    "initial_direction",
    "tool_length_vector",
    "holder_rotations",
    "part_rotations",
    "resulting_tool_length",
    "table_offset",
    "relative_direction",
    "machine_position",
]

_EPS_AXIS = 1e-12


def rotation(axis: Sequence[float] | np.ndarray, angle_deg: float) -> np.ndarray:
    """Right-handed rotation matrix about ``axis`` by ``angle_deg`` (Rodrigues).

    Parameters
    ----------
    axis:
        Direction (any length). A zero vector yields the identity (absent axis).
    angle_deg:
        Rotation angle [deg].
    """
    v = np.asarray(axis, dtype=float)
    nv = float(np.linalg.norm(v))
    if nv < _EPS_AXIS:
        return np.eye(3)
    k = v / nv
    t = math.radians(angle_deg)
    kx = np.array([[0.0, -k[2], k[1]], [k[2], 0.0, -k[0]], [-k[1], k[0], 0.0]])
    return np.eye(3) + math.sin(t) * kx + (1.0 - math.cos(t)) * (kx @ kx)


def rpy_matrix(x_deg: float = 0.0, y_deg: float = 0.0, z_deg: float = 0.0) -> np.ndarray:
    """Frame rotation of ``ROT X.. Y.. Z..`` with the default MD10600 (RPY, ``Rz·Ry·Rx``) [deg]."""
    return (
        rotation((0.0, 0.0, 1.0), z_deg)
        @ rotation((0.0, 1.0, 0.0), y_deg)
        @ rotation((1.0, 0.0, 0.0), x_deg)
    )


def initial_direction(plane: Plane | str = Plane.G17) -> np.ndarray:
    """Tool direction with both angles zero and no frame: +Z (G17), +Y (G18), +X (G19; the spec's
    R3 reading of a manual typo)."""
    p = Plane.parse(plane)
    e = np.zeros(3)
    e[p.axes[2]] = 1.0
    return e


def tool_length_vector(
    lengths: Sequence[float],
    plane: Plane | str = Plane.G17,
    family: ToolFamily | str = ToolFamily.MILLING,
) -> np.ndarray:
    """The tool's own length vector ``L_tool`` [mm] for the active plane (spec §3.4).

    Milling: G17 ``L1→Z, L2→Y, L3→X``; G18 ``L1→Y, L2→X, L3→Z``; G19 ``L1→X, L2→Z, L3→Y``
    (L1 along the applicate, L2 the ordinate, L3 the abscissa). Turning: G18 ``L1→X, L2→Z, L3→Y``
    and the cyclic analogues (L1 ordinate, L2 abscissa, L3 applicate).

    Parameters
    ----------
    lengths:
        ``(L1,)``, ``(L1, L2)`` or ``(L1, L2, L3)`` [mm]: geometry + wear + adapter already summed.
    plane:
        Active plane.
    family:
        Tool family choosing the table.
    """
    p = Plane.parse(plane)
    fam = parse_enum(ToolFamily, family, "tool family")
    ls = [float(x) for x in lengths] + [0.0] * (3 - len(lengths))
    if len(ls) != 3:
        raise ValueError(f"expected 1 to 3 tool lengths, got {len(lengths)}")
    u, v, w = p.axes
    out = np.zeros(3)
    if fam is ToolFamily.MILLING:
        out[w], out[v], out[u] = ls
    else:
        out[v], out[u], out[w] = ls
    return out


def holder_rotations(
    carrier: Carrier, angle1: float, angle2: float
) -> tuple[np.ndarray, np.ndarray]:
    """``(R1, R2)`` for axis positions ``angle1, angle2`` [deg] (``θi = αi − offset_i``)."""
    off1, off2 = carrier.axis_offsets
    return (rotation(carrier.v1, angle1 - off1), rotation(carrier.v2, angle2 - off2))


def _tool_part(carrier: Carrier, r1: np.ndarray, r2: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
    kt = carrier.kinematic_type
    if kt is KinematicType.T:
        return r1 @ r2, np.eye(3)
    if kt is KinematicType.P:
        return np.eye(3), r1 @ r2
    return r1, r2


def part_rotations(carrier: Carrier, angle1: float, angle2: float) -> tuple[np.ndarray, np.ndarray]:
    """``(R_tool, R_part)``: rotation of the tool and of the part (the latter for a PAROT-like
    frame; TCARR itself does not rotate the coordinate system)."""
    return _tool_part(carrier, *holder_rotations(carrier, angle1, angle2))


def resulting_tool_length(
    carrier: Carrier,
    angle1: float,
    angle2: float,
    tool: Sequence[float] | np.ndarray,
    *,
    wear: Sequence[float] | np.ndarray | None = None,
    wear_mode: WearMode = WearMode.TOWSTD,
) -> np.ndarray:
    """F1: resulting tool length vector ``L_res`` [mm] (tool tip → holder reference point).

    Parameters
    ----------
    carrier:
        The holder.
    angle1, angle2:
        Axis positions [deg].
    tool:
        ``L_tool`` [mm] already assigned to axes for the plane (see :func:`tool_length_vector`).
    wear:
        Optional wear vector [mm] in the same axes; with ``TOWSTD`` it is rotated with the tool
        (equivalent to adding it to ``tool``), with ``TOWMCS`` it is added unrotated.
    wear_mode:
        Wear handling.
    """
    r1, r2 = holder_rotations(carrier, angle1, angle2)
    l1, l2, l3, _ = carrier.offsets
    lt = np.asarray(tool, dtype=float)
    w = np.zeros(3) if wear is None else np.asarray(wear, dtype=float)
    if wear_mode is WearMode.TOWSTD:
        lt, w = lt + w, np.zeros(3)
    kt = carrier.kinematic_type
    if kt is KinematicType.T:
        res = l1 + r1 @ (l2 + r2 @ (l3 + lt))
    elif kt is KinematicType.P:
        res = lt.copy()
    else:
        res = l1 + r1 @ (l2 + lt)
    return res + w


def table_offset(carrier: Carrier, angle1: float, angle2: float) -> np.ndarray:
    """F2: additive translation Δ [mm] of the table reference point (zero for type T)."""
    r1, r2 = holder_rotations(carrier, angle1, angle2)
    _, l2, l3, l4 = carrier.offsets
    kt = carrier.kinematic_type
    if kt is KinematicType.T:
        return np.zeros(3)
    if kt is KinematicType.P:
        return l2 + r1 @ (l3 + r2 @ l4)
    return l3 + r2 @ l4


def relative_direction(
    carrier: Carrier, angle1: float, angle2: float, base: Sequence[float] | np.ndarray
) -> np.ndarray:
    """F3: ``d_rel = R_partᵀ · R_tool · e``, the direction ``base`` (e, a unit vector) after the
    holder moved, seen from the un-rotated workpiece."""
    r_tool, r_part = part_rotations(carrier, angle1, angle2)
    return r_part.T @ (r_tool @ np.asarray(base, dtype=float))


def machine_position(
    carrier: Carrier,
    angle1: float,
    angle2: float,
    programmed: Sequence[float],
    tool: Sequence[float] | np.ndarray,
) -> np.ndarray:
    """Position of the holder reference point [mm] for a programmed point: ``P + Δ + L_res``
    (F4; the workpiece zero moves with the table, axis directions stay parallel)."""
    p = np.asarray(programmed, dtype=float)
    return p + table_offset(carrier, angle1, angle2) + resulting_tool_length(
        carrier, angle1, angle2, tool
    )
