"""Where a SINUMERIK block goes: end point and circle of a block in the frames of
:mod:`trcopt.controllers.siemens.frames`, polar coordinates, ``CIP`` and ``CT``.

* The axis words of a block are in the WCS; the end point and centre are computed there and mapped
  into the plan's coordinates (the reference settable zero system) by the programmable frame (and
  the difference of two settable zero offsets). Unprogrammed axes keep their physical position
  (the WCS value of the current position under the frame in force). A frame must keep the working
  plane (a rotation about its applicate only) and, for a circle, scale it uniformly; a frame that
  mirrors the plane turns G2 into G3 (and the compensation side, :mod:`.reader`).
* ``G110``/``G111``/``G112`` set the pole relative to the last programmed point, to the WCS
  origin, or to the last pole (with the plane axes or with ``AP=``/``RP=``); the pole starts at the
  WCS origin. ``AP=`` (degrees from the plane's first axis, counter-clockwise) and ``RP=`` are modal;
  ``G2``/``G3`` with them is a circle about the pole.
* ``CIP`` with ``I1=``/``J1=``/``K1=``: the circle through the intermediate point (absolute under G90,
  ``=AC``; relative to the start under G91, ``=IC``), in a plane parallel to the working plane.
* ``CT``: the circle tangent to the preceding motion at its end.
* ``G53``/``G153``/``SUPA``: the block's axis values are machine positions,
  ``P = S_ref⁻¹(P_mcs)`` with ``S_ref`` the settable frame of the reference (its translation, and
  its rotation about Z and scale when the zero-offset file gives them); without a zero-offset
  file it is an error. A change of settable zero offset maps ``P = S_ref⁻¹(S_active(F(P_wcs)))``.
"""

from __future__ import annotations

import dataclasses
import math

from trcopt.codes import Code
from trcopt.controllers.siemens.block import Block
from trcopt.controllers.siemens.frames import (
    IDENTITY,
    Frame,
    ZeroOffsets,
    mirroring,
    rotation,
    scaling,
    translation,
)
from trcopt.controllers.siemens.path_control import PathControlState
from trcopt.errors import SourceSpan
from trcopt.nc.modal import ModalState, fail
from trcopt.nc.model import Move, MoveKind

__all__ = ["MotionGeometry", "CIP", "CT"]

CIP, CT = -1, -2  # motion codes of CIP and CT beside G0…G3
_ARC, _NONE = MoveKind.ARC, MoveKind.NONE
Vec = tuple[float, float, float]


