"""TCARR / TCOABS / TCOFR in a part program: the ``"toolholder"`` entry of the plan JSON.

:func:`scan_program` extracts ``$TC_CARRn[m]=`` assignments and the holder words from SINUMERIK
text (a small scanner for users without the full NC front end); :func:`evaluate_toolholder`
runs the words in program order like the control and reports the active holder, the angles, the
``$P_TCANG`` values and the tool vector.

Assumptions (the spec leaves them open):

* group 42 starts as TCOABS (the control's default);
* TCOFR* read the *programmed frame rotation* at the moment the holder is (re)selected; events
  ``{"word": "ROT"|"AROT", "value": [x, y, z]}`` (degrees, RPY ``Rz·Ry·Rx``) set/compose it, and
  without any the frame is the identity, so TCOFR requests the tool along +Z (angles that leave
  the tool vertical, nearest to the specified angles);
* a later frame change does not move the holder until TCARR or a group-42 word is programmed
  again (spec REQ-TH-14); a plane change G17–G19 recomputes only the tool vector;
* the carrier data are the values collected from the whole program (definitions are assumed to
  precede the activation); the data block is validated when ``TCARR=m`` selects it, so alarm
  14153 carries the line and block number of that TCARR;
* an error stops the evaluation like the control would; the dict reflects the state up to there.
"""

from __future__ import annotations

import math
import re
from collections.abc import Mapping, Sequence
from typing import Any

import numpy as np

from trcopt.codes import Code
from trcopt.errors import AlarmError, Diagnostic, Severity, SourceSpan
from trcopt.geometry.plane import Plane
from trcopt.kinematics.carrier import Carrier, carrier_from_assignments
from trcopt.kinematics.forward import (
    initial_direction,
    relative_direction,
    resulting_tool_length,
    rpy_matrix,
    table_offset,
    tool_length_vector,
)
from trcopt.kinematics.orientation import solve_orientation, tcoabs_angles
from trcopt.kinematics.selection import Selection
from trcopt.modes import OrientationWord, ToolFamily, parse_enum

__all__ = ["evaluate_toolholder", "scan_program"]

_GROUP42 = {w.value for w in OrientationWord}


def _vec(v: np.ndarray) -> list[float]:
    return [float(x) + 0.0 for x in v]


def _nan_none(x: float) -> float | None:
    return None if math.isnan(x) else float(x)


