"""A sweep: programs × option sets, read from a TOML or CSV file, expanded into jobs.

TOML (the cross product of every axis)::

    programs = ["../problems/corners/*.mpf", "part.ngc"]   # globs, relative to this file
    outputs = ["json", "gcode", "svg"]                      # optional: each plan's files (json, gcode,
                                                            # svg, html, csv: the feed profile)

    [options]            # the same for every plan
    timing = true

    [axes]               # one value per plan from each list: their cross product
    tolerance = [0.005, 0.01, 0.05]
    corners = ["arc", "optimal"]
    machine = ["default", "machines/slow.toml"]             # relative to this file
    jerk = [false, true]

CSV (one option set per row, no product): a header ``program,<option>,…`` and one row per set;
``program`` may be a glob, an empty cell leaves the option at its default.

The option names are those of ``trcopt plan`` (``-`` or ``_`` alike): ``dialect``, ``profile``
(alias ``controller``), ``machine``, ``timing``, ``verify``, ``strict``, ``tool-table``,
``tool-unit``, ``appr-radius``, ``corners``, ``tolerance``, ``tolerance-kind``, ``jerk``,
``jerk-engine``. Every
option set is turned into :class:`~trcopt.pipeline.PlanOptions` when the sweep is read, so a bad
value (an unknown corner mode, a negative tolerance, a machine file that does not load) is an
error before any plan runs.
"""

from __future__ import annotations

import csv
import glob
import hashlib
import itertools
import json
import os
import tomllib
from collections.abc import Mapping
from dataclasses import dataclass, field
from pathlib import Path
from typing import Any

from trcopt.codes import Code
from trcopt.config import DEFAULT_MACHINE, load_machine
from trcopt.errors import ConfigError, TrcoptError
from trcopt.pipeline import PlanOptions

__all__ = ["Job", "Sweep", "load_sweep", "plan_options", "OPTION_NAMES", "OUTPUT_KINDS"]

# sweep name → PlanOptions field
OPTION_NAMES: dict[str, str] = {
    "dialect": "dialect",
    "profile": "profile",
    "controller": "profile",
    "machine": "machine",
    "timing": "timing",
    "verify": "verify",
    "strict": "strict",
    "tool_table": "tool_table",
    "tool_unit": "tool_unit",
    "appr_radius": "appr_radius",
    "corners": "corners",
    "tolerance": "tolerance_mm",
    "tolerance_kind": "tolerance_kind",
    "jerk": "jerk",
    "jerk_engine": "jerk_engine",
}
_BOOLEAN = {"timing", "verify", "strict", "jerk"}
_FLOAT = {"tolerance"}
_PATHS = {"machine", "tool_table"}
OUTPUT_KINDS = ("json", "gcode", "svg", "html", "csv")
DEFAULT = "default"  # ``machine = "default"``: the embedded machine


@dataclass(frozen=True, slots=True)
class Job:
    """One plan of a sweep: a program and an option set, and the key that names its row."""

    program: str  # as the table shows it: relative to the sweep file where it lies below it
    path: str  # the file to read
    options: tuple[tuple[str, Any], ...]  # sweep names and values, sorted by name
    key: str
    plan_options: PlanOptions = field(compare=False, repr=False)

    @property
    def options_text(self) -> str:
        """The option set as the table shows it: ``corners=arc tolerance=0.01`` (sorted)."""
        return " ".join(f"{k}={_text(v)}" for k, v in self.options)


@dataclass(slots=True)
class Sweep:
    """The jobs of a sweep file, in sweep order, and the per-plan outputs it asks for."""

    source: str
    jobs: list[Job]
    outputs: tuple[str, ...] = ()


def _text(value: Any) -> str:
    return ("true" if value else "false") if isinstance(value, bool) else str(value)


def job_key(program: str, options: Mapping[str, Any]) -> str:
    """The key of a row: a hash of the program (as the table names it) and the option set."""
    text = json.dumps([program, sorted(options.items())], sort_keys=True, default=str)
    return hashlib.sha256(text.encode()).hexdigest()[:16]


def _name(raw: str, where: str) -> str:
    name = raw.strip().replace("-", "_")
    if name not in OPTION_NAMES:
        raise ConfigError(f"{where}: unknown option {raw!r} (valid: {', '.join(sorted(OPTION_NAMES))})")
    return name


def _value(name: str, value: Any, where: str) -> Any:
    """A sweep value as the option needs it (CSV cells are text)."""
    if name in _BOOLEAN and isinstance(value, str):
        low = value.strip().lower()
        if low not in ("true", "false", "1", "0", "yes", "no", "on", "off"):
            raise ConfigError(f"{where}: {name} must be true or false, got {value!r}")
        return low in ("true", "1", "yes", "on")
    if name in _BOOLEAN and not isinstance(value, bool):
        raise ConfigError(f"{where}: {name} must be true or false, got {value!r}")
    if name in _FLOAT:
        try:
            return float(value)
        except (TypeError, ValueError):
            raise ConfigError(f"{where}: {name} must be a number, got {value!r}") from None
    if not isinstance(value, str | bool | int | float):
        raise ConfigError(f"{where}: {name} must be a single value, got {value!r}")
    return value


def plan_options(options: Mapping[str, Any], base: Path = Path("."), cache: dict | None = None) -> PlanOptions:
    """The :class:`PlanOptions` of a sweep option set (names as :data:`OPTION_NAMES`; paths
    relative to ``base``; ``machine = "default"`` is the embedded machine). Plans in a batch run
    in one process each (``workers = 1``): the batch is parallel across plans."""
    kwargs: dict[str, Any] = {"workers": 1}
    for name, value in options.items():
        target = OPTION_NAMES[name]
        if name in _PATHS and isinstance(value, str) and value != DEFAULT:
            value = str(base / value)
        if name == "machine":
            if value == DEFAULT:
                value = DEFAULT_MACHINE
            else:
                cache = {} if cache is None else cache
                if value not in cache:
                    cache[value] = load_machine(value)
                value = cache[value]
        kwargs[target] = value
    try:
        return PlanOptions(**kwargs)
    except ValueError as exc:  # an unknown tool unit or APPR/DEP radius reading
        raise TrcoptError(str(exc), code=Code.USAGE) from None


