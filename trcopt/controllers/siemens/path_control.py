"""SINUMERIK path control: exact stop (G60, G9), continuous path (G64) and rounding (G641–G645,
ADIS, ADISPOS, CTOL, CYCLE832), as the reader tracks them.

:class:`PathControlState` holds the modal words of G group 10 and the rounding settings while a
program is read; :meth:`PathControlState.control` gives the
:class:`~trcopt.nc.model.PathControl` at the end of a block. What each word means, with the
manual pages it was taken from, is in ``docs/continuous_path.md``:

* ``G60`` (modal) and ``G9`` (this block): exact stop at the block end;
* ``G64``: continuous path without rounding: the speed falls at each corner until the axis velocity
  jump is within a·(MD32310 − 1)·IPO cycle, a few mm/s — planned as a stop at every tangent
  discontinuity, as without a mode;
* ``G641``: rounding by distance, the transition starts ``ADIS`` (``ADISPOS`` for G0) before the
  corner and ends as far after it; ``ADIS=0`` (the default) is G64;
* ``G642``/``G645`` (and ``G643``/``G644`` with a warning): rounding within the contour
  tolerance ``CTOL`` (else the machine's default, :data:`DEFAULT_CONTOUR_TOL_MM`);
* ``CYCLE832(_TOL, _TOLM, …)``: ``_TOL > 0`` selects G642 with ``CTOL = _TOL``; ``_TOL = 0`` or
  ``_TOLM = 0`` (``_OFF``) deselects it (exact stop G60, the machine's usual reset value).
"""

from __future__ import annotations

from trcopt.codes import Code
from trcopt.errors import Diagnostic, Severity, SourceSpan
from trcopt.modes import PathMode, ToleranceKind
from trcopt.nc.model import EXACT_PATH, MoveKind, PathControl

__all__ = ["DEFAULT_CONTOUR_TOL_MM", "PATH_CONTROL_G", "PathControlState", "cycle832_arguments"]

#: Contour tolerance of G642/G645 when the program sets none (SD42465 $SC_SMOOTH_CONTUR_TOL), mm.
DEFAULT_CONTOUR_TOL_MM = 0.05
#: The G codes of group 10 (exact stop / continuous path).
PATH_CONTROL_G = (60, 64, 641, 642, 643, 644, 645)
#: CYCLE832 machining types (``_TOLM``) by name, as the cycle's predefined constants read.
_CYCLE832_TYPES = {
    "_OFF": 0, "_FINISH": 1, "_SEMIFIN": 2, "_ROUGH": 3, "_ORI_FINISH": 1, "_ORI_SEMIFIN": 2, "_ORI_ROUGH": 3,
}  # fmt: skip


def cycle832_arguments(text: str) -> tuple[float, int]:
    """``(_TOL mm-or-inch, _TOLM)`` from the argument text of ``CYCLE832(…)``; empty arguments
    are 0 (``CYCLE832()`` deselects). Raises :class:`ValueError` for an argument that is not a
    number or a machining-type constant."""
    parts = [p.strip() for p in text.split(",")] if text.strip() else []
    tol = float(parts[0]) if parts and parts[0] else 0.0
    tolm = 1 if tol > 0 else 0  # the cycle's default machining type: finishing
    if len(parts) > 1 and parts[1]:
        name = parts[1].upper()
        tolm = _CYCLE832_TYPES[name] if name in _CYCLE832_TYPES else int(float(name))
    if tol < 0:
        raise ValueError(f"negative tolerance {tol:g}")
    return tol, tolm


class PathControlState:
    """Modal path-control words of one program read (see the module description)."""

    __slots__ = ("group", "adis", "adispos", "ctol", "word", "_warned")

    def __init__(self) -> None:
        self.group = 0  # 0: nothing programmed (trcopt's exact path); else 60, 64, 641, …
        self.adis = 0.0  # mm
        self.adispos = 0.0  # mm
        self.ctol: float | None = None  # mm; None: the machine's default
        self.word = ""
        self._warned: set[str] = set()

    def select(self, g: int, text: str) -> None:
        """A G word of group 10."""
        self.group, self.word = g, text.upper()

    def cycle832(self, tol_mm: float, tolm: int, text: str) -> None:
        """``CYCLE832``: G642 within ``tol_mm`` (mm), or deselection (G60)."""
        if tol_mm > 0.0 and tolm != 0:
            self.group, self.ctol, self.word = 642, tol_mm, text
        else:
            self.group, self.ctol, self.word = 60, None, text

    def control(self, kind: MoveKind, exact_stop: bool, span: SourceSpan, diagnostics: list[Diagnostic]) -> PathControl:
        """The path control at the end of a block of ``kind`` (``exact_stop``: G9 in the block)."""
        g = self.group
        if exact_stop:
            return PathControl(PathMode.EXACT_STOP, word="G9")
        if g == 0:
            return EXACT_PATH
        if g == 60:
            return PathControl(PathMode.EXACT_STOP, word=self.word)
        if g == 641:
            adis = self.adispos if kind is MoveKind.RAPID else self.adis
            if adis > 0.0:
                name = "ADISPOS" if kind is MoveKind.RAPID else "ADIS"
                return PathControl(PathMode.BLEND, adis, ToleranceKind.DISTANCE, f"G641 {name}={adis:g}")
            g = 64  # ADIS=0: continuous path without rounding
        if g == 64:
            # no rounding; the speed falls at a corner until the axis velocity jump is at most
            # a·(MD32310 − 1)·IPO cycle (a few mm/s): modelled as the stop at a tangent
            # discontinuity of the exact path (docs/continuous_path.md)
            return PathControl(PathMode.EXACT_PATH, word=self.word or "G64")
        if g in (643, 644):
            self._warn(
                f"G{g}",
                f"G{g} is planned as G642: rounding within the contour tolerance "
                f"{self._ctol():g} mm (its axis-specific rules are not modelled)",
                span,
                diagnostics,
            )
        tol = self._ctol()
        word = self.word if self.word.startswith("CYCLE832") else f"G{g} CTOL={tol:g}"
        return PathControl(PathMode.BLEND, tol, ToleranceKind.CONTOUR, word)

    def _ctol(self) -> float:
        return DEFAULT_CONTOUR_TOL_MM if self.ctol is None else self.ctol

    def _warn(self, key: str, message: str, span: SourceSpan, diagnostics: list[Diagnostic]) -> None:
        """One warning per word and program (at its first block)."""
        if key not in self._warned:
            self._warned.add(key)
            diagnostics.append(Diagnostic(Severity.WARNING, Code.NC_PATH_CONTROL, message, span))
