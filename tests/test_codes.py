"""The diagnostic code catalogue: complete, documented, the only place codes are defined, and
enforced when a diagnostic or an error is made."""

from __future__ import annotations

import ast
import re
from pathlib import Path

import pytest

from trcopt.codes import MEANING, Code, family
from trcopt.errors import Diagnostic, Severity, TrcoptError

ROOT = Path(__file__).resolve().parents[1]
DOC = ROOT / "docs" / "diagnostics.md"
CODE_LIKE = re.compile(r"^(?:1\d{4}|[A-Z][A-Z0-9]*(?:-[A-Z0-9]+)+|[EW]_[A-Z0-9_]+)$")
NOT_CODES = {"UTF-8"}


def catalogue_rows() -> list[str]:
    """The table rows of docs/diagnostics.md as the catalogue says they must read."""
    rows = []
    for c in Code:
        meaning = MEANING[c].replace("|", "\\|")
        rows.append(f"| `{c.value}` | {family(c)} | {meaning} |")
    return rows


def test_every_code_has_a_meaning_and_one_spelling() -> None:
    assert set(MEANING) == set(Code)
    for c in Code:
        assert c.value.isdigit() or re.fullmatch(r"[A-Z][A-Z0-9]*(-[A-Z0-9]+)*", c.value), c
        assert c.name == (f"ALARM_{c.value}" if c.value.isdigit() else c.value.replace("-", "_"))


def test_the_documentation_lists_the_catalogue() -> None:
    documented = [line for line in DOC.read_text(encoding="utf-8").splitlines() if line.startswith("| `")]
    assert documented == catalogue_rows()


def test_every_code_written_in_the_package_is_catalogued() -> None:
    """String constants that look like codes, anywhere in the package: no code lives elsewhere."""
    known = {c.value for c in Code}
    strays = set()
    for path in (ROOT / "trcopt").rglob("*.py"):
        tree = ast.parse(path.read_text(encoding="utf-8"))
        # a constant given to a parameter or keyword called "code" is a code, whatever it looks like
        as_code = {id(k.value) for k in ast.walk(tree) if isinstance(k, ast.keyword) and k.arg == "code"}
        for args in (a for a in ast.walk(tree) if isinstance(a, ast.arguments)):
            positional = [*args.posonlyargs, *args.args]
            with_default = positional[len(positional) - len(args.defaults) :]
            pairs = [*zip(with_default, args.defaults, strict=True)]
            pairs += zip(args.kwonlyargs, args.kw_defaults, strict=True)
            as_code |= {id(d) for a, d in pairs if a.arg == "code" and d is not None}
        for node in ast.walk(tree):
            if isinstance(node, ast.Constant) and isinstance(node.value, str):
                if (CODE_LIKE.match(node.value) or id(node) in as_code) and node.value not in known | NOT_CODES:
                    strays.add(f"{path.relative_to(ROOT)}: {node.value}")
    assert sorted(strays) == []


def test_unknown_codes_are_rejected_when_made() -> None:
    with pytest.raises(ValueError, match="NO-SUCH-CODE"):
        Diagnostic(Severity.ERROR, "NO-SUCH-CODE", "x")
    with pytest.raises(ValueError, match="NO-SUCH-CODE"):
        TrcoptError("x", code="NO-SUCH-CODE")
    d = Diagnostic(Severity.WARNING, "10763", "omitted")
    assert d.code is Code.ALARM_10763 and d.code == "10763" and d.to_json()["code"] == "10763"
    assert TrcoptError("x").code is Code.TRCOPT


@pytest.mark.parametrize(("code", "expected"), [("10751", "SINUMERIK alarm"), ("HH-CR-CHORD", "Heidenhain TNC"),
                                                ("USAGE", "usage, files and outputs")])
def test_family(code: str, expected: str) -> None:
    assert family(code) == expected