def evaluate_toolholder(
    carriers: Mapping[int, Mapping[int, float | str]],
    events: Sequence[Mapping[str, Any]],
    file: str,
    *,
    tool_lengths: Sequence[float] = (0.0, 0.0, 0.0),
    family: ToolFamily | str = ToolFamily.MILLING,
    plane: Plane | str = Plane.G17,
    axis_positions: Mapping[str, float] | None = None,
) -> tuple[dict[str, Any], list[Diagnostic]]:
    """Run the holder words of a program in order.

    Parameters
    ----------
    carriers:
        ``{m: {n: value}}``: the ``$TC_CARRn[m]`` values collected from the program.
    events:
        In program order, each ``{"line": int, "block": "N10" | None, "word": ..., "value": ...}``
        with word ``TCARR`` (value m; 0 deselects), ``TCOABS``, ``TCOFR``, ``TCOFRZ``,
        ``TCOFRY``, ``TCOFRX`` (value None); optionally ``G17``/``G18``/``G19`` and
        ``ROT``/``AROT`` (value ``[x, y, z]`` degrees, or None for ``ROT`` alone = no rotation).
        An optional ``"column"`` is carried into the spans.
    file:
        Program name for diagnostics.
    tool_lengths:
        Active tool ``(L1, L2, L3)`` [mm]; the default zero-length tool makes ``tool_vector`` the
        holder's own contribution.
    family:
        Tool family for the plane assignment of the lengths.
    plane:
        Plane at program start.
    axis_positions:
        Rotary axis positions [deg] by name, used when ``$TC_CARR21/22`` reference an axis.

    Returns
    -------
    (dict, list[Diagnostic])
        The dict has ``active`` (holder number, 0 = none), ``word`` (group 42), ``plane``,
        ``kinematic_type``, ``angles_deg`` ([α1, α2] or None), ``p_tcang`` ($P_TCANG[1..4], null
        for NaN), ``p_tcang0``, ``p_tcsol``, ``tool_vector`` (L_res [mm]), ``tool_direction``
        (unit, relative to the workpiece), ``table_offset`` (Δ [mm]), ``tool_lengths`` and
        ``activations`` (one record per (re)computation with line and block).
    """
    diags: list[Diagnostic] = []
    state: dict[str, Any] = {
        "active": 0,
        "word": OrientationWord.TCOABS.value,
        "plane": Plane.parse(plane).value,
        "kinematic_type": None,
        "angles_deg": None,
        "p_tcang": None,
        "p_tcang0": None,
        "p_tcsol": None,
        "tool_vector": None,
        "tool_direction": None,
        "table_offset": None,
        "tool_lengths": [float(x) for x in tool_lengths],
        "activations": [],
    }
    frame = np.eye(3)
    word = OrientationWord.TCOABS
    cur_plane = Plane.parse(plane)
    carrier: Carrier | None = None
    selection: Selection | None = None
    warned: set[int] = set()

    def publish(span: SourceSpan, recompute_angles: bool) -> None:
        nonlocal selection
        assert carrier is not None
        if recompute_angles or selection is None:
            if word is OrientationWord.TCOABS:
                selection = tcoabs_angles(carrier, axis_positions, span=span)
            else:
                selection = solve_orientation(
                    carrier, frame=frame, word=word, axis_positions=axis_positions, span=span
                )
        a1, a2 = selection.chosen
        lt = tool_length_vector(tool_lengths, cur_plane, family)
        res = resulting_tool_length(carrier, a1, a2, lt)
        delta = table_offset(carrier, a1, a2)
        tdir = relative_direction(carrier, a1, a2, initial_direction(cur_plane))
        state.update(
            active=carrier.number,
            word=word.value,
            plane=cur_plane.value,
            kinematic_type=carrier.kinematic_type.value,
            angles_deg=[a1, a2],
            p_tcang=[_nan_none(x) for x in selection.p_tcang],
            p_tcang0=selection.tcang0,
            p_tcsol=selection.tcsol,
            tool_vector=_vec(res),
            tool_direction=_vec(tdir),
            table_offset=_vec(delta),
        )
        state["activations"].append(
            {
                "line": span.line,
                "block": span.block,
                "holder": carrier.number,
                "word": word.value,
                "plane": cur_plane.value,
                "angles_deg": [a1, a2],
                "p_tcang": [_nan_none(x) for x in selection.p_tcang],
                "tool_vector": _vec(res),
                "table_offset": _vec(delta),
                "reasons": list(selection.reasons),
            }
        )

    for ev in _block_order(events):
        span = SourceSpan(
            file=file,
            line=int(ev.get("line", 0) or 0),
            column=int(ev.get("column", 0) or 0),
            block=ev.get("block"),
        )
        w = str(ev.get("word", "")).upper()
        value = ev.get("value")
        try:
            if w == "TCARR":
                m = int(value or 0)
                if m == 0:
                    carrier, selection = None, None
                    state.update(
                        active=0,
                        kinematic_type=None,
                        angles_deg=None,
                        p_tcang=None,
                        p_tcang0=None,
                        p_tcsol=None,
                        tool_vector=None,
                        tool_direction=None,
                        table_offset=None,
                    )
                    continue
                if m not in carriers:
                    raise AlarmError(
                        Diagnostic(
                            Severity.ERROR,
                            Code.TH_UNKNOWN_HOLDER,
                            f"toolholder {m} selected by TCARR={m} has no $TC_CARR data",
                            span,
                        )
                    )
                carrier = carrier_from_assignments(carriers[m], m, span)
                if m not in warned:
                    diags.extend(carrier.warnings())
                    warned.add(m)
                publish(span, True)
            elif w in _GROUP42:
                word = parse_enum(OrientationWord, w)
                if carrier is not None:
                    publish(span, True)
            elif w in ("G17", "G18", "G19"):
                cur_plane = Plane.parse(w)
                state["plane"] = cur_plane.value
                if carrier is not None:
                    publish(span, False)
            elif w in ("ROT", "AROT"):
                rot = np.eye(3) if value is None else rpy_matrix(*[float(x) for x in value])
                frame = rot if w == "ROT" else frame @ rot
            else:
                diags.append(
                    Diagnostic(
                        Severity.WARNING,
                        Code.TH_UNKNOWN_WORD,
                        f"toolholder evaluation ignores word {w!r}",
                        span,
                    )
                )
        except AlarmError as exc:
            diags.append(exc.diagnostic)
            break
    return state, diags


