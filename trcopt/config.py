"""Settings as frozen dataclasses: compensation machine data, tolerances, machine limits.

The TRC machine data follow spec §0.5 of ``sinumerik_trc.md`` (with its errata: MD20240 default 3).
``Machine`` is the kinematic description used by the timing stage: per-axis limits and optional
vector (path) limits on the tool-centre motion (:class:`PathLimits`). It loads from the TOML format
of design.md §3.1b (``docs/machine.md``) and falls back to :data:`DEFAULT_MACHINE` for missing axes.
"""

from __future__ import annotations

import math
import os
from dataclasses import dataclass, field, fields, replace
from pathlib import Path
from typing import Any

from trcopt.errors import ConfigError
from trcopt.modes import FeedReference, parse_enum

__all__ = [
    "Tolerances",
    "TrcSettings",
    "AxisLimits",
    "PathLimits",
    "Machine",
    "DEFAULT_MACHINE",
    "load_machine",
    "machine_from_dict",
    "read_toml",
    "file_beside",
]


def read_toml(path: str | Path, what: str) -> dict[str, Any]:
    """The table of the TOML file ``path``; ``what`` names the file's kind in errors ("tool table",
    "machine file", …). Unreadable, non-UTF-8 or invalid TOML: :class:`ConfigError` naming the file."""
    import tomllib  # here: a run that reads no TOML file does not load the parser

    p = Path(path)
    try:
        return tomllib.loads(p.read_text(encoding="utf-8"))
    except OSError as exc:
        raise ConfigError(f"cannot read {what} {p}: {exc.strerror}") from None
    except UnicodeDecodeError as exc:
        raise ConfigError(f"{p}: not a text file (a {what} is UTF-8 TOML): byte {exc.start}") from None
    except tomllib.TOMLDecodeError as exc:
        raise ConfigError(f"{p}: invalid TOML: {exc}") from None


def file_beside(program: str, suffix: str, shared: str) -> Path | None:
    """The settings file that belongs to a program file: ``<stem><suffix>`` beside it, else
    ``shared`` in its folder; None when there is none (or the program is not a file)."""
    p = Path(program)
    if not p.name or not os.path.exists(p):  # os.path: False for a name the system refuses
        return None
    for cand in (p.with_name(p.stem + suffix), p.with_name(shared)):
        if os.path.isfile(cand):
            return cand
    return None


@dataclass(frozen=True, slots=True)
class Tolerances:
    """Named geometric tolerances.

    Parameters
    ----------
    coincidence_mm:
        Two points closer than this are the same point (default 1 µm). Also the gap below which a
        junction counts as tangential (R·|δ| small).
    relative:
        Relative tolerance of geometric predicates (1e-9).
    arc_end_radius_mm:
        Largest accepted difference between an arc's start and end radius (controllers: 0.002 mm).
    """

    coincidence_mm: float = 1e-3
    relative: float = 1e-9
    arc_end_radius_mm: float = 0.002


@dataclass(frozen=True, slots=True)
class TrcSettings:
    """SINUMERIK machine data that govern 2D tool radius compensation (spec §0.5).

    Angles in degrees as the machine data are written.
    """

    cutcom_corner_limit_deg: float = 100.0  # MD20210
    cutcom_max_disc: int = 50  # MD20220
    cutcom_curve_insert_limit_deg: float = 10.0  # MD20230
    cutcom_maxnum_check_blocks: int = 3  # MD20240 (errata: default 3)
    cutcom_maxnum_dummy_blocks: int = 3  # MD20250
    wab_maxnum_dummy_blocks: int = 5  # MD20202
    wab_clearance_tolerance_mm: float = 0.01  # MD20204
    suppress_10763: bool = False  # MD11410 bit 1
    strict: bool = False  # raise 10751 on reversed elements under CDOF (spec R28, §D-11)
    tolerances: Tolerances = field(default_factory=Tolerances)

    @property
    def corner_limit_rad(self) -> float:
        return math.radians(self.cutcom_corner_limit_deg)

    @property
    def curve_insert_limit_rad(self) -> float:
        return math.radians(self.cutcom_curve_insert_limit_deg)

    def with_(self, **changes: Any) -> TrcSettings:
        return replace(self, **changes)


