"""SINUMERIK settable zero offsets with rotation and scale from the zero-offset file: the
controller composes the settable frame and the programmable frame, ``P_mcs = S(F(P_wcs))``, so a
rotated (scaled) G54 gives the tool-centre path of the same program with ``ROT`` (``SCALE``)
programmed under an unrotated one."""

from __future__ import annotations

import math
from pathlib import Path

import pytest

from trcopt.controllers import read_program
from trcopt.controllers.siemens.frames import Frame, load_zero_offsets, rotation, scaling, translation
from trcopt.errors import ConfigError, Severity
from trcopt.pipeline import PlanOptions, plan_file

OFFSETS = """
[G54]
X = 100.0
Y = 50.0
Z = -20.0
ROT_Z = 30.0
[G55]
X = 100.0
Y = 50.0
Z = -20.0
[G56]
X = 100.0
Y = 50.0
Z = -20.0
ROT_Z = 30.0
SCALE = 2.0
[G57]
X = -40.0
Y = 10.0
ROT_Z = -45.0
"""
TOOL = "$TC_DP1[1,1]=120 $TC_DP6[1,1]=5\n"
# a compensated contour with an arc; the plan's reference is G500 (its first motion), so the
# settable frames of G54… appear in the plan (machine coordinates)
CONTOUR = (
    "N30 G0 X-20 Y-20 Z5\nN40 G1 Z-5 F500\nN50 G42 X0 Y0\nN60 X40\nN70 G3 X60 Y20 CR=20\nN80 G1 Y50\n"
    "N90 X10\nN100 G40 X10 Y70\nN110 G0 Z50\nN120 M30\n"
)


def _plan(folder: Path, name: str, text: str):
    (folder / "offsets.toml").write_text(OFFSETS)
    path = folder / name
    path.write_text(text)
    result = plan_file(path, PlanOptions(timing=False))
    assert result.ok, [d.format() for d in result.diagnostics]
    return [(s.kind, s.start_xyz, s.end_xyz, s.center_xyz) for s in result.toolpath]


def _same(a, b, tol=1e-9):
    assert len(a) == len(b) > 8
    for (ka, sa, ea, ca), (kb, sb, eb, cb) in zip(a, b, strict=True):
        assert ka == kb
        assert math.dist(sa, sb) <= tol and math.dist(ea, eb) <= tol
        assert (ca is None) == (cb is None) and (ca is None or math.dist(ca, cb) <= tol)


def test_a_rotated_g54_gives_the_path_of_rot_programmed(tmp_path):
    head = TOOL + "N10 G17 G90 G500 T1 D1 G0 X0 Y0 Z50\n"
    rotated = _plan(tmp_path, "a.mpf", head + "N20 G54\n" + CONTOUR)
    programmed = _plan(tmp_path, "b.mpf", head + "N20 G55\nN25 ROT Z30\n" + CONTOUR)
    _same(rotated, programmed)
    # and it is turned: the first contour line (G42 on X0→X40, offset to −Y) runs at 30°
    line = next(p for p in rotated if p[0] == "line" and math.dist(p[1], p[2]) > 39)
    angle = math.degrees(math.atan2(line[2][1] - line[1][1], line[2][0] - line[1][0]))
    assert angle == pytest.approx(30.0, abs=1e-9)
    # not the path of the unrotated offset
    unrotated = _plan(tmp_path, "c.mpf", head + "N20 G55\n" + CONTOUR)
    assert max(math.dist(x[2], y[2]) for x, y in zip(rotated, unrotated, strict=True)) > 10


def test_a_rotated_and_scaled_g56_gives_the_path_of_rot_and_ascale(tmp_path):
    head = TOOL + "N10 G17 G90 G500 T1 D1 G0 X0 Y0 Z50\n"
    settable = _plan(tmp_path, "a.mpf", head + "N20 G56\n" + CONTOUR)
    programmed = _plan(tmp_path, "b.mpf", head + "N20 G55\nN25 ROT Z30\nN26 ASCALE X2 Y2 Z2\n" + CONTOUR)
    _same(settable, programmed)