def _block_order(events: Sequence[Mapping[str, Any]]) -> list[Mapping[str, Any]]:
    """Within one block (same line) the words act together: apply plane, frame and group-42 words
    before ``TCARR`` so that ``TCARR=1 TCOFR`` selects the holder once, in the block's mode."""
    out: list[Mapping[str, Any]] = []
    i = 0
    while i < len(events):
        j = i
        while j < len(events) and events[j].get("line") == events[i].get("line"):
            j += 1
        group = list(events[i:j])
        if events[i].get("line") is None:
            out.extend(group)
        else:
            out.extend(sorted(group, key=lambda e: str(e.get("word", "")).upper() == "TCARR"))
        i = j
    return out


# ------------------------------------------------------------------------------------------------
# a small scanner for SINUMERIK text
# ------------------------------------------------------------------------------------------------

_ASSIGN = re.compile(
    r"\$TC_CARR(\d+)\s*\[\s*(\d+)\s*\]\s*=\s*"
    r"(\"[^\"]*\"|'[^']*'|[-+]?(?:\d+\.?\d*|\.\d+)(?:[eE][-+]?\d+)?|[A-Za-z_]\w*)",
    re.IGNORECASE,
)
_TCARR = re.compile(r"\bTCARR\s*=\s*(\d+)", re.IGNORECASE)
_WORD = re.compile(r"\b(TCOABS|TCOFR[XYZ]?|G1[789])\b", re.IGNORECASE)
_ROT = re.compile(r"\b(A?ROT)\b((?:\s*[XYZ]\s*=?\s*[-+]?(?:\d+\.?\d*|\.\d+))*)", re.IGNORECASE)
_ROT_ARG = re.compile(r"([XYZ])\s*=?\s*([-+]?(?:\d+\.?\d*|\.\d+))", re.IGNORECASE)
_BLOCK = re.compile(r"^\s*/?\s*(N\d+)", re.IGNORECASE)


def _value(text: str) -> float | str:
    if text[:1] in "\"'":
        return text[1:-1]
    try:
        return float(text)
    except ValueError:
        return text


def scan_program(
    text: str, file: str = "<program>"
) -> tuple[dict[int, dict[int, float | str]], list[dict[str, Any]]]:
    """Collect ``$TC_CARRn[m]=value`` assignments and the holder words of a SINUMERIK program.

    Comments (``;`` to end of line) are skipped. ``$TC_CARR1[0]=0`` clears all blocks. Words
    found: ``TCARR=m``, ``TCOABS``, ``TCOFR``/``TCOFRZ``/``TCOFRY``/``TCOFRX``, ``G17``–``G19``
    and ``ROT``/``AROT`` with ``X``/``Y``/``Z`` angles.

    Returns
    -------
    (carriers, events)
        In the shapes :func:`evaluate_toolholder` takes.
    """
    carriers: dict[int, dict[int, float | str]] = {}
    events: list[dict[str, Any]] = []
    for lineno, raw in enumerate(text.splitlines(), start=1):
        line = raw.split(";", 1)[0]
        bm = _BLOCK.match(line)
        block = bm.group(1).upper() if bm else None
        found: list[tuple[int, dict[str, Any]]] = []
        for am in _ASSIGN.finditer(line):
            n, m, val = int(am.group(1)), int(am.group(2)), _value(am.group(3))
            if n == 1 and m == 0:
                carriers.clear()
            else:
                carriers.setdefault(m, {})[n] = val
        for tm in _TCARR.finditer(line):
            found.append((tm.start(), {"word": "TCARR", "value": int(tm.group(1))}))
        for wm in _WORD.finditer(line):
            found.append((wm.start(), {"word": wm.group(1).upper(), "value": None}))
        for rm in _ROT.finditer(line):
            args = {k.upper(): float(v) for k, v in _ROT_ARG.findall(rm.group(2))}
            angles = [args.get("X", 0.0), args.get("Y", 0.0), args.get("Z", 0.0)] if args else None
            found.append((rm.start(), {"word": rm.group(1).upper(), "value": angles}))
        for col, ev in sorted(found, key=lambda t: t[0]):
            events.append({"line": lineno, "block": block, "column": col + 1, **ev})
    return carriers, events