@dataclass(frozen=True, slots=True)
class AxisLimits:
    """Kinematic limits of one axis: velocity (mm/s), acceleration (mm/s²), optional jerk (mm/s³)."""

    vmax_mm_s: float
    amax_mm_s2: float
    jmax_mm_s3: float | None = None

    def __post_init__(self) -> None:
        for name in ("vmax_mm_s", "amax_mm_s2"):
            value = getattr(self, name)
            if not (isinstance(value, int | float) and math.isfinite(value) and value > 0):
                raise ConfigError(f"axis limit {name} must be a positive number, got {value!r}")
        if self.jmax_mm_s3 is not None and not (
            math.isfinite(self.jmax_mm_s3) and self.jmax_mm_s3 > 0
        ):
            raise ConfigError(f"axis limit jmax_mm_s3 must be positive, got {self.jmax_mm_s3!r}")


def _positive_limit(value: Any) -> bool:
    """True for a positive finite int or float (bool is not a number here)."""
    return isinstance(value, int | float) and not isinstance(value, bool) and math.isfinite(value) and value > 0


@dataclass(frozen=True, slots=True)
class PathLimits:
    """Vector limits on the tool-centre motion (the ``[path]`` table of a machine file).

    Each limit is optional (None: not limited); all that are given hold together with the per-axis
    limits.

    Parameters
    ----------
    vmax_mm_s:
        Largest tool-centre path speed ``|v|``, mm/s.
    amax_mm_s2:
        Largest norm of the acceleration vector ``|a|`` (tangential and centripetal together), mm/s².
    jmax_mm_s3:
        Largest norm of the jerk vector ``|j|``, mm/s³ (the jerk-limited feed only).

    Raises
    ------
    ConfigError
        A limit that is given is not a positive finite number.
    """

    vmax_mm_s: float | None = None
    amax_mm_s2: float | None = None
    jmax_mm_s3: float | None = None

    def __post_init__(self) -> None:
        for f in fields(self):
            value = getattr(self, f.name)
            if value is not None and not _positive_limit(value):
                raise ConfigError(f"path limit {f.name} must be a positive finite number, got {value!r}")
            if value is not None:
                object.__setattr__(self, f.name, float(value))

    @property
    def given(self) -> bool:
        """True when at least one vector limit is set."""
        return self.vmax_mm_s is not None or self.amax_mm_s2 is not None or self.jmax_mm_s3 is not None

    def to_json(self) -> dict[str, float | None]:
        """The three limits by key (None where not given)."""
        return {"vmax_mm_s": self.vmax_mm_s, "amax_mm_s2": self.amax_mm_s2, "jmax_mm_s3": self.jmax_mm_s3}


@dataclass(frozen=True, slots=True)
class Machine:
    """A machine: name, rapid feed (mm/min), per-axis limits for X, Y, Z and vector limits.

    ``feed_reference`` says whether the programmed feed applies to the contour
    (``FeedReference.CONTOUR``, SINUMERIK's CFC-like reading) or to the tool centre
    (``FeedReference.CENTRE``, CFTCP, the default). ``path`` holds the optional vector limits on
    the tool-centre motion (:class:`PathLimits`; None is read as no vector limit).
    """

    name: str = "trcopt default 3-axis mill"
    rapid_mm_min: float = 20000.0
    axes: tuple[tuple[str, AxisLimits], ...] = (
        ("X", AxisLimits(250.0, 2000.0, 50000.0)),
        ("Y", AxisLimits(250.0, 2000.0, 50000.0)),
        ("Z", AxisLimits(100.0, 1000.0, 20000.0)),
    )
    feed_reference: FeedReference = FeedReference.CENTRE
    path: PathLimits = PathLimits()

    def __post_init__(self) -> None:
        # a string is accepted here, at the boundary, and becomes the mode
        object.__setattr__(self, "feed_reference", parse_enum(FeedReference, self.feed_reference, "feed_reference"))
        if self.path is None:
            object.__setattr__(self, "path", PathLimits())
        elif not isinstance(self.path, PathLimits):
            raise ConfigError(f"machine path limits must be a PathLimits, got {type(self.path).__name__}")

    def axis(self, name: str) -> AxisLimits:
        for key, limits in self.axes:
            if key == name:
                return limits
        raise ConfigError(f"machine {self.name!r} has no axis {name!r}")

    @property
    def rapid_mm_s(self) -> float:
        return self.rapid_mm_min / 60.0

    def to_json(self) -> dict[str, Any]:
        """The machine as the plan JSON describes it; ``path`` only when a vector limit is given."""
        out: dict[str, Any] = {
            "name": self.name,
            "rapid_mm_min": self.rapid_mm_min,
            "feed_reference": self.feed_reference.value,
            "axes": {
                k: {"vmax_mm_s": a.vmax_mm_s, "amax_mm_s2": a.amax_mm_s2, "jmax_mm_s3": a.jmax_mm_s3}
                for k, a in self.axes
            },
        }
        if self.path.given:
            out["path"] = self.path.to_json()
        return out


