"""Toolholder carrier files: one ``$TC_CARRn[m]`` data block as TOML.

Keys are the system-variable names without ``$`` and without the block index (``TC_CARR7 = 0.0``,
``TC_CARR23 = "T"``), plus the metadata keys ``number`` and ``fine_offsets_enabled``; see
:func:`carrier_from_toml_dict`. Every problem is a :class:`~trcopt.errors.ConfigError` that names
the file and the key (code ``"14153"`` for an invalid kinematic type, the toolholder code for an
invalid value). The data block itself is :mod:`trcopt.kinematics.carrier`.
"""

from __future__ import annotations

import tomllib
from collections.abc import Mapping
from pathlib import Path

from trcopt.errors import AlarmError, ConfigError, SourceSpan
from trcopt.kinematics.carrier import LAST_INDEX, UNDEFINED_INDICES, Carrier, carrier_from_assignments

__all__ = ["carrier_from_toml_dict", "load_carrier_toml"]


def carrier_from_toml_dict(data: Mapping[str, object], file: str = "<toml>") -> Carrier:
    """Build a carrier from the parsed contents of a carrier TOML file.

    Keys are the system-variable names without ``$`` and without the block index:
    ``TC_CARR7 = 0.0``, ``TC_CARR23 = "T"`` (case-insensitive). Two optional metadata keys:
    ``number`` (data block number, default 1) and ``fine_offsets_enabled`` (default true).
    Absent keys take the control's defaults.

    Raises
    ------
    ConfigError
        Naming the offending key: unknown keys, undefined indices (47–54, 61–63), wrong value
        types; code ``"14153"`` for an invalid kinematic type.
    """
    span = SourceSpan(file=file)
    values: dict[int, object] = {}
    number = 1
    fine = True
    for key, value in data.items():
        k = str(key)
        if k == "number":
            if isinstance(value, bool) or not isinstance(value, int) or value < 0:
                raise ConfigError(f"{file}: key 'number' must be a non-negative integer", span)
            number = value
            continue
        if k == "fine_offsets_enabled":
            if not isinstance(value, bool):
                raise ConfigError(f"{file}: key 'fine_offsets_enabled' must be true or false", span)
            fine = value
            continue
        upper = k.upper().lstrip("$")
        digits = upper[len("TC_CARR") :]
        if not upper.startswith("TC_CARR") or not digits.isdigit():
            raise ConfigError(
                f"{file}: unknown key {k!r} (expected TC_CARR1 … TC_CARR65, 'number' or "
                "'fine_offsets_enabled')",
                span,
            )
        n = int(digits)
        if n < 1 or n > LAST_INDEX or n in UNDEFINED_INDICES:
            raise ConfigError(
                f"{file}: unknown key {k!r}: $TC_CARR{n} is not a defined toolholder parameter",
                span,
            )
        if isinstance(value, dict | list):
            raise ConfigError(f"{file}: key {k!r} must be a single value", span)
        values[n] = value
    try:
        return carrier_from_assignments(values, number, span, fine_offsets_enabled=fine)
    except AlarmError as exc:
        d = exc.diagnostic
        code = d.code
        key = _key_in_message(d.message)
        raise ConfigError(f"{file}: key {key}: {d.message}", span, code) from None


def _key_in_message(message: str) -> str:
    # the assignment errors name "$TC_CARRn[m]"; turn that into the TOML key "TC_CARRn"
    start = message.find("$TC_CARR")
    if start < 0:
        return "?"
    end = message.find("[", start)
    return repr(message[start + 1 : end])


def load_carrier_toml(path: str | Path) -> Carrier:
    """Read a carrier TOML file (keys ``TC_CARR1 … TC_CARR65``, see
    :func:`carrier_from_toml_dict`).

    Raises
    ------
    ConfigError
        File missing or unreadable, invalid TOML, unknown keys (named), invalid values; code
        ``"14153"`` when ``TC_CARR23`` is not T/P/M.
    """
    p = Path(path)
    try:
        with p.open("rb") as fh:
            data = tomllib.load(fh)
    except OSError as exc:
        raise ConfigError(f"{p}: cannot read carrier file: {exc.strerror}") from None
    except UnicodeDecodeError as exc:
        raise ConfigError(f"{p}: not a text file (a carrier file is UTF-8 TOML): byte {exc.start}") from None
    except tomllib.TOMLDecodeError as exc:
        raise ConfigError(f"{p}: invalid TOML: {exc}") from None
    return carrier_from_toml_dict(data, str(p))