def _programs(patterns: list[str], base: Path, where: str) -> list[tuple[str, str]]:
    """(table name, path) of every file the globs match, in sorted order, each once."""
    found: dict[str, str] = {}
    for pattern in patterns:
        full = pattern if os.path.isabs(pattern) else str(base / pattern)
        matches = sorted(glob.glob(full, recursive=True))
        matches = [m for m in matches if os.path.isfile(m) and not m.endswith(".expected.json")]
        if not matches:
            raise ConfigError(f"{where}: no program matches {pattern!r}")
        for m in matches:
            try:
                shown = os.path.relpath(m, base) if not os.path.isabs(pattern) else m
            except ValueError:  # another drive
                shown = m
            found.setdefault(Path(shown).as_posix(), m)
    return list(found.items())


def _jobs(programs: list[tuple[str, str]], sets: list[dict[str, Any]], base: Path) -> list[Job]:
    cache: dict[str, Any] = {}
    built: dict[str, PlanOptions] = {}
    jobs: list[Job] = []
    for shown, path in programs:
        for opts in sets:
            ordered = tuple(sorted(opts.items()))
            text = json.dumps(ordered, default=str)
            if text not in built:
                built[text] = plan_options(dict(ordered), base, cache)
            jobs.append(Job(shown, path, ordered, job_key(shown, dict(ordered)), built[text]))
    return jobs


def _read_toml(path: Path) -> Sweep:
    where = str(path)
    try:
        data = tomllib.loads(path.read_text(encoding="utf-8"))
    except tomllib.TOMLDecodeError as exc:
        raise ConfigError(f"{where}: {exc}") from None
    unknown = set(data) - {"programs", "options", "axes", "outputs"}
    if unknown:
        raise ConfigError(f"{where}: unknown key {sorted(unknown)[0]!r} (valid: programs, options, axes, outputs)")
    patterns = data.get("programs")
    if isinstance(patterns, str):
        patterns = [patterns]
    if not patterns or not all(isinstance(p, str) for p in patterns):
        raise ConfigError(f"{where}: 'programs' must be a glob or a list of globs")
    fixed = {_name(k, where): _value(_name(k, where), v, where) for k, v in data.get("options", {}).items()}
    axes: dict[str, list[Any]] = {}
    for k, values in data.get("axes", {}).items():
        name = _name(k, where)
        values = values if isinstance(values, list) else [values]
        if not values:
            raise ConfigError(f"{where}: axes.{k} is empty")
        if name in fixed:
            raise ConfigError(f"{where}: {k} is both an option and an axis")
        axes[name] = [_value(name, v, f"{where}: axes.{k}") for v in values]
    sets = [{**fixed, **dict(zip(axes, combo, strict=True))} for combo in itertools.product(*axes.values())]
    outputs = data.get("outputs", [])
    outputs = [outputs] if isinstance(outputs, str) else outputs
    bad = [o for o in outputs if o not in OUTPUT_KINDS]
    if bad:
        raise ConfigError(f"{where}: unknown output {bad[0]!r} (valid: {', '.join(OUTPUT_KINDS)})")
    base = path.parent
    return Sweep(where, _jobs(_programs(patterns, base, where), sets, base), tuple(outputs))


def _read_csv(path: Path) -> Sweep:
    where = str(path)
    rows = list(csv.reader(path.read_text(encoding="utf-8").splitlines()))
    rows = [r for r in rows if any(c.strip() for c in r) and not r[0].lstrip().startswith("#")]
    if not rows or rows[0][0].strip() != "program":
        raise ConfigError(f"{where}: the first column of the header must be 'program'")
    names = [_name(h, where) for h in rows[0][1:]]
    base = path.parent
    jobs: list[Job] = []
    for n, row in enumerate(rows[1:], start=2):
        if len(row) > len(names) + 1:
            raise ConfigError(f"{where}: row {n} has more cells than the header")
        opts = {k: _value(k, c, f"{where}: row {n}") for k, c in zip(names, row[1:], strict=False) if c.strip()}
        jobs += _jobs(_programs([row[0].strip()], base, f"{where}: row {n}"), [opts], base)
    return Sweep(where, jobs)


def load_sweep(path: str | os.PathLike[str]) -> Sweep:
    """Read a sweep file (``.toml`` or ``.csv``) and expand it into jobs.

    Raises
    ------
    ConfigError
        The file cannot be read, names an unknown option or output, a glob matches no file, or
        an option value is invalid (also :class:`TrcoptError` with code ``USAGE``).
    """
    p = Path(path)
    try:
        p.read_bytes()
    except OSError as exc:
        raise ConfigError(f"cannot read sweep file {p}: {exc.strerror}", code=Code.IO) from None
    if p.suffix.lower() == ".csv":
        sweep = _read_csv(p)
    else:
        sweep = _read_toml(p)
    keys = [j.key for j in sweep.jobs]
    if len(set(keys)) != len(keys):
        seen: set[str] = set()
        twice = next(j for j in sweep.jobs if j.key in seen or seen.add(j.key))  # type: ignore[func-returns-value]
        raise ConfigError(f"{p}: {twice.program} with {twice.options_text or 'the defaults'} is in the sweep twice")
    if not sweep.jobs:
        raise ConfigError(f"{p}: the sweep has no plan")
    return sweep
