"""Forward chain: rotation sense, axis offsets, tool length per plane, wear modes, F1/F2."""

from __future__ import annotations

import math

import numpy as np
import pytest

from trcopt.geometry.plane import Plane
from trcopt.kinematics import (
    Carrier,
    KinematicType,
    initial_direction,
    part_rotations,
    relative_direction,
    resulting_tool_length,
    rotation,
    rpy_matrix,
    table_offset,
    tool_length_vector,
)
from trcopt.modes import WearMode


def test_rotation_is_right_handed() -> None:
    # +90° about +Z turns +X into +Y; about +X turns +Y into +Z
    np.testing.assert_allclose(rotation((0, 0, 5), 90) @ (1, 0, 0), (0, 1, 0), atol=1e-15)
    np.testing.assert_allclose(rotation((1, 0, 0), 90) @ (0, 1, 0), (0, 0, 1), atol=1e-15)
    np.testing.assert_allclose(rotation((0, 0, 0), 90), np.eye(3))


def test_rpy_is_rz_ry_rx() -> None:
    r = rpy_matrix(10, 20, 30)
    expected = rotation((0, 0, 1), 30) @ rotation((0, 1, 0), 20) @ rotation((1, 0, 0), 10)
    np.testing.assert_allclose(r, expected, atol=1e-15)


@pytest.mark.parametrize(("plane", "axis"), [("G17", 2), ("G18", 1), ("G19", 0)])
def test_initial_direction_per_plane(plane: str, axis: int) -> None:
    e = np.zeros(3)
    e[axis] = 1.0
    np.testing.assert_array_equal(initial_direction(plane), e)


@pytest.mark.parametrize(
    ("plane", "milling", "turning"),
    [
        (Plane.G17, (3, 2, 1), (2, 1, 3)),
        (Plane.G18, (2, 1, 3), (1, 3, 2)),
        (Plane.G19, (1, 3, 2), (3, 2, 1)),
    ],
)
def test_tool_length_assignment(plane: Plane, milling: tuple, turning: tuple) -> None:
    np.testing.assert_array_equal(tool_length_vector((1, 2, 3), plane), milling)
    np.testing.assert_array_equal(tool_length_vector((1, 2, 3), plane, "turning"), turning)


def test_tool_length_vector_rejects_four_values() -> None:
    with pytest.raises(ValueError):
        tool_length_vector((1, 2, 3, 4))


def test_axis_offset_sign_reading_r2() -> None:
    # θ = α − offset: at α = offset the described geometry holds
    c = Carrier(v1=(1, 0, 0), axis_offset1=90.0)
    lt = (0, 0, 100)
    np.testing.assert_allclose(resulting_tool_length(c, 90, 0, lt), (0, 0, 100), atol=1e-12)
    # the alternative reading θ = α + offset would give (0, −100, 0) at A = 0; we give (0, 100, 0)
    np.testing.assert_allclose(resulting_tool_length(c, 0, 0, lt), (0, 100, 0), atol=1e-12)


def test_wear_modes() -> None:
    c = Carrier(v1=(0, 1, 0))
    wear = (0.0, 0.0, -0.2)
    std = resulting_tool_length(c, 90, 0, (0, 0, 100), wear=wear)
    mcs = resulting_tool_length(c, 90, 0, (0, 0, 100), wear=wear, wear_mode=WearMode.TOWMCS)
    np.testing.assert_allclose(std, (99.8, 0, 0), atol=1e-12)
    np.testing.assert_allclose(mcs, (100.0, 0, -0.2), atol=1e-12)


@pytest.mark.parametrize("kin", list(KinematicType))
def test_closed_chain_is_neutral_at_zero(kin: KinematicType) -> None:
    c = Carrier(
        kinematic_type=kin,
        v1=(0, 1, 0),
        v2=(0, 0, 1),
        l1=(0, 0, -120),
        l2=(0, 0, 120) if kin is KinematicType.M else (10, 0, -40),
        l3=(100, 50, -200) if kin is KinematicType.M else (0, 5, 30),
        l4=(-100, -50, 200) if kin is KinematicType.M else (-10, -5, 10),
    )
    if kin is KinematicType.T:
        c = Carrier(v1=(0, 1, 0), v2=(0, 0, 1), l1=(-10, -5, 10), l2=(10, 0, -40), l3=(0, 5, 30))
    np.testing.assert_allclose(resulting_tool_length(c, 0, 0, (0, 0, 100)), (0, 0, 100), atol=1e-12)
    np.testing.assert_allclose(table_offset(c, 0, 0), (0, 0, 0), atol=1e-12)


def test_relative_direction_per_type() -> None:
    e = np.array([0.0, 0.0, 1.0])
    for kin in KinematicType:
        c = Carrier(kinematic_type=kin, v1=(0, 1, 0), v2=(0, 0, 1))
        r_tool, r_part = part_rotations(c, 30, 45)
        np.testing.assert_allclose(relative_direction(c, 30, 45, e), r_part.T @ r_tool @ e)
    # type P: the table tilts +30 about Y, so the tool leans −30 relative to the part
    p = Carrier(kinematic_type=KinematicType.P, v1=(0, 1, 0))
    s = math.sin(math.radians(30))
    np.testing.assert_allclose(relative_direction(p, 30, 0, e), (-s, 0, math.cos(math.radians(30))))
