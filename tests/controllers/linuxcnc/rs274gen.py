"""Seeded random RS274NGC programs for the differential comparison with LinuxCNC's ``rs274``:
work offsets (G10 L2/L20, G54…G59.3), G92/G92.1/G92.2/G92.3, G52, G53, G28/G30 and
their .1, tool changes and length offsets (T M6, M61, G43 H, G43.1, G49, G10 L1/L10), canned
cycles (G73 G81–G87 G89, G98/G99, L, G91), compensated contours (G41/G42 with D from the tool
table or the spindle tool, G41.1/G42.1), lathe profiles in G18 (G41.1/G42.1 D L: tool
orientations), feed modes (G95 with S, G93 with F on every move), predefined parameters (``#<_x>``…), DEBUG messages, and
now and then a block LinuxCNC refuses (offsets, cycles or mode changes under compensation, a
cycle without R, …). A program keeps its unit: rs274 (standalone) keeps a tool length offset's
number through G20/G21 (its canon does not convert it).

Every line carries a unique ``N`` number, so that an error ``rs274`` reports (it names the
block's text, not its line) can be found. The tool table is LinuxCNC's default ``sim.tbl``
(inch): T1 D0.125 Z0.511, T2 D0.0625 Z0.1, T3 D0.201 Z1.273.
"""

from __future__ import annotations

import random

__all__ = ["program"]

TOOLS = (1, 2, 3)


