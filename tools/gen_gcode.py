#!/usr/bin/env python3
"""Seeded random G-code programs in novanc's subset, for tools/compare_rs274.py
(docs/gcode.md "Agreement with LinuxCNC"). Every program sets G54 to X300 Y300 Z-400 so its
moves stay inside the travel, and ends with M30.

usage: gen_gcode.py OUTDIR COUNT [SEED]
"""
import math
import os
import random
import sys

TOOLS = [2, 4, 6, 13, 14, 15]  # T codes with tool data in the sample magazine
MILLS = [(13, 4.0), (14, 6.0), (15, 10.0)]  # end mills and their radii


def num(r, x, dec=3):
    s = f"{x:.{dec}f}".rstrip("0").rstrip(".")
    if s in ("-0", ""):
        s = "0"
    # Sometimes a bracket expression, sometimes a number without a decimal point.
    k = r.random()
    if k < 0.08:
        return f"[{s}+0]"
    if k < 0.12 and "." in s:
        return f"[{s}*2/2]"
    return s


class Gen:
    def __init__(self, seed):
        self.r = random.Random(seed)
        self.lines = []
        self.pos = [0.0, 0.0, 20.0]  # program coordinates, mm
        self.inch = False
        self.inc = False
        self.plane = 17

    def emit(self, s):
        self.lines.append(s)

    def coord(self, lo=-80, hi=80):
        return round(self.r.uniform(lo, hi), self.r.choice([0, 1, 2, 3]))

    def word(self, axis, v):
        i = "XYZ".index(axis)
        val = v - self.pos[i] if self.inc else v
        if self.inch:
            val /= 25.4
            return f"{axis}{num(self.r, val, 4)}"
        return f"{axis}{num(self.r, val)}"

    def goto(self, p, g):
        if any(v is None for v in self.pos):
            self.inc = False
            self.lines.append("G90")
            p = [20.0 if v is None else v for v in p]
            words = [self.word(a, p[i]) for i, a in enumerate("XYZ")]
            self.emit(f"{g} " + " ".join(words))
            self.pos = [self.rounded(v) for v in p]
            return
        words = [self.word(a, p[i]) for i, a in enumerate("XYZ") if self.r.random() < 0.8 or abs(p[i] - self.pos[i]) > 1e-9]
        if not words:
            words = [self.word("X", p[0])]
            p = [p[0], self.pos[1], self.pos[2]]
        else:
            q = list(self.pos)
            for w in words:
                pass
            for i, a in enumerate("XYZ"):
                if any(w.startswith(a) for w in words):
                    q[i] = self.rounded(p[i])
            p = q
        self.emit(f"{g} " + " ".join(words))
        self.pos = list(p)

    def rounded(self, v):
        # What the printed word carries (inches at 4 decimals).
        if self.inch:
            d = (v - 0) / 25.4
            return round(d, 4) * 25.4 if not self.inc else v
        return round(v, 3)

    def modes(self):
        r = self.r
        if r.random() < 0.3:
            self.inch = not self.inch
            self.emit("G20" if self.inch else "G21")
        if r.random() < 0.3:
            self.inc = not self.inc
            self.emit("G91" if self.inc else "G90")

    def linear(self):
        p = [self.coord(), self.coord(), self.coord(-60, 40)]
        g = self.r.choice(["G0", "G1", "G01", "G00"])
        self.goto(p, g)

    def arc(self):
        r = self.r
        plane = r.choice([17, 17, 18, 19])
        ax = {17: (0, 1, 2), 18: (2, 0, 1), 19: (1, 2, 0)}[plane]
        u, v, n = ax
        rad = round(r.uniform(2, 30), 2)
        a0 = r.uniform(0, 2 * math.pi)
        sweep = r.uniform(0.2, 6.2) * r.choice([1, -1])
        c = list(self.pos)
        c[u] = self.pos[u] - rad * math.cos(a0)
        c[v] = self.pos[v] - rad * math.sin(a0)
        e = list(self.pos)
        e[u] = round(c[u] + rad * math.cos(a0 + sweep), 3)
        e[v] = round(c[v] + rad * math.sin(a0 + sweep), 3)
        if r.random() < 0.3:
            e[n] = round(self.pos[n] + r.uniform(-5, 5), 3)
        if any(abs(x) > 120 for x in e[:2]) or not (-80 < e[2] < 60) or any(abs(x) > 120 for x in c[:2]) or not (-80 < c[2] < 60):
            return
        g = "G3" if sweep > 0 else "G2"
        k = 25.4 if self.inch else 1.0
        dec = 4 if self.inch else 3
        if r.random() < 0.4 and abs(sweep) < 2 * math.pi - 0.1:
            big = abs(sweep) > math.pi
            chord = math.hypot(e[u] - self.pos[u], e[v] - self.pos[v])
            if chord < 0.5 or abs(abs(sweep) - math.pi) < 0.05:
                return
            centre = f"R{'-' if big else ''}{rad / k:.{dec}f}"
            # R arcs: put the end exactly on the circle of radius rad.
        else:
            names = "IJK"
            centre = f"{names[min(u, v)]}{(c[min(u, v)] - self.pos[min(u, v)]) / k:.{dec}f} {names[max(u, v)]}{(c[max(u, v)] - self.pos[max(u, v)]) / k:.{dec}f}"
        if plane != self.plane:
            self.emit(f"G{plane}")
            self.plane = plane
        words = []
        for i, a in enumerate("XYZ"):
            if i != n or e[n] != self.pos[n]:
                words.append(self.word(a, e[i]))
        self.emit(f"{g} {' '.join(words)} {centre}")
        self.pos = e

    def offsets(self):
        r = self.r
        if r.random() < 0.5:
            p = r.randint(2, 6)
            self.emit(f"G10 L2 P{p} X{300 + r.randint(-50, 50)} Y{300 + r.randint(-50, 50)} Z{-400 + r.randint(-30, 30)}")
        else:
            p = r.randint(2, 6)
            self.emit(f"G10 L20 P{p} X{r.randint(-20, 20)} Y{r.randint(-20, 20)} Z{r.randint(-10, 10)}")
        # Move back to safe known state: G54.
        self.emit("G54")

    def tool(self):
        # rs274 2.9 moves the current Z in the wrong units when G43/G49 change under G20
        # after G43 under G21: keep tool changes in mm.
        if self.inch:
            self.emit("G21")
            self.inch = False
        t = self.r.choice(TOOLS)
        self.emit(f"T{t} M6")
        self.emit(self.r.choice([f"G43 H{t}", "G43", "G49"]))

    def cycle(self):
        r = self.r
        kind = r.choice(["G81", "G82", "G73", "G83", "G84", "G85", "G86", "G89"])
        ret = r.choice(["G98", "G99"])
        rr = round(r.uniform(0, 10), 1)
        z = round(rr - r.uniform(1, 20), 1)
        extra = ""
        if kind in ("G73", "G83"):
            extra = f" Q{round(r.uniform(0.5, 5), 1)}"
        if kind in ("G82", "G86", "G89"):
            extra += f" P{round(r.uniform(0, 1), 2)}"
        k = 25.4 if self.inch else 1.0
        if self.inc:
            self.emit("G90")
            self.inc = False
        if self.plane != 17:
            self.emit("G17")
            self.plane = 17
        if kind in ("G84", "G86"):
            self.emit("M3")
        self.emit(f"{ret} {kind} X{self.coord() / k:.3f} Y{self.coord() / k:.3f} Z{z / k:.4f} R{rr / k:.4f}{extra}")
        for _ in range(r.randint(0, 3)):
            self.emit(f"X{self.coord() / k:.3f} Y{self.coord() / k:.3f}")
        self.emit("G80")
        self.emit("G0 Z20" if not self.inch else "G0 Z0.8")
        self.pos = [None, None, 20.0 if not self.inch else 0.8 * 25.4]
        # Position unknown in XY after a cycle: go somewhere explicit.
        self.emit("G90")
        self.goto([self.coord(), self.coord(), self.pos[2]], "G0")

    def comp(self):
        r = self.r
        t, rad = r.choice(MILLS)
        if self.inc:
            self.emit("G90")
            self.inc = False
        if self.inch:
            self.emit("G21")
            self.inch = False
        if self.plane != 17:
            self.emit("G17")
            self.plane = 17
        w = round(r.uniform(30, 60), 1)
        h = round(r.uniform(30, 60), 1)
        cr = round(r.uniform(rad + 1, min(w, h) / 2 - 1), 1)
        x0, y0 = round(r.uniform(-60, 0), 1), round(r.uniform(-60, 0), 1)
        side = r.choice(["G41", "G42"])
        self.emit(f"T{t} M6")
        self.emit(f"G0 X{x0 - 20} Y{y0 - 20}")
        # A rounded rectangle (outside contour: G41 climbs CW? either side works for convex).
        pts = [
            f"{side} D{t} G1 X{x0 + cr} Y{y0} F300",
            f"G1 X{x0 + w - cr}",
            f"G3 X{x0 + w} Y{y0 + cr} R{cr}",
            f"G1 Y{y0 + h - cr}",
            f"G3 X{x0 + w - cr} Y{y0 + h} I{-cr} J0",
            f"G1 X{x0 + cr}",
            f"G3 X{x0} Y{y0 + h - cr} R{cr}",
            f"G1 Y{y0 + cr}",
            f"G3 X{x0 + cr} Y{y0} I{cr} J0",
            f"G1 X{x0 + cr + 5}",
            f"G40 G1 X{x0 + cr + 5} Y{y0 - 20}",
        ]
        if side == "G42":
            # The same contour; G42 puts the tool inside the CCW corners: keep it outside by
            # running it clockwise.
            pts = [
                f"{side} D{t} G1 X{x0} Y{y0 + cr} F300",
                f"G1 Y{y0 + h - cr}",
                f"G2 X{x0 + cr} Y{y0 + h} R{cr}",
                f"G1 X{x0 + w - cr}",
                f"G2 X{x0 + w} Y{y0 + h - cr} I0 J{-cr}",
                f"G1 Y{y0 + cr}",
                f"G2 X{x0 + w - cr} Y{y0} R{cr}",
                f"G1 X{x0 + cr}",
                f"G2 X{x0} Y{y0 + cr} I0 J{cr}",
                f"G1 Y{y0 + cr + 5}",
                f"G40 G1 X{x0 - 20} Y{y0 + cr + 5}",
            ]
        for i, p in enumerate(pts):
            self.emit(p)
            # Z-only moves and functions between compensated moves (LinuxCNC queues them).
            if 0 < i < len(pts) - 2 and r.random() < 0.25:
                self.emit(r.choice([f"G1 Z{round(r.uniform(-10, 5), 2)}", "M8", "M9", "G4 P0.1"]))
        self.pos = [None, None, self.pos[2]]
        self.goto([self.coord(), self.coord(), self.pos[2]], "G0")

    def sub(self):
        if self.plane != 17:
            self.emit("G17")
            self.plane = 17
        self.emit(f"M98 P{self.r.choice([100, 200])} L{self.r.randint(1, 3)}")
        self.pos = [None, None, None]
        self.emit("G90 G17 G21")
        self.inc, self.plane, self.inch = False, 17, False
        self.goto([self.coord(), self.coord(), self.coord(-40, 20)], "G0")

    def program(self):
        r = self.r
        self.emit("%")
        self.emit(f"O{r.randint(1000, 9999)} (generated)")
        self.emit("G21 G90 G17 G94 G40 G49 G80")
        self.emit("G10 L2 P1 X300 Y300 Z-400")
        self.emit("G54 F500 S1000 M3")
        self.emit("G0 X0 Y0 Z20")
        for _ in range(r.randint(5, 30)):
            k = r.random()
            if any(v is None for v in self.pos):
                self.goto([self.coord(), self.coord(), 20.0], "G0")
            if k < 0.15:
                self.modes()
            elif k < 0.45:
                self.linear()
            elif k < 0.7:
                self.arc()
            elif k < 0.76:
                self.offsets()
            elif k < 0.82:
                self.tool()
                self.emit("G0 Z20" if not self.inch else "G0 Z0.8")
                self.pos[2] = 20.0 if not self.inch else 0.8 * 25.4
                if self.inc:
                    self.emit("G90")
                    self.inc = False
            elif k < 0.9:
                self.cycle()
            elif k < 0.95:
                self.comp()
            else:
                self.sub()
        self.emit("G21 G90 G17 G49 G0 Z20")
        self.emit("M30")
        self.emit("O200")
        self.emit("G91 G0 X-3 Y2")
        self.emit("M98 P100 L2")
        self.emit("G90")
        self.emit("M99")
        self.emit("O100")
        self.emit("G91 G1 X2 Y1 F300")
        self.emit("G17 G2 X4 Y0 I2 J0")
        self.emit("G90")
        self.emit("M99")
        self.emit("%")
        return "\n".join(self.lines) + "\n"


def main():
    out, count = sys.argv[1], int(sys.argv[2])
    seed = int(sys.argv[3]) if len(sys.argv) > 3 else 1
    os.makedirs(out, exist_ok=True)
    for i in range(count):
        g = Gen(seed * 100_000 + i)
        with open(os.path.join(out, f"gen{seed}_{i:04d}.ngc"), "w") as f:
            f.write(g.program())


if __name__ == "__main__":
    main()