DEFAULT_MACHINE = Machine()

_MACHINE_KEYS = {"name", "rapid_mm_min", "axes", "feed_reference", "path"}
_AXIS_KEYS = {f.name for f in fields(AxisLimits)}
_PATH_KEYS = tuple(f.name for f in fields(PathLimits))


def _path_from_table(raw: Any, source: str) -> PathLimits:
    """The ``[path]`` table: each key optional, a positive finite number; unknown keys are errors."""
    if not isinstance(raw, dict):
        raise ConfigError(f"{source}: 'path' must be a table")
    bad = set(raw) - set(_PATH_KEYS)
    if bad:
        raise ConfigError(f"{source}: unknown key path.{sorted(bad)[0]} (valid: {', '.join(_PATH_KEYS)})")
    for key in _PATH_KEYS:
        if key in raw and not _positive_limit(raw[key]):
            raise ConfigError(f"{source}: path.{key} must be a positive finite number, got {raw[key]!r}")
    return PathLimits(**{k: float(raw[k]) for k in _PATH_KEYS if k in raw})


def machine_from_dict(data: dict[str, Any], source: str = "<machine>") -> Machine:
    """Build a :class:`Machine` from a parsed TOML table; unknown keys are errors naming the key.

    The optional ``path`` table gives the vector limits (:class:`PathLimits`); the default machine
    has none.
    """
    unknown = set(data) - _MACHINE_KEYS
    if unknown:
        raise ConfigError(f"{source}: unknown machine key {sorted(unknown)[0]!r}")
    base = DEFAULT_MACHINE
    axes = dict(base.axes)
    raw_axes = data.get("axes", {})
    if not isinstance(raw_axes, dict):
        raise ConfigError(f"{source}: 'axes' must be a table")
    for name, table in raw_axes.items():
        if name not in ("X", "Y", "Z"):
            raise ConfigError(f"{source}: unknown axis {name!r} (valid: X, Y, Z)")
        if not isinstance(table, dict):
            raise ConfigError(f"{source}: axes.{name} must be a table")
        bad = set(table) - _AXIS_KEYS
        if bad:
            raise ConfigError(f"{source}: unknown key axes.{name}.{sorted(bad)[0]}")
        for key, value in table.items():
            if not _positive_limit(value):
                raise ConfigError(f"{source}: axes.{name}.{key} must be a positive finite number, got {value!r}")
        try:
            axes[name] = AxisLimits(
                float(table["vmax_mm_s"]),
                float(table["amax_mm_s2"]),
                None if table.get("jmax_mm_s3") is None else float(table["jmax_mm_s3"]),
            )
        except KeyError as exc:
            raise ConfigError(f"{source}: axes.{name} needs {exc.args[0]}") from None
        except (TypeError, ValueError) as exc:
            raise ConfigError(f"{source}: axes.{name}: {exc}") from None
    try:
        feed_reference = parse_enum(FeedReference, data.get("feed_reference", base.feed_reference), "feed_reference")
    except ValueError as exc:
        raise ConfigError(f"{source}: {exc}") from None
    rapid = data.get("rapid_mm_min", base.rapid_mm_min)
    if not _positive_limit(rapid):
        raise ConfigError(f"{source}: rapid_mm_min must be a positive finite number, got {rapid!r}")
    path = _path_from_table(data["path"], source) if "path" in data else base.path
    return Machine(
        name=str(data.get("name", base.name)),
        rapid_mm_min=float(rapid),
        axes=tuple((k, axes[k]) for k in ("X", "Y", "Z")),
        feed_reference=feed_reference,
        path=path,
    )


def load_machine(path: str | Path) -> Machine:
    """Load a machine TOML file (design.md §3.1b)."""
    return machine_from_dict(read_toml(path, "machine file"), str(path))