class MotionGeometry:
    """The geometry part of :class:`~trcopt.controllers.siemens.reader.SiemensReader`."""

    file: str
    state: ModalState
    moves: list[Move]
    last_motion: Move | None
    frame: Frame
    settable: int
    reference: int | None
    zero: ZeroOffsets | None
    zero_source: str
    circle: int
    arc_ccw: bool
    pole: tuple[float, float]
    polar: list[float]
    geom_scale: float
    feed_scale: float
    absolute: bool
    path: PathControlState
    _plane_uv: tuple[int, int]

    # ------------------------------------------------------------------ frames
    def _effective(self, span: SourceSpan) -> Frame:
        """The map WCS → plan coordinates of this block."""
        if self.reference is None or self.settable == self.reference:
            return self.frame
        active = self._offset(self.settable, span)
        ref = self._offset(self.reference, span)
        # WCS → (programmable frame) → active SZS → (settable frame) → MCS → reference SZS
        frame = ref.inverse().then(active).then(self.frame)
        return IDENTITY if frame == IDENTITY else frame

    def _offset(self, g: int, span: SourceSpan) -> Frame:
        value = None if self.zero is None else self.zero.get(g)
        if value is None:
            where = self.zero_source if self.zero is None else f"G{g} is not in {self.zero.source}"
            raise fail(
                Code.NC_FRAME,
                f"the settable zero offset G{g} is needed here (G{self.reference} is the plan's reference, "
                f"machine coordinates or a change of zero offset after the first motion): {where}",
                span,
            )
        return value

    def _frame_block(self, words: list, span: SourceSpan) -> None:
        """A frame instruction with its axis values (alone in its block)."""
        head = words[0]
        name = head.name
        at = self._at(span, head)  # type: ignore[attr-defined]
        if head.value is not None:
            raise fail(Code.NC_SYNTAX, f"{name} takes its values from the axis words after it", at)
        values: dict[str, float] = {}
        for w in words[1:]:
            if w.name in ("X", "Y", "Z") or (w.name == "RPL" and name in ("ROT", "AROT")):
                if w.name in values:
                    raise fail(Code.NC_SYNTAX, f"{w.name} twice in a {name} block", self._at(span, w))  # type: ignore[attr-defined]
                values[w.name] = self._number(w, span)  # type: ignore[attr-defined]
            else:
                raise fail(Code.NC_SYNTAX, f"{w.text}: a frame instruction {name} must be alone in its block "
                           "with its axis values", self._at(span, w))  # type: ignore[attr-defined]  # fmt: skip
        base = name[1:] if name.startswith("A") else name
        if base == "TRANS":
            k = self.geom_scale
            part = translation(tuple(values.get(a, 0.0) * k for a in "XYZ"))  # type: ignore[arg-type]
        elif base == "ROT":
            if "RPL" in values and len(values) > 1:
                raise fail(Code.NC_SYNTAX, f"{name}: RPL= together with axis angles", at)
            if "RPL" in values:
                part = rotation(self.state.plane.axes[2], values["RPL"])
            else:
                part = (
                    rotation(2, values.get("Z", 0.0))
                    .then(rotation(1, values.get("Y", 0.0)))
                    .then(rotation(0, values.get("X", 0.0)))
                )
        elif base == "SCALE":
            for a, f in values.items():
                if f == 0.0:
                    raise fail(Code.NC_FRAME, f"{name} {a}0: a scale factor 0 makes the plane degenerate", at)
            part = scaling(tuple(values.get(a, 1.0) for a in "XYZ"))  # type: ignore[arg-type]
        else:  # MIRROR
            part = mirroring(tuple(a in values for a in "XYZ"))  # type: ignore[arg-type]
        frame = part if name == base else self.frame.then(part)
        self.frame = IDENTITY if frame == IDENTITY else frame

    def _settable(self, g: int, text: str, actions: list[str]) -> None:
        self.settable = g
        if self.reference is None or g == self.reference:
            actions.append(text.upper())  # the output is in this zero system: the word stays

    # ------------------------------------------------------------------ the block's geometry
    def _geometry(self, b: Block, span: SourceSpan) -> tuple[MoveKind, Vec, Vec | None, bool | None, bool, SourceSpan]:
        """``(kind, end, centre, ccw, plane_programmed, span)`` of the block, in plan coordinates."""
        st = self.state
        pos = st.position
        plane = st.plane
        u, v, w = plane.axes
        axes = b.axes
        motion = st.motion
        if b.machine:
            return self._machine(b, span)
        if axes == [None, None, None] and b.centre_col == 0 and b.ap is None and b.rp is None and b.pole is None:
            return _NONE, pos, None, None, False, span  # nothing to go to (the frames are not needed)
        frame = self._effective(span)
        start = pos if frame is IDENTITY else frame.invert(pos)
        end = list(start)
        any_axis = False
        for i in (0, 1, 2):
            a = axes[i]
            if a is not None:
                any_axis = True
                end[i] = a[0] if a[1] else start[i] + a[0]
        if b.pole is not None:
            self._set_pole(b, start, end, span)
            return _NONE, pos, None, None, False, span
        polar = b.ap is not None or b.rp is not None
        if polar:
            any_axis = True
            for k, value in ((0, b.ap), (1, b.rp)):
                if value is not None:
                    self.polar[k] = value[0] if value[1] else self.polar[k] + value[0]
            ap, rp = self.polar
            c, s = math.cos(math.radians(ap)), math.sin(math.radians(ap))
            end[u], end[v] = self.pole[0] + rp * c, self.pole[1] + rp * s
        plane_programmed = axes[u] is not None or axes[v] is not None or polar
        has_centre = b.centre_col != 0
        center: Vec | None = None
        ccw: bool | None = None
        kind = _NONE
        circle = self.circle
        if motion is _ARC and (any_axis or has_centre):
            kind = _ARC
            if circle == CIP:
                center, ccw = self._cip(b, start, tuple(end), span)  # type: ignore[arg-type]
            elif circle == CT:
                ccw = None
            elif polar and not has_centre:
                ccw = self.arc_ccw
                center = plane.to_xyz((self.pole[0], self.pole[1], start[w]))
            else:
                ccw = self.arc_ccw
                center = self._arc_centre(b, start, tuple(end), ccw, span)  # type: ignore[attr-defined]
        elif any_axis:
            kind = motion
            if has_centre:
                self._warn(Code.NC_UNSUPPORTED_WORD, "circle centre/radius outside G2/G3 ignored",  # type: ignore[attr-defined]
                           SourceSpan(self.file, span.line, b.centre_col, span.block))  # fmt: skip
        if kind is _NONE:
            return _NONE, pos, None, None, plane_programmed, span
        if self.reference is None:
            self.reference = self.settable
        end_t: Vec = (end[0], end[1], end[2])
        if frame is not IDENTITY:
            problem = frame.plane_problem(plane, kind is _ARC)
            if problem is not None:
                raise fail(Code.NC_FRAME, f"{problem}: not modelled by trcopt", span)
            end_t = frame.apply(end_t)
            if center is not None:
                center = frame.apply(center)
            if ccw is not None and frame.mirrored(plane):
                ccw = not ccw
        if kind is _ARC and circle == CT:
            center, ccw = self._ct(pos, end_t, span)
        return kind, end_t, center, ccw, plane_programmed, span

    def _machine(self, b: Block, span: SourceSpan) -> tuple[MoveKind, Vec, Vec | None, bool | None, bool, SourceSpan]:
        st = self.state
        if st.motion is _ARC:
            raise fail(Code.NC_UNSUPPORTED, "a circle in machine coordinates (G53/G153/SUPA) is not modelled", span)
        if b.ap is not None or b.rp is not None or b.pole is not None:
            raise fail(Code.NC_UNSUPPORTED, "polar coordinates in machine coordinates (G53/G153/SUPA)", span)
        if self.reference is None:
            self.reference = self.settable
        ref = self._offset(self.reference, span)
        pos = st.position
        here = ref.apply(pos)  # the machine position now
        goal = list(here)
        machine: list[float | None] = [None, None, None]
        for i in (0, 1, 2):
            a = b.axes[i]
            if a is not None:
                goal[i] = a[0] if a[1] else here[i] + a[0]
                machine[i] = goal[i]
        if not any(m is not None for m in machine):
            return _NONE, pos, None, None, False, span
        if ref.m == IDENTITY.m:  # a translation: the unprogrammed axes stay exactly where they are
            end = [goal[i] - ref.t[i] if machine[i] is not None else pos[i] for i in (0, 1, 2)]
        else:
            end = list(ref.invert((goal[0], goal[1], goal[2])))
        u, v, _ = st.plane.axes
        span = dataclasses.replace(span, machine=(machine[0], machine[1], machine[2]))
        return st.motion, (end[0], end[1], end[2]), None, None, b.axes[u] is not None or b.axes[v] is not None, span

    # ------------------------------------------------------------------ polar, CIP, CT
    def _set_pole(self, b: Block, start: Vec, end: list[float], span: SourceSpan) -> None:
        g, col = b.pole  # type: ignore[misc]
        u, v, w = self.state.plane.axes
        if b.axes[w] is not None:
            raise fail(Code.NC_SYNTAX, f"G{g}: the pole lies in the working plane (no applicate)", span)
        ref = {110: (start[u], start[v]), 111: (0.0, 0.0), 112: self.pole}[g]
        if b.ap is not None or b.rp is not None:
            if b.axes[u] is not None or b.axes[v] is not None:
                raise fail(Code.NC_SYNTAX, f"G{g}: the pole either with axes or with AP/RP", span)
            ap = 0.0 if b.ap is None else b.ap[0]
            rp = 0.0 if b.rp is None else b.rp[0]
            self.pole = (ref[0] + rp * math.cos(math.radians(ap)), ref[1] + rp * math.sin(math.radians(ap)))
            return
        pu = b.axes[u]
        pv = b.axes[v]
        # the axis values of the pole block: G111 absolute, G110/G112 relative to their reference
        self.pole = (
            ref[0] if pu is None else (pu[0] if g == 111 else ref[0] + pu[0]),
            ref[1] if pv is None else (pv[0] if g == 111 else ref[1] + pv[0]),
        )

    def _cip(self, b: Block, start: Vec, end: Vec, span: SourceSpan) -> tuple[Vec, bool]:
        plane = self.state.plane
        u, v, w = plane.axes
        inter = b.inter or [None, None, None]
        if inter[u] is None or inter[v] is None:
            raise fail(Code.NC_ARC_CENTRE, "CIP needs the intermediate point in both plane axes (I1=, J1=, K1=)", span)
        mid = [s if p is None else (p[0] if p[1] else s + p[0]) for s, p in zip(start, inter, strict=True)]
        if abs(mid[w] - start[w]) > 1e-9 or abs(end[w] - start[w]) > 1e-9:
            raise fail(Code.NC_UNSUPPORTED, "CIP: a circle not parallel to the working plane is not modelled", span)
        ax, ay = start[u], start[v]
        bx, by = mid[u], mid[v]
        cx, cy = end[u], end[v]
        d = 2.0 * (ax * (by - cy) + bx * (cy - ay) + cx * (ay - by))
        if abs(d) < 1e-12:
            raise fail(Code.NC_ARC_CENTRE, "CIP: start, intermediate and end point lie on one line", span)
        a2, b2, c2 = ax * ax + ay * ay, bx * bx + by * by, cx * cx + cy * cy
        ou = (a2 * (by - cy) + b2 * (cy - ay) + c2 * (ay - by)) / d
        ov = (a2 * (cx - bx) + b2 * (ax - cx) + c2 * (bx - ax)) / d
        ccw = (bx - ax) * (cy - ay) - (by - ay) * (cx - ax) > 0.0
        return plane.to_xyz((ou, ov, start[w])), ccw

    def _ct(self, start: Vec, end: Vec, span: SourceSpan) -> tuple[Vec, bool]:
        plane = self.state.plane
        u, v, w = plane.axes
        prev = self.last_motion
        if prev is None:
            raise fail(Code.NC_ARC_CENTRE, "CT: no preceding motion to be tangent to", span)
        if prev.kind is _ARC and prev.center is not None:
            ru, rv = prev.end[u] - prev.center[u], prev.end[v] - prev.center[v]
            tu, tv = (-rv, ru) if prev.ccw else (rv, -ru)
        else:
            tu, tv = prev.end[u] - prev.start[u], prev.end[v] - prev.start[v]
        norm = math.hypot(tu, tv)
        if norm < 1e-12:
            raise fail(Code.NC_ARC_CENTRE, "CT: the preceding motion has no direction in the working plane", span)
        tu, tv = tu / norm, tv / norm
        du, dv = end[u] - start[u], end[v] - start[v]
        nu, nv = -tv, tu  # left normal
        dn = du * nu + dv * nv
        if abs(dn) < 1e-12:
            raise fail(
                Code.NC_ARC_CENTRE, "CT: the end point lies on the tangent (a straight line, not a circle)", span
            )
        rho = (du * du + dv * dv) / (2.0 * dn)
        return plane.to_xyz((start[u] + rho * nu, start[v] + rho * nv, start[w])), rho > 0.0

    # ------------------------------------------------------------------ SAVE
    def _snapshot(self) -> tuple[object, ...]:
        st = self.state
        p = self.path
        path = (p.group, p.adis, p.adispos, p.ctol, p.word)
        return (self.absolute, st.motion, self.arc_ccw, self.circle, st.plane, self.geom_scale, self.feed_scale,
                self.frame, self.settable, path, self.feed_type)  # type: ignore[attr-defined]  # fmt: skip

    def _restore(self, saved: tuple[object, ...]) -> None:
        st = self.state
        (self.absolute, st.motion, self.arc_ccw, self.circle, st.plane, self.geom_scale, self.feed_scale,
         self.frame, self.settable, path, feed_type) = saved  # type: ignore[assignment]  # fmt: skip
        self._restore_feed_type(feed_type)  # type: ignore[attr-defined]  # G94/G95: F deleted on a change
        self._plane_uv = (st.plane.axes[0], st.plane.axes[1])
        p = self.path
        p.group, p.adis, p.adispos, p.ctol, p.word = path  # type: ignore[misc]
