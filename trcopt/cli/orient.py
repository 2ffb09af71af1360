"""``trcopt orient``: both holder solutions for a requested orientation, the chosen one and why.

The main CLI adds the arguments with :func:`add_arguments`; :func:`run_orient` does the work
and returns the exit code (0 ok, 1 unreachable orientation or alarm, 2 usage or file error).
Errors print as ``file: error …`` on stderr, never as a traceback.
"""

from __future__ import annotations

import argparse
import json
import math
import sys
from pathlib import Path
from typing import Any

import numpy as np

from trcopt.errors import AlarmError, ConfigError, Diagnostic, Severity, SourceSpan
from trcopt.kinematics.carrier import ALARM_KINEMATIC_TYPE, Carrier, carrier_from_assignments
from trcopt.kinematics.carrier_toml import load_carrier_toml
from trcopt.kinematics.forward import (
    initial_direction,
    relative_direction,
    resulting_tool_length,
    table_offset,
    tool_length_vector,
)
from trcopt.kinematics.inverse import inverse_solutions
from trcopt.kinematics.orientation import frame_matrix, reference_angles
from trcopt.kinematics.program import scan_program
from trcopt.kinematics.selection import Selection, select_solution
from trcopt.modes import OrientationWord, ToolFamily, parse_enum

__all__ = ["add_arguments", "run_orient", "DEFAULT_TOOL_LENGTHS"]

#: Tool lengths used when ``--tool-length`` is not given: the reference milling tool of the
#: spec's worked examples (L1 = 100 mm), so printed tool vectors match §11.
DEFAULT_TOOL_LENGTHS = (100.0, 0.0, 0.0)


def add_arguments(p: argparse.ArgumentParser) -> None:
    """The arguments of ``trcopt orient``."""
    p.description = (
        "Print both solutions (alpha1, alpha2) [deg] of a SINUMERIK toolholder with "
        "orientation capability for a requested tool direction or frame, the chosen pair "
        "and why (360 deg shift, Hirth grid, order, software limits)."
    )
    p.add_argument(
        "--carrier",
        required=True,
        metavar="FILE",
        help="carrier TOML (keys TC_CARR1..65) or a SINUMERIK program with $TC_CARR assignments",
    )
    p.add_argument("--holder", type=int, default=None, metavar="M",
                   help="data block number when FILE is a program defining several")
    g = p.add_mutually_exclusive_group(required=True)
    g.add_argument("--direction", nargs=3, type=float, metavar=("DX", "DY", "DZ"),
                   help="requested tool direction relative to the workpiece")
    g.add_argument("--frame", nargs="+", type=float, metavar="ANGLE",
                   help="ROT X Y Z angles [deg] (RPY, Rz*Ry*Rx) or 9 numbers of a rotation "
                        "matrix (row-major)")
    p.add_argument("--word", default="TCOFR", choices=["TCOFR", "TCOFRZ", "TCOFRY", "TCOFRX"],
                   help="which tool axis follows the same frame axis (default TCOFR = Z)")
    p.add_argument("--plane", default="G17", choices=["G17", "G18", "G19"],
                   help="active plane: assigns the tool lengths (angles do not depend on it)")
    p.add_argument("--tool-length", nargs="+", type=float, default=None, metavar="L",
                   help="tool lengths L1 [L2 [L3]] in mm (default 100 0 0)")
    p.add_argument("--family", default="milling", choices=["milling", "turning"],
                   help="tool family for the length assignment (default milling)")
    p.add_argument("--reference", nargs=2, type=float, default=None, metavar=("A1", "A2"),
                   help="specified angles [deg] (default $TC_CARR13/14)")
    p.add_argument("--json", default=None, metavar="OUT", help="write the result as JSON")
    p.set_defaults(handler=run_orient)


def _err(file: str, message: str, code: str = "USAGE") -> None:
    """``file: error CODE: message`` (the one error form of every command)."""
    prefix = f"{file}: "
    if message.startswith(prefix):
        message = message[len(prefix) :]
    print(f"{file}: error {code}: {message}", file=sys.stderr)


def _load(args: argparse.Namespace) -> Carrier:
    path = Path(args.carrier)
    if path.suffix.lower() == ".toml":
        return load_carrier_toml(path)
    try:
        text = path.read_text(encoding="utf-8", errors="replace")
    except OSError as exc:
        raise ConfigError(f"{path}: cannot read program: {exc.strerror}") from None
    carriers, _ = scan_program(text, str(path))
    if not carriers:
        raise ConfigError(f"{path}: no $TC_CARR assignments found")
    if args.holder is None:
        if len(carriers) != 1:
            raise ConfigError(
                f"{path}: defines toolholders {sorted(carriers)}; choose one with --holder"
            )
        m = next(iter(carriers))
    else:
        m = args.holder
        if m not in carriers:
            raise ConfigError(
                f"{path}: toolholder {m} is not defined (defined: {sorted(carriers)})"
            )
    return carrier_from_assignments(carriers[m], m, SourceSpan(file=str(path)))


def _fmt(x: float) -> str:
    return f"{x:.6f}"