class _Gen:
    def __init__(self, seed: int) -> None:
        self.r = random.Random(seed)
        self.lines: list[str] = []
        self.metric = self.r.random() < 0.7
        self.k = 1.0 if self.metric else 1 / 25.4  # program units per mm
        self.comp = False
        self.tool: int | None = None
        self.m61 = False

    def n(self, mm: float) -> str:
        return f"{mm * self.k:.4f}".rstrip("0").rstrip(".") or "0"

    def rnd(self, lo: float, hi: float) -> str:
        return self.n(self.r.uniform(lo, hi))

    def add(self, text: str) -> None:
        self.lines.append(text)

    # -- features -------------------------------------------------------------------------------
    def offsets(self) -> None:
        r = self.r
        choice = r.randrange(9)
        if choice == 0:
            self.add(f"G10 L2 P{r.randrange(0, 10)} X{self.rnd(-50, 50)} Y{self.rnd(-50, 50)} Z{self.rnd(-20, 20)}")
        elif choice == 1:
            self.add(f"G10 L20 P{r.randrange(0, 4)} X{self.rnd(-20, 20)} Y{self.rnd(-20, 20)}")
        elif choice == 2:
            self.add(r.choice(("G54", "G55", "G56", "G57", "G58", "G59", "G59.1", "G59.2", "G59.3")))
        elif choice == 3:
            self.add(
                f"G92 X{self.rnd(-10, 10)} Y{self.rnd(-10, 10)}" + (f" Z{self.rnd(-5, 5)}" if r.random() < 0.5 else "")
            )
        elif choice == 4:
            self.add(r.choice(("G92.1", "G92.2", "G92.3")))
        elif choice == 5:
            self.add(f"G52 X{self.rnd(-10, 10)} Y{self.rnd(-10, 10)}")
        elif choice == 6:
            self.add(f"G53 G0 Z{self.rnd(-5, 30)}" + (f" X{self.rnd(-30, 30)}" if r.random() < 0.4 else ""))
        elif choice == 7:
            which = r.choice(("G28", "G30"))
            axes = r.choice(("", " Z0", f" G91 Z{self.rnd(0, 5)}", f" X{self.rnd(-10, 10)} Z{self.rnd(0, 20)}"))
            self.add(which + axes)
            if "G91" in axes:
                self.add("G90")
        else:
            if r.random() < 0.5:
                self.add(f"#5161={self.rnd(-1, 1)} #5163={self.rnd(0, 2)}")
            self.add(r.choice(("G28.1", "G30.1")))

    def tool_change(self) -> None:
        r = self.r
        t = r.choice(TOOLS)
        choice = r.randrange(5)
        # a tool change cancels the length offset first: rs274 (standalone) re-reads its position
        # after M6/M61 from a canon that ignores tool length offsets (a jump LinuxCNC does not make)
        # (a move after G49 makes its position known to that canon again)
        if choice in (0, 1):
            self.add("G49")
            self.add(f"G0 Z{self.rnd(5, 20)}")
        if choice == 0:
            self.add(f"T{t} M6")
            self.tool = t
            self.m61 = False
            self.add(r.choice((f"G43 H{t}", "G43", f"G43 H{t} Z{self.rnd(5, 20)}")))
        elif choice == 1:
            # rs274 (standalone) sets the tool number only and keeps the old tool's data in the
            # spindle slot (LinuxCNC's task loads the new tool's): no D0/G43 after M61 here
            self.add(f"M61 Q{t}")
            self.m61 = True
        elif choice == 2:
            self.add(f"G43.1 Z{self.rnd(-10, 10)}")
        elif choice == 3:
            self.add("G49")
        else:
            # not T1: rs274 (standalone) starts with T1's pocket "loaded" into an empty spindle, so
            # G10 L1 P1 before any M6 changes its spindle tool
            t = r.choice(TOOLS[1:])
            self.add(
                f"G10 L{r.choice((1, 10))} P{t} Z{self.rnd(-10, 10)}"
                + (f" R{self.rnd(0.5, 3)}" if r.random() < 0.5 else "")
            )

    def cycle(self) -> None:
        r = self.r
        g = r.choice(("G81", "G82", "G83", "G73", "G85", "G89", "G84", "G86", "G87"))
        plane = r.choice(("G17", "G17", "G17", "G18", "G19"))
        if plane != "G17":
            self.add(plane)
        if g in ("G84", "G86", "G87") and r.random() < 0.85:
            self.add("M3 S1000")
        inc = r.random() < 0.25
        a, b, c = {"G17": "XYZ", "G18": "ZXY", "G19": "YZX"}[plane]
        words = [r.choice(("G98", "G99", "")), "G91" if inc else "", g]
        if inc:
            words += [f"{a}{self.rnd(-5, 5)}", f"{b}{self.rnd(-5, 5)}", f"{c}{self.rnd(-8, -1)}", f"R{self.rnd(-2, 3)}"]
        else:
            words += [f"{a}{self.rnd(-30, 30)}", f"{b}{self.rnd(-30, 30)}", f"{c}{self.rnd(-8, -1)}"]
            if r.random() < 0.95:
                words.append(f"R{self.rnd(0.5, 5)}")
        if g in ("G82", "G89", "G86"):
            words.append(f"P{r.choice(('0.5', '1'))}")
        if g in ("G83", "G73"):
            words += [f"Q{self.rnd(0.7, 3)}", f"D{self.rnd(0.1, 0.6)}"]
        if g == "G87":
            words += [f"I{self.rnd(-2, 2)}", f"J{self.rnd(-2, 2)}", f"K{self.rnd(-6, -1)}"]
        if r.random() < 0.3:
            words.append(f"L{r.randrange(1, 4)}")
        self.add(" ".join(w for w in words if w) + (f" F{self.rnd(50, 300)}" if r.random() < 0.3 else ""))
        for _ in range(r.randrange(0, 3)):
            self.add(f"{a}{self.rnd(-30, 30)} {b}{self.rnd(-30, 30)}" if not inc else f"{a}{self.rnd(-5, 5)}")
        self.add("G80" + (" G90" if inc else "") + (" G17" if plane != "G17" else ""))

    def contour(self) -> None:
        r = self.r
        x0, y0 = r.uniform(-20, 20), r.uniform(-20, 20)
        w, h = r.uniform(8, 30), r.uniform(8, 30)
        self.add(f"G0 X{self.n(x0 - 5)} Y{self.n(y0 - 5)}")
        self.add(f"G0 Z{self.rnd(-2, 2)}")
        side = r.choice(("G41", "G42"))
        kind = r.randrange(4)
        if kind == 0:
            on = f"{side} D{r.choice(TOOLS)}"
        elif kind == 1 and not self.m61:
            on = side + r.choice(("", " D0"))
        elif kind == 1:
            on = f"{side} D{r.choice(TOOLS)}"
        else:
            on = f"{side}.1 D{self.rnd(0.5, 4)}"
        self.add(f"{on} G1 X{self.n(x0)} Y{self.n(y0)} F{self.rnd(100, 800)}")
        self.comp = True
        rad = min(w, h) * r.uniform(0.1, 0.45)
        pts = [
            f"G1 X{self.n(x0 + w - rad)}",
            f"G3 X{self.n(x0 + w)} Y{self.n(y0 + rad)} R{self.n(rad)}"
            if side == "G41"
            else f"G1 X{self.n(x0 + w)} Y{self.n(y0 + rad)}",
            f"G1 Y{self.n(y0 + h)}",
            f"G2 X{self.n(x0 + w / 2)} Y{self.n(y0 + h)} I{self.n(-w / 4)} J0"
            if r.random() < 0.5
            else f"G1 X{self.n(x0 + w / 2)}",
            f"G1 X{self.n(x0)}",
            f"G1 Y{self.n(y0)}",
        ]
        for text in pts:
            self.add(text)
            if r.random() < 0.015:  # a block LinuxCNC refuses under compensation
                self.add(
                    r.choice(
                        (
                            "G92 X0",
                            "G55",
                            "G81 X1 Y1 Z-1 R1",
                            "G64 P0.01",
                            "T2 M6",
                            "G43 H1",
                            "G53 G0 Z10",
                            "G28",
                            "G10 L20 P0 X0",
                            "G18",
                        )
                    )
                )
        self.add(f"G40 G1 X{self.n(x0 - 5)} Y{self.n(y0 - 5)}")
        self.comp = False

    def polyline(self) -> None:
        """A compensated open polyline of random turns, lines and R arcs (corner cases)."""
        import math

        r = self.r
        x, y, heading = r.uniform(-10, 10), r.uniform(-10, 10), r.uniform(0, 2 * math.pi)
        self.add(f"G0 X{self.n(x)} Y{self.n(y)}")
        ex, ey = x + 8 * math.cos(heading), y + 8 * math.sin(heading)
        self.add(f"{r.choice(('G41.1', 'G42.1'))} D{self.rnd(0.5, 3)} G1 X{self.n(ex)} Y{self.n(ey)}")
        x, y = x + 8 * math.cos(heading), y + 8 * math.sin(heading)
        for _ in range(r.randrange(2, 7)):
            heading += r.choice((r.uniform(-2.8, 2.8), r.uniform(-0.06, 0.06), math.pi / 2, -math.pi / 2))
            length = r.uniform(3, 20)
            x, y = x + length * math.cos(heading), y + length * math.sin(heading)
            if r.random() < 0.3:
                self.add(f"{r.choice(('G2', 'G3'))} X{self.n(x)} Y{self.n(y)} R{self.n(length * r.uniform(0.55, 2))}")
            else:
                self.add(f"G1 X{self.n(x)} Y{self.n(y)}")
        self.add(f"G40 G1 X{self.n(x + 5)} Y{self.n(y + 5)}")

    def lathe(self) -> None:
        """A compensated lathe profile in G18 (X, Z): ``G41.1/G42.1 D L`` with a tool orientation
        0–9 (the tip, not the nose centre, is programmed), entry by a line or an R arc, lines and R
        arcs, G40; now and then the L word outside G18 (an error)."""
        r = self.r
        x, z = r.uniform(5, 20), r.uniform(-5, 5)
        plane = "G18" if r.random() < 0.95 else "G17"
        self.add(f"{plane} G0 X{self.n(x)} Z{self.n(z)}")
        side = r.choice(("G41.1", "G42.1"))
        self.add(f"{side} D{self.rnd(0.4, 3)} L{r.randrange(10)}")
        self.comp = True
        for _ in range(r.randrange(2, 7)):
            nx, nz = x + r.uniform(-8, 8), z + r.uniform(4, 20)
            if r.random() < 0.35:
                chord = ((nx - x) ** 2 + (nz - z) ** 2) ** 0.5
                self.add(f"{r.choice(('G2', 'G3'))} X{self.n(nx)} Z{self.n(nz)} R{self.n(chord * r.uniform(0.55, 2))}")
            else:
                self.add(f"G1 X{self.n(nx)} Z{self.n(nz)}")
            x, z = nx, nz
        self.add("G40")
        self.add(f"G0 X{self.n(x + 5)}")
        self.add("G17")
        self.comp = False

    def feed_mode(self) -> None:
        """Moves in G95 (units per revolution: F × S, now and then S0 — an error) or G93 (inverse
        time: F on every feed move, now and then missing — an error), then back to G94."""
        r = self.r
        if r.random() < 0.5:
            speed = 0 if r.random() < 0.1 else r.randrange(100, 3000)
            self.add(f"S{speed} M3")
            self.add(f"G95 G1 X{self.rnd(-30, 30)} Y{self.rnd(-30, 30)} F{self.rnd(0.01, 0.3)}")
            self.add(f"G2 X{self.rnd(-30, 30)} Y{self.rnd(-30, 30)} R{self.rnd(45, 60)}")
        else:
            self.add(f"G93 G1 X{self.rnd(-30, 30)} Y{self.rnd(-30, 30)} F{r.uniform(1, 200):.3f}")
            self.add(f"G3 X{self.rnd(-30, 30)} Y{self.rnd(-30, 30)} R{self.rnd(45, 60)} F{r.uniform(1, 200):.3f}")
            if r.random() < 0.1:
                self.add(f"G1 X{self.rnd(-30, 30)}")
        self.add(f"G94 F{self.rnd(100, 600)}")

    def language(self) -> None:
        """A loop with incremental moves, or a subroutine called with arguments."""
        r = self.r
        label = 100 + len(self.lines)
        if r.random() < 0.5:
            self.add(f"o{label} repeat [{r.randrange(1, 4)}]")
            self.add(f"G91 G1 X{self.rnd(-3, 3)} Y{self.rnd(-3, 3)}")
            self.add("G90")
            self.add(f"o{label} endrepeat")
        else:
            self.add("#<i>=0")
            self.add(f"o{label} while [#<i> LT {r.randrange(1, 4)}]")
            self.add(f"G0 X[#<_x>+{self.rnd(1, 3)}] Y[#<i>*{self.rnd(1, 3)}]")
            self.add("#<i>=[#<i>+1]")
            self.add(f"o{label} endwhile")

    def probe_params(self) -> None:
        r = self.r
        choice = r.randrange(3)
        if choice == 0:
            self.add(f"G0 X[#<_x>+{self.rnd(1, 5)}] Y[#<_y>-{self.rnd(1, 5)}]")
        elif choice == 1:
            self.add("(DEBUG, at #<_x> #<_y> #<_z> abs #<_abs_x> tool #<_current_tool> cs #<_coord_system>)")
        else:
            self.add(f"#1=[#5221+#5222] G0 X[#1+{self.rnd(0, 3)}]")


def program(seed: int) -> str:
    """The text of random program ``seed`` (deterministic)."""
    g = _Gen(seed)
    r = g.r
    g.add("%")
    g.add(("G21" if g.metric else "G20") + " G17 G90 G94 G40 G49 G80")
    g.add(f"F{g.rnd(100, 600)}")
    features = [
        g.offsets, g.offsets, g.tool_change, g.cycle, g.contour, g.probe_params, g.polyline, g.language, g.lathe,
        g.feed_mode,
    ]
    for _ in range(r.randrange(3, 9)):
        r.choice(features)()
        if r.random() < 0.3:
            g.add(f"G0 X{g.rnd(-30, 30)} Y{g.rnd(-30, 30)} Z{g.rnd(0, 10)}")
    if r.random() < 0.05:
        g.add(r.choice(("G81 X1 Y1 Z-1", "G82 X1 Y1 Z-1 R1", "G83 X1 Y1 Z-1 R1", "G10 L2 P12 X1", "G92")))
    g.add("M2")
    g.add("%")
    numbered = [g.lines[0]]
    for i, line in enumerate(g.lines[1:-1], start=1):
        numbered.append(f"N{i * 10} {line}")
    numbered.append(g.lines[-1])
    return "\n".join(numbered) + "\n"
