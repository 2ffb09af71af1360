"""The verification report: per constraint family, the largest residual and where it occurs.

:class:`FamilyResidual` keeps the largest residual of one family and its first segment; values
are added one by one (:meth:`FamilyResidual.add`) or as a whole array in path order
(:meth:`FamilyResidual.add_many`, the same result). :class:`VerificationReport` is the plan
JSON's ``"verification"`` and the diagnostics of a failed family.
"""

from __future__ import annotations

from collections.abc import Sequence
from dataclasses import dataclass, field
from typing import Any

from trcopt.codes import Code
from trcopt.errors import Diagnostic, Severity, SourceSpan
from trcopt.path import Segment

__all__ = ["FAMILIES", "FAMILY_CODES", "INFORMATIONAL", "FamilyResidual", "VerificationReport"]

FAMILIES = ("radius", "tangency", "continuity", "no_reversal", "clearance", "lead_clearance")
INFORMATIONAL = ("lead_clearance",)
_UNITS = {
    "radius": "mm",
    "tangency": "",
    "continuity": "mm",
    "no_reversal": "mm",
    "clearance": "mm",
    "lead_clearance": "mm",
}
FAMILY_CODES = {
    "radius": Code.VERIFY_RADIUS,
    "tangency": Code.VERIFY_TANGENCY,
    "continuity": Code.VERIFY_CONTINUITY,
    "no_reversal": Code.VERIFY_NO_REVERSAL,
    "clearance": Code.VERIFY_CLEARANCE,
}
_FAILURE = {
    "radius": "a compensated tool-centre element is not at the tool radius from its programmed element",
    "tangency": "a joint of the tool-centre path that must be tangent is not (or an offset element runs "
    "against its programmed element)",
    "continuity": "consecutive tool-centre segments do not meet",
    "no_reversal": "the infeed reverses its direction during an approach or retraction",
    "clearance": "the tool comes closer than its radius to the part contour (a gouge)",
}


@dataclass(slots=True)
class FamilyResidual:
    """Largest residual of one constraint family and where it occurs."""

    name: str
    max_residual: float = 0.0
    checks: int = 0
    segment: int | None = None
    block: str | None = None
    line: int | None = None
    span: SourceSpan | None = None  # of the worst segment (for the diagnostic; not in the JSON)

    @property
    def unit(self) -> str:
        return _UNITS[self.name]

    def add(self, value: float, k: int, seg: Segment) -> None:
        self.checks += 1
        if value > self.max_residual or self.segment is None and value >= self.max_residual:
            self.max_residual = float(value)
            self.segment, self.block, self.line, self.span = k, seg.span.block, seg.span.line, seg.span

    def add_many(self, values: Any, ks: Any, segments: Sequence[Segment]) -> None:
        """:meth:`add` of ``values[j]`` at segment ``ks[j]`` (of ``segments``) for j = 0, 1, … in
        turn (NumPy arrays; NaN counts as a check and never as the largest)."""
        import numpy as np

        m = len(values)
        if m == 0:
            return
        self.checks += m
        start = 0
        if self.segment is None:
            first = np.nonzero(values >= self.max_residual)[0]
            if first.size == 0:
                return
            start = int(first[0]) + 1
            self._put(values[start - 1], int(ks[start - 1]), segments)
        rest = values[start:]
        above = rest > self.max_residual
        if above.any():
            j = start + int(np.argmax(rest == rest[above].max()))
            self._put(values[j], int(ks[j]), segments)

    def _put(self, value: float, k: int, segments: Sequence[Segment]) -> None:
        seg = segments[k]
        self.max_residual = float(value)
        self.segment, self.block, self.line, self.span = k, seg.span.block, seg.span.line, seg.span

    def to_json(self) -> dict[str, Any]:
        return {
            "max_residual": self.max_residual,
            "unit": self.unit,
            "checks": self.checks,
            "segment": self.segment,
            "block": self.block,
            "line": self.line,
        }


@dataclass(slots=True)
class VerificationReport:
    """Per-family residuals of a tool-centre path; ``ok`` when all are within ``tolerance``."""

    families: dict[str, FamilyResidual]
    tolerance: float = 1e-6
    seconds: float = 0.0
    notes: list[str] = field(default_factory=list)

    @property
    def ok(self) -> bool:
        """All model families within tolerance (``lead_clearance`` is informational)."""
        return not self.failed

    @property
    def failed(self) -> list[FamilyResidual]:
        return [f for f in self.families.values() if f.max_residual > self.tolerance and f.name not in INFORMATIONAL]

    def max_residual(self, family: str) -> float:
        return self.families[family].max_residual

    def to_json(self) -> dict[str, Any]:
        """The plan JSON key ``"verification"``."""
        return {
            "ok": self.ok,
            "tolerance": self.tolerance,
            "families": {k: f.to_json() for k, f in self.families.items()},
            "notes": list(self.notes),
        }

    def summary_line(self) -> str:
        """One line for the CLI summary."""
        parts = [f"{f.name} {f.max_residual:.1e}" for f in self.families.values()]
        head = "verification: " + ", ".join(parts)
        if self.ok:
            return head + " — ok"
        bad = "; ".join(
            f"{f.name} violated by {f.max_residual:.6g}{' ' + f.unit if f.unit else ''} "
            f"at {f.block or f'line {f.line}'} (segment {f.segment})"
            for f in self.failed
        )
        return head + " — FAILED: " + bad

    def diagnostics(self, *, strict: bool = False) -> list[Diagnostic]:
        """One diagnostic per failed family (``VERIFY-CLEARANCE``, …) at the block and line of its
        worst segment: a warning, or an error when ``strict``."""
        severity = Severity.ERROR if strict else Severity.WARNING
        out = []
        for f in self.failed:
            unit = f" {f.unit}" if f.unit else ""
            out.append(
                Diagnostic(
                    severity,
                    FAMILY_CODES[f.name],
                    f"verification: {_FAILURE[f.name]}: {f.name} residual {f.max_residual:.6g}{unit} "
                    f"(tolerance {self.tolerance:g}) at tool-centre segment {f.segment}",
                    f.span or SourceSpan(),
                )
            )
        return out

    def lead_note(self) -> str | None:
        """A note when a NORM/KONT activation or deselection move or a lead block comes closer
        than R to the part contour (the controller's construction does that when the program's
        start or end point is close to the contour); None otherwise."""
        f = self.families["lead_clearance"]
        if f.max_residual <= self.tolerance:
            return None
        return (
            f"approach/retraction/lead move at {f.block or f'line {f.line}'} (segment {f.segment}) comes "
            f"{f.max_residual:.6g} mm closer than the tool radius to the contour"
        )