def run_orient(args: argparse.Namespace) -> int:
    """Execute ``trcopt orient``; see :func:`add_arguments` for the options. Returns the exit code."""
    file = str(args.carrier)
    try:
        carrier = _load(args)
    except AlarmError as exc:  # alarm 14153 from a program's data block
        dg = exc.diagnostic
        _err(file, dg.message, dg.code)
        return 1
    except ConfigError as exc:
        _err(file, exc.message, exc.code)
        return 1 if exc.code == str(ALARM_KINEMATIC_TYPE) else 2
    word = parse_enum(OrientationWord, args.word)
    try:
        e = np.zeros(3)
        e[word.base_axis] = 1.0
        if args.direction is not None:
            d = np.asarray(args.direction, dtype=float)
            if not np.all(np.isfinite(d)) or float(np.linalg.norm(d)) < 1e-12:
                raise ValueError("--direction must be a non-zero vector")
            d = d / np.linalg.norm(d)
        else:
            vals = list(args.frame)
            if len(vals) in (1, 2):
                vals = vals + [0.0] * (3 - len(vals))
            if len(vals) == 9:
                rot = frame_matrix(np.asarray(vals).reshape(3, 3))
            elif len(vals) == 3:
                rot = frame_matrix(vals)
            else:
                raise ValueError("--frame takes up to 3 ROT angles or 9 matrix entries")
            d = rot @ e
        lengths = tuple(args.tool_length) if args.tool_length else DEFAULT_TOOL_LENGTHS
        if len(lengths) > 3:
            raise ValueError("--tool-length takes at most 3 values")
    except ValueError as exc:
        _err(file, str(exc))
        return 2
    ref = tuple(args.reference) if args.reference else reference_angles(carrier)
    ref = (float(ref[0]), float(ref[1]))
    inv = inverse_solutions(carrier, d, e, ref)
    diags: list[Diagnostic] = list(carrier.warnings())
    selection: Selection | None = None
    try:
        selection = select_solution(carrier, inv, ref, word=word, span=SourceSpan(file=file))
    except AlarmError as exc:
        diags.append(exc.diagnostic)

    kt = carrier.kinematic_type.value
    print(f"{file}: toolholder {carrier.number}, kinematic type {kt}")
    print(
        f"requested {word.value}: tool axis {'XYZ'[word.base_axis]} -> direction "
        f"({', '.join(f'{x:.6g}' for x in d)}); specified angles ({ref[0]:g}, {ref[1]:g})"
    )
    print(f"case: {inv.kind.value} ({inv.note})")
    for i, p in enumerate(inv.pairs, start=1):
        free = "".join(
            f" [axis {k} free]" for k, f in ((1, p.free1), (2, p.free2)) if f
        )
        print(f"exact solution {i}: alpha1 = {_fmt(p.angle1)}  alpha2 = {_fmt(p.angle2)}{free}")
    tool_vec: list[float] | None = None
    out: dict[str, Any] = {
        "solutions": [],
        "chosen": None,
        "p_tcang": [None, None, None, None],
        "tool_vector": None,
    }
    if selection is not None:
        for i, p in enumerate(selection.ordered, start=1):
            print(f"solution {i} (shifted/rounded): ({_fmt(p.angle1)}, {_fmt(p.angle2)})")
        a1, a2 = selection.chosen
        print(f"chosen: ({_fmt(a1)}, {_fmt(a2)})")
        print(
            "$P_TCANG[1..4] = ("
            + ", ".join("nan" if math.isnan(x) else f"{x:.6g}" for x in selection.p_tcang)
            + ")"
        )
        for r in selection.reasons:
            print(f"  because: {r}")
        lt = tool_length_vector(lengths, args.plane, ToolFamily(args.family))
        res = resulting_tool_length(carrier, a1, a2, lt)
        tool_vec = [float(x) + 0.0 for x in res]
        delta = table_offset(carrier, a1, a2)
        tdir = relative_direction(carrier, a1, a2, initial_direction(args.plane))
        print(
            f"tool vector ({args.plane}, L = {', '.join(f'{x:g}' for x in lengths)} mm): "
            f"({', '.join(f'{x:.4f}' for x in res)}) mm"
        )
        if carrier.kinematic_type.value != "T":
            print(f"table offset: ({', '.join(f'{x:.4f}' for x in delta)}) mm")
        if selection.orientation_error_deg > 0.0:
            print(f"orientation error (Hirth): {selection.orientation_error_deg:.4f} deg")
        out.update(
            solutions=[list(p.angles) for p in selection.ordered],
            chosen=[a1, a2],
            p_tcang=[None if math.isnan(x) else x for x in selection.p_tcang],
            tool_vector=tool_vec,
            tool_direction=[float(x) + 0.0 for x in tdir],
            table_offset=[float(x) + 0.0 for x in delta],
            p_tcsol=selection.tcsol,
            reasons=list(selection.reasons),
        )
    else:
        out["solutions"] = [list(p.angles) for p in inv.pairs]
    out["p_tcang0"] = inv.count
    out["diagnostics"] = [dg.to_json() for dg in diags]
    for dg in diags:
        stream = sys.stderr if dg.severity is Severity.ERROR else sys.stdout
        print(f"{file}: {dg.severity.value} {dg.code}: {dg.message}", file=stream)
    if args.json:
        try:
            from trcopt.io import write_text_atomic

            write_text_atomic(args.json, json.dumps(out, indent=2) + "\n")
        except OSError as exc:  # OutputError: nothing half-written
            _err(args.json, str(exc), "OUTPUT")
            return 2
    return 0 if selection is not None else 1