def test_the_programmable_frame_acts_inside_the_settable_one(tmp_path):
    # G54 (T, ROT_Z 30) with TRANS X10 == G55 (T) with ROT Z30 and ATRANS X10
    head = TOOL + "N10 G17 G90 G500 T1 D1 G0 X0 Y0 Z50\n"
    a = _plan(tmp_path, "a.mpf", head + "N20 G54\nN25 TRANS X10 Y-5\n" + CONTOUR)
    b = _plan(tmp_path, "b.mpf", head + "N20 G55\nN25 ROT Z30\nN26 ATRANS X10 Y-5\n" + CONTOUR)
    _same(a, b)


def test_a_change_between_two_rotated_offsets_is_relative_to_the_reference(tmp_path):
    # reference G57 (rotated −45°); then G54 (rotated +30°): in G57's system the contour of G54 is
    # the G54 path mapped back through G57's settable frame
    head = TOOL + "N10 G17 G90 G57 T1 D1 G0 X0 Y0 Z50\n"
    changed = _plan(tmp_path, "a.mpf", head + "N20 G54\n" + CONTOUR)
    machine = _plan(tmp_path, "b.mpf", TOOL + "N10 G17 G90 G500 T1 D1 G0 X0 Y0 Z50\nN20 G54\n" + CONTOUR)
    g57 = load_zero_offsets(tmp_path / "offsets.toml").get(57)
    assert g57 is not None
    back = g57.inverse()
    for (ka, _, ea, ca), (kb, _, eb, cb) in list(zip(changed, machine, strict=True))[2:]:
        assert ka == kb
        assert math.dist(ea, back.apply(eb)) <= 1e-9
        assert (ca is None) == (cb is None) and (ca is None or math.dist(ca, back.apply(cb)) <= 1e-9)


def test_a_machine_position_under_a_rotated_reference(tmp_path):
    (tmp_path / "offsets.toml").write_text(OFFSETS)
    prog = read_program(
        "N10 G17 G90 G54 G0 X30 Y-20 Z10\nN20 G53 G0 X100 Y50\nN30 G0 X10\nM30\n",
        file=str(tmp_path / "p.mpf"),
        zero_offsets=tmp_path / "offsets.toml",
    )
    assert [d.format() for d in prog.diagnostics if d.severity is Severity.ERROR] == []
    ends = {m.span.block: m.end for m in prog.moves}
    # machine X100 Y50 is G54's origin in the plane; Z keeps its position
    assert ends["N20"] == pytest.approx((0.0, 0.0, 10.0), abs=1e-9)
    assert ends["N30"] == pytest.approx((10.0, 0.0, 10.0), abs=1e-9)


def test_a_rotation_about_z_tilts_the_working_plane_g18(tmp_path):
    (tmp_path / "offsets.toml").write_text(OFFSETS)
    prog = read_program(
        TOOL + "N10 G18 G90 G500 T1 D1 G0 X0 Y0 Z0\nN20 G54\nN30 G1 X20 Z5 F100\nM30\n",
        file=str(tmp_path / "p.mpf"),
        zero_offsets=tmp_path / "offsets.toml",
    )
    errs = [d for d in prog.diagnostics if d.severity is Severity.ERROR]
    assert [(str(d.code), d.span.block) for d in errs] == [("NC-FRAME", "N30")]
    assert "out of itself" in errs[0].message


def test_the_settable_frame_is_translation_then_rotation_then_scale(tmp_path):
    (tmp_path / "o.toml").write_text(OFFSETS)
    g56 = load_zero_offsets(tmp_path / "o.toml").get(56)
    expected = translation((100.0, 50.0, -20.0)).then(rotation(2, 30.0)).then(scaling((2.0, 2.0, 2.0)))
    assert isinstance(g56, Frame) and g56 == expected
    p = (3.0, -4.0, 1.5)
    assert g56.inverse().apply(g56.apply(p)) == pytest.approx(p, abs=1e-12)


@pytest.mark.parametrize(
    ("row", "words"),
    [
        ("X = 1.0\nSCALE = 0.0", "SCALE = 0"),
        ("X = 1.0\nROT_X = 5.0", "ROT_Z (rotation about Z, degrees)"),
        ('ROT_Z = "30"', "ROT_Z must be a number"),
        ("SCALE = inf", "not a finite value"),
    ],
)
def test_bad_rotation_or_scale_in_the_zero_offset_file(tmp_path, row, words):
    path = tmp_path / "o.toml"
    path.write_text(f"[G54]\n{row}\n")
    with pytest.raises(ConfigError) as exc:
        load_zero_offsets(path)
    assert words in exc.value.message and "[G54]" in exc.value.message
