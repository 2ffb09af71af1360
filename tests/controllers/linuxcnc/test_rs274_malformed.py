"""RS274NGC errors raised before a block's words are read still carry the block number."""

from __future__ import annotations

import pytest

from trcopt.codes import Code
from trcopt.pipeline import PlanOptions, plan


@pytest.mark.parametrize(
    ("line", "code", "column"),
    [
        ("N20 G1 X5 (unclosed", Code.NC_SYNTAX, 11),
        ("N20 G1 X5 E3", Code.NC_UNSUPPORTED, 11),
        ("N20 G1 X5 @", Code.NC_SYNTAX, 11),
        ("n 20 G1 X5 A1", Code.NC_UNSUPPORTED, 12),
        ("N20 G1 X[1/0]", Code.LCNC_EXPRESSION, 9),
    ],
)
def test_early_errors_carry_the_block_number(line: str, code: Code, column: int) -> None:
    result = plan(f"G21 F100\n{line}\nM2\n", file="p.ngc", options=PlanOptions(timing=False))
    err = result.errors[0]
    assert err.code is code
    assert (err.span.file, err.span.line, err.span.block) == ("p.ngc", 2, "N20")
    assert err.span.column == column

