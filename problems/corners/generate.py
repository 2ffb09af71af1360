"""Writes the generated benchmark contours of this folder (CAM-style polylines and a gear).

Run:  python problems/corners/generate.py

* ``cam_circle.mpf`` — a circular pocket R 25 as 1 mm G1 chords (157 chords, deflection 2.29°),
  G41 inside (inside corners), approached from and left to the centre, R = 3.
* ``cam_freeform.mpf`` — a closed three-lobed cam r(θ) = 28 + 6·sin 3θ as G1 chords of 0.5–2 mm
  chosen for a deflection of about 3° (less near the inflections), convex and concave stretches, G42, R = 3.
* ``gear_12.mpf`` — a 12-tooth gear of straight flanks (root R 25, tip R 30), G42 outside, R = 2:
  48 sharp corners, 24 of them inside corners.

The files are written with six decimals; the numbers in the headers are computed, not typed.
"""

from __future__ import annotations

import math
from pathlib import Path

HERE = Path(__file__).resolve().parent


def _program(title: str, radius: float, pts: list[tuple[float, float]], approach: tuple[float, float],
             leave: tuple[float, float], side: str = "G42") -> str:
    lines = [f"; {title}", f"$TC_DP1[1,1]=120 $TC_DP6[1,1]={radius:g}"]
    n = 10
    lines.append(f"N{n} G17 G90 T1 D1 G0 X{approach[0]:.6f} Y{approach[1]:.6f} Z0")
    n += 10
    x0, y0 = pts[0]
    lines.append(f"N{n} G1 {side} X{x0:.6f} Y{y0:.6f} F6000")
    for x, y in pts[1:]:
        n += 10
        lines.append(f"N{n} X{x:.6f} Y{y:.6f}")
    n += 10
    lines.append(f"N{n} G40 X{leave[0]:.6f} Y{leave[1]:.6f}")
    n += 10
    lines.append(f"N{n} M30")
    return "\n".join(lines) + "\n"


def cam_circle() -> str:
    R, chord = 25.0, 1.0
    count = round(2 * math.pi * R / chord)
    pts = [(R * math.cos(2 * math.pi * i / count), R * math.sin(2 * math.pi * i / count)) for i in range(count + 1)]
    pts[-1] = pts[0]
    # start and end in the middle of a chord: a closed contour entered at a vertex of an inside
    # corner is gouged by the approach (the controller's path too)
    mid = ((pts[-2][0] + pts[0][0]) / 2, (pts[-2][1] + pts[0][1]) / 2)
    pts = [mid, *pts[:-1], mid]
    defl = math.degrees(2 * math.pi / count)
    real = 2 * R * math.sin(math.pi / count)
    title = (f"Corner benchmark: CAM-style polyline, circular pocket R {R:g} in {count} chords of {real:.4f} mm "
             f"(deflection {defl:.2f} deg), G41 inside, R = 3")
    return _program(title, 3, pts, (0.0, 0.0), (0.0, 0.0), side="G41")


def _cam_r(t: float) -> tuple[float, float, float]:
    """Radius r(θ), r′, r″ of the three-lobed cam."""
    return 28 + 6 * math.sin(3 * t), 18 * math.cos(3 * t), -54 * math.sin(3 * t)


def cam_freeform() -> tuple[str, float, float, float, float, int]:
    pts: list[tuple[float, float]] = []
    t = 0.0
    while t < 2 * math.pi:
        r, rp, rpp = _cam_r(t)
        pts.append((r * math.cos(t), r * math.sin(t)))
        speed = math.hypot(r, rp)
        kappa = abs(r * r + 2 * rp * rp - r * rpp) / speed**3
        chord = min(max(math.radians(3.0) / max(kappa, 1e-9), 0.5), 1.9)
        t += chord / speed
    pts.append(pts[0])
    chords = [math.dist(a, b) for a, b in zip(pts, pts[1:], strict=False)]
    defl = []
    for a, b, c in zip(pts, pts[1:], pts[2:], strict=False):
        u = (b[0] - a[0], b[1] - a[1])
        v = (c[0] - b[0], c[1] - b[1])
        defl.append(abs(math.degrees(math.atan2(u[0] * v[1] - u[1] * v[0], u[0] * v[0] + u[1] * v[1]))))
    title = (f"Corner benchmark: CAM-style polyline, three-lobed cam r = 28 + 6 sin 3t in {len(chords)} chords "
             f"of {min(chords):.2f}-{max(chords):.2f} mm (deflection {min(defl):.2f}-{max(defl):.2f} deg), "
             "G42 outside, R = 3")
    x0, y0 = pts[0]
    return _program(title, 3, pts, (x0 + 12, y0 - 12), (x0 + 12, y0 + 12)), 0, 0, 0, 0, len(chords)


def gear() -> str:
    teeth, root, tip = 12, 25.0, 30.0
    pitch = 2 * math.pi / teeth
    pts = []
    for i in range(teeth):
        a = i * pitch
        # root land, flank up, tip land, flank down (angular widths 0.3/0.2/0.25/0.25 of the pitch)
        for frac, rad in ((0.0, root), (0.3, root), (0.5, tip), (0.75, tip)):
            pts.append((rad * math.cos(a + frac * pitch), rad * math.sin(a + frac * pitch)))
    # start and end in the middle of a tip land, approached and left along its normal
    k = len(pts) - 2
    mid = ((pts[k][0] + pts[k + 1][0]) / 2, (pts[k][1] + pts[k + 1][1]) / 2)
    ring = [mid, *pts[k + 1:], *pts[: k + 1], mid]
    out = math.hypot(*mid)
    far = ((out + 10) * mid[0] / out, (out + 10) * mid[1] / out)
    title = (
        f"Corner benchmark: {teeth}-tooth gear, straight flanks, root R {root:g}, tip R {tip:g}, G42 outside, R = 2"
    )
    return _program(title, 2, ring, far, far)


def main() -> None:
    (HERE / "cam_circle.mpf").write_text(cam_circle())
    (HERE / "cam_freeform.mpf").write_text(cam_freeform()[0])
    (HERE / "gear_12.mpf").write_text(gear())


if __name__ == "__main__":
    main()
