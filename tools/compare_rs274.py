#!/usr/bin/env python3
"""Compare novanc's G-code reading with LinuxCNC 2.9's rs274 on programs (docs/gcode.md
"Agreement with LinuxCNC"). Development only: needs rs274 (Debian package linuxcnc-uspace)
and a built novanc; the test suite never runs this.

For each program: rs274 -g prints canonical calls in program coordinates; this script adds the
work offset, the tool length offset and the units to get machine millimetres, drops moves shorter
than half a pulse (0.0005 mm; 0.0013 mm where rs274 printed inches, its 4 decimals' step), and compares every move's kind and end point and every arc's centre and direction with
the blocks `novanc translate` prints, in the same order, to 0.001 mm. Where rs274 refuses a
program, novanc must refuse it.

Spirals: an I J K arc whose end radius differs from its start radius by more than 0.0265 mm is
split into the arcs novanc cuts it as (docs/gcode.md "Arcs"), each ending on LinuxCNC's spiral.

Moves near the pulse: where the move-by-move comparison fails, the program is compared again as
a path (compare_as_paths): each run of straight moves shorter than 0.02 mm is a polyline, the
lists must meet again at an agreeing straight move or arc after it, and every point of each
polyline must lie within 0.003 mm of the other's. Printed as "agree as a path".

Splines: rs274 prints a G5, G5.1 or G5.2 … G5.3 curve only as `NURBS_FEED(n, ...)` (n its
control points), without its points. Such a line (or a run of them) matches the run of novanc
feed moves (its chords, one at least per spline) that ends where the next rs274 move starts:
the run stops at the first novanc move that agrees with rs274's next move. An arc after it must
start on its own circle there. The curves themselves are checked by novanc's unit tests.

Lathes (--machine a lathe description, `kind lathe`): novanc translate --machine FILE lists
channel 1's blocks, X a radius, the tool post starting at the top of both travels. rs274 is
given the same start (a `G53 G0 X Z` line before the program, its move not compared) and
novanc's power-on modes G18 G21 G7 (docs/lathe-gcode.md "Initial modes"), the
description's tools of channel 1 as its tool table (nose radius as D, tip as the orientation Q,
offsets X Z), and no quill-up tool change.

Rotary axes (--rotary): straight moves also compare A, B and C (degrees; rs274's standalone
configuration has them unwrapped and without offsets, so the --machine description should
give `a rotary travel ...`, `b ...`, `c ...` without `wrap`). A move of the rotary axes alone
counts as a move.

usage: compare_rs274.py [--novanc BIN] [--golden DIR] [--machine FILE] [--rotary] PROG.ngc...
  --machine FILE a mill description for novanc translate; its `remap M6 ...` line goes to
                 rs274's INI as REMAP=M6 ...; or a lathe's (above)
  --rotary       compare A, B and C on straight moves (above)
  --golden DIR   also write DIR/NAME.ngc and DIR/NAME.expect (the rs274 moves in machine mm,
                 or 'ERROR message') for tests/gcode_golden.rs
Exit 0 if every program agrees.
"""
import math
import os
import re
import subprocess
import sys
import tempfile

# One level of recursion for each run of splines in a program (compare).
sys.setrecursionlimit(100000)

ROOT = os.path.dirname(os.path.dirname(os.path.abspath(__file__)))
TOL = 0.001 + 1e-6


# --rotary: straight moves carry A, B and C.
ROTARY = [False]

# A lathe description's channel 1 (--machine): {"home": (x, z), "tools": [(n, radius, tip, x, z)]}.
LATHE = [None]


def read_lathe(path):
    """Channel 1 of a lathe description, or None for a mill's."""
    if path is None:
        return None
    lines = [line.split("#")[0].split() for line in open(path)]
    if not any(f[:2] == ["kind", "lathe"] for f in lines):
        return None
    home = [0.0, 0.0]
    tools = []
    channels = 0
    for f in lines:
        if not f:
            continue
        if f[0] == "channel":
            channels += 1
        if channels != 1:
            continue
        if f[0] in ("x", "z") and len(f) >= 4 and f[1] == "travel":
            home["xz".index(f[0])] = float(f[3])
        elif f[0] == "tool":
            w = dict(zip(f[2::2], f[3::2]))
            off = f[f.index("offset") + 1:f.index("offset") + 3] if "offset" in f else ["0", "0"]
            tools.append((int(f[1]), float(w.get("radius", 0)), int(w.get("tip", 0)), float(off[0]), float(off[1])))
    return {"home": tuple(home), "tools": tools}


# novanc's tip positions (Fanuc's chart, +X up) as LinuxCNC's orientations of the same tool: its
# chart is drawn with +X down (interp_queue.cc's latheorigin: orientation 3 puts the tip at
# +X, -Z of the nose centre, which is Fanuc's tip 2).
LINUXCNC_Q = [0, 4, 3, 2, 1, 5, 8, 7, 6, 9]


def tool_table():
    """The sample magazine as an rs274 tool table (rs274 reads it in inches); on a lathe, the
    description's tools of channel 1."""
    if LATHE[0]:
        return "".join(f"T{n} P{n} X{x / 25.4:.9f} Z{z / 25.4:.9f} D{2 * r / 25.4:.9f} Q{LINUXCNC_Q[tip]} ;\n"
                       for n, r, tip, x, z in LATHE[0]["tools"])
    tools = {}
    for line in open(os.path.join(ROOT, "tooldata/tools.tt")):
        f = line.split(";")[0].split()
        if len(f) >= 4:
            tools[f[0]] = (float(f[2]), float(f[3]))
    out = []
    for line in open(os.path.join(ROOT, "tooldata/magazine.tc")):
        f = line.split("#")[0].split(";")[0].split()
        if len(f) >= 2 and f[0].upper().startswith("T") and f[1] in tools:
            t = int(f[0][1:])
            dia, setlen = tools[f[1]]
            out.append(f"T{t} P{t} Z{setlen / 25.4:.9f} D{dia / 25.4:.9f} ;")
    return "\n".join(out) + "\n"


NUM = r"(-?\d+(?:\.\d+)?)"


MACHINE = [None]


def remap_lines():
    """The REMAP lines of the --machine description (its `remap M6 ...` line, LinuxCNC's
    `REMAP=M6 ...`)."""
    if not MACHINE[0]:
        return ""
    out = ""
    for line in open(MACHINE[0]):
        f = line.split("#")[0].split()
        if f and f[0] == "remap":
            out += "REMAP=" + " ".join(f[1:]) + "\n"
    return out


def rs274_ini(prog, tmp):
    """An INI for rs274: M6 retracts Z to machine 0 first (TOOL_CHANGE_QUILL_UP, novanc's
    tool change), subroutines are found beside the program and in programs/, and M6 is
    remapped as the --machine description says."""
    path = os.path.join(tmp, "novanc.ini")
    dirs = [os.path.dirname(os.path.abspath(prog)), os.path.join(ROOT, "programs")]
    with open(path, "w") as f:
        quill = "" if LATHE[0] else "TOOL_CHANGE_QUILL_UP = 1\n"
        f.write("[EMCIO]\n%s[RS274NGC]\nSUBROUTINE_PATH = %s\n" % (quill, ":".join(dirs)))
        f.write(remap_lines())
    return path


def rot(x, y, deg):
    a = math.radians(deg)
    return x * math.cos(a) - y * math.sin(a), x * math.sin(a) + y * math.cos(a)


def turned(sp, e, c, u, v, ccw, n):
    """The angle an arc of n turns from sp to e about c turns (radians; a full turn when the
    ends meet), in the plane of axes u, v."""
    a0 = math.atan2(sp[v] - c[v], sp[u] - c[u])
    a1 = math.atan2(e[v] - c[v], e[u] - c[u])
    d = (a1 - a0) if ccw else (a0 - a1)
    while d <= 1e-12:
        d += 2 * math.pi
    while d > 2 * math.pi + 1e-12:
        d -= 2 * math.pi
    return d + 2 * math.pi * (n - 1)


def rs274_moves(prog, tbl):
    """(moves, error): moves as tuples ('R'|'F'|'P', x, y, z) or ('A', ccw, plane, x, y, z, cx, cy, cz)."""
    with tempfile.TemporaryDirectory() as tmp:
        env = dict(os.environ, HOME=tmp)
        ini = rs274_ini(prog, tmp)
        run = os.path.abspath(prog)
        if LATHE[0]:
            # The lathe's start, the top of both travels (in the program's folder, for its
            # subroutines).
            hx, hz = LATHE[0]["home"]
            run = os.path.join(tmp, os.path.basename(prog))
            with open(prog, errors="replace") as src, open(run, "w") as dst:
                dst.write(f"G18 G21 G8\nG53 G0 X{hx} Z{hz}\nG7\n" + src.read())
        p = subprocess.run(["rs274", "-i", ini, "-t", tbl, "-g", run], capture_output=True, text=True,
                           timeout=600, env=env, cwd=tmp)
    factor = 1.0
    g5x = [0.0, 0.0, 0.0]
    g92 = [0.0, 0.0, 0.0]
    # --rotary: the rotary axes' offsets (degrees, added as LinuxCNC's canon adds them).
    g5x_abc = [0.0, 0.0, 0.0]
    g92_abc = [0.0, 0.0, 0.0]
    rotation = 0.0
    tlo = [0.0, 0.0, 0.0]
    moves = []
    last = [0.0, 0.0, 0.0]
    kept = [[0.0, 0.0, 0.0]]
    # After a spline, where it ended in X and Y is not printed (its Z is the Z before it).
    after_spline = False

    def machine(x, y, z):
        x, y, z = x * factor + g92[0], y * factor + g92[1], z * factor + g92[2]
        x, y = rot(x, y, rotation)
        return [x + g5x[0] + tlo[0], y + g5x[1] + tlo[1], z + g5x[2] + tlo[2]]

    printed = set(p.stdout.splitlines())
    def arc_to(at, c, ccw, plane, allowance):
        """An arc from the last move's end to program point `at` about program centre `c`."""
        nonlocal last
        normal = {"XY": 2, "XZ": 1, "YZ": 0}[plane]
        cc = list(c)
        cc[normal] = at[normal]
        me = machine(*at)
        mc = machine(*cc)
        mc[normal] = last[normal]
        moves.append(("A", ccw, plane, *me, *mc))
        inch.append(allowance)
        last = me

    for line in (p.stdout + p.stderr).splitlines():
        m = re.match(r"\s*\d+ N[.\d]*\s*([A-Z][A-Z0-9_]*)\((.*)\)\s*$", line)
        if not m:
            if line.strip() in ("executing", ""):
                continue
            if line in printed:
                # (PRINT, ...) and (DEBUG, ...) output: rs274 prints errors on stderr.
                continue
            return moves, line.strip()
        name, args = m.group(1), m.group(2)
        vals = [float(v) for v in re.findall(r"-?\d+\.\d+|-?\d+", args)] if name not in ("COMMENT", "MESSAGE") else []
        if name == "USE_LENGTH_UNITS":
            new = 25.4 if "INCHES" in args else 1.0
            # The last programmed point, in the units rs274 prints from now on.
            last_prog[0] = [v * factor / new for v in last_prog[0]]
            factor = new
        elif name == "SET_G5X_OFFSET":
            g5x = [v * factor for v in vals[1:4]]
            g5x_abc = list(vals[4:7])
        elif name == "SET_G92_OFFSET":
            g92 = [v * factor for v in vals[:3]]
            g92_abc = list(vals[3:6])
        elif name == "SET_XY_ROTATION":
            rotation = vals[0]
        elif name == "USE_TOOL_LENGTH_OFFSET":
            # Printed in the program's units.
            tlo = [v * factor for v in vals[:3]]
        elif name in ("STRAIGHT_TRAVERSE", "STRAIGHT_FEED", "STRAIGHT_PROBE"):
            e = machine(vals[0], vals[1], vals[2])
            if ROTARY[0]:
                # A B C in degrees, whatever the length units, with their offsets.
                e = e + [vals[3 + r] + g5x_abc[r] + g92_abc[r] for r in range(3)]
            # Shorter than half a pulse from the last move kept (rs274's inch rounding, or CAM
            # output in steps below a pulse): novanc cannot move it. In inches rs274 prints 4
            # decimals: a move below 0.00127 mm is its rounding.
            least = 0.0005 if factor == 1.0 else 0.0013
            if len(kept[0]) < len(e):
                kept[0] = kept[0] + [0.0] * (len(e) - len(kept[0]))
            if after_spline or max(abs(e[i] - kept[0][i]) for i in range(len(e))) >= least or name == "STRAIGHT_PROBE":
                kind = {"STRAIGHT_TRAVERSE": "R", "STRAIGHT_FEED": "F", "STRAIGHT_PROBE": "P"}[name]
                moves.append((kind, *e))
                inch.append(factor != 1.0)
                kept[0] = e
            last = e
            after_spline = False
        elif name == "RIGID_TAP":
            # G33.1: in to the point at the spindle's pitch, and out again to where it began
            # (novanc prints the two feed moves, with the spindle's stops and reversals).
            e = machine(vals[0], vals[1], vals[2])
            start = last
            for p in (e, start):
                moves.append(("F", *p))
                inch.append(factor != 1.0)
            kept[0] = start
        elif name == "ARC_FEED":
            fe, se, fa, sa, turns, ae = vals[:6]
            plane = current_plane[0]
            if plane == "XY":
                e, c = [fe, se, ae], [fa, sa, 0.0]
            elif plane == "XZ":
                e, c = [se, ae, fe], [sa, 0.0, fa]
            else:
                e, c = [ae, fe, se], [0.0, fa, sa]
            normal = {"XY": 2, "XZ": 1, "YZ": 0}[plane]
            ccw = int(turns > 0)
            n = int(abs(turns))
            u, v = {"XY": (0, 1), "XZ": (2, 0), "YZ": (1, 2)}[plane]
            sp = last_prog[0]
            r0 = math.hypot(sp[u] - c[u], sp[v] - c[v])
            r1 = math.hypot(e[u] - c[u], e[v] - c[v])
            # (After a spline the arc's start is not printed: it is not split.)
            if not after_spline and abs(r1 - r0) * factor > SPIRAL_WHOLE_MM:
                # A spiral wider than novanc's pulse core turns: novanc cuts it as arcs about
                # the same centre whose ends are on LinuxCNC's spiral (radius and normal axis
                # in proportion to the angle): split rs274's arc at the same points.
                a0 = math.atan2(sp[v] - c[v], sp[u] - c[u])
                total = turned(sp, e, c, u, v, ccw, n)
                pieces = int(max(math.ceil(abs(r1 - r0) * factor / SPIRAL_STEP_MM), math.ceil(total / math.pi)))
                for k in range(1, pieces):
                    f = k / pieces
                    a = a0 + (1 if ccw else -1) * f * total
                    r = r0 + f * (r1 - r0)
                    at = list(sp)
                    at[u] = c[u] + r * math.cos(a)
                    at[v] = c[v] + r * math.sin(a)
                    at[normal] = sp[normal] + f * (e[normal] - sp[normal])
                    arc_to(at, c, ccw, plane, factor != 1.0)
                n = 1
            if n > 1:
                # Whole turns first, the normal axis shared out by angle (as novanc splits them).
                total = turned(sp, e, c, u, v, ccw, n)
                step = (e[normal] - sp[normal]) * 2 * math.pi / total
                at = list(sp)
                for _ in range(n - 1):
                    at[normal] += step
                    # Rebuilt from rs274's printed centre: wider allowance (see "turns").
                    arc_to(at, c, ccw, plane, "turn")
            arc_to(e, c, ccw, plane, factor != 1.0)
            kept[0] = last
            after_spline = False
        elif name == "NURBS_FEED":
            # The curve's points are not printed: where it ends is unknown here.
            moves.append(("S", int(vals[0])))
            inch.append(False)
            after_spline = True
        elif name == "SELECT_PLANE":
            current_plane[0] = {"CANON_PLANE_XY": "XY", "CANON_PLANE_XZ": "XZ", "CANON_PLANE_YZ": "YZ"}[args.strip()]
        if name in ("STRAIGHT_TRAVERSE", "STRAIGHT_FEED", "STRAIGHT_PROBE"):
            last_prog[0] = vals[:3]
        elif name == "ARC_FEED":
            last_prog[0] = e
    if LATHE[0] and moves:
        # The start line's move.
        del moves[0], inch[0]
    return moves, None


last_prog = [[0.0, 0.0, 0.0]]
# Spirals (src/gcode/geom.rs): novanc cuts one whole up to this radius difference (mm), beyond
# it in pieces changing the radius by at most SPIRAL_STEP_MM and turning at most half a turn.
SPIRAL_WHOLE_MM = 0.0265
SPIRAL_STEP_MM = 0.02
current_plane = ["XY"]
# Per rs274 move: whether it was printed in inches (4 decimals = 0.00127 mm).
inch = []


def novanc_moves(prog, novanc):
    machine = ["--machine", MACHINE[0]] if MACHINE[0] else []
    p = subprocess.run([novanc, "translate", prog] + machine, capture_output=True, text=True, timeout=600)
    if p.returncode != 0:
        return [], p.stderr.strip() or "refused"
    moves = []
    pos = [LATHE[0]["home"][0], 0.0, LATHE[0]["home"][1]] if LATHE[0] else [0.0, 0.0, 0.0]
    abc = [0.0, 0.0, 0.0]
    g = None
    plane = "XY"
    for line in p.stdout.splitlines():
        words = dict()
        gs = []
        for w in line.split():
            if w[0] == "G":
                gs.append(38 if w.startswith("G38") else int(w[1:]))
            elif w[0] == "M":
                continue
            else:
                words[w[0]] = float(w[1:]) if w[1:] else 0.0
        for x in gs:
            if x in (17, 18, 19):
                plane = {17: "XY", 18: "XZ", 19: "YZ"}[x]
            elif x in (0, 1, 2, 3, 38):
                g = x
            elif x == 33:
                # A thread pass: a feed move (rs274's STRAIGHT_FEED under spindle sync).
                g = 1
            elif x == 4:
                pass
        if 4 in gs or not any(k in words for k in ("XYZABC" if ROTARY[0] else "XYZ")):
            continue
        start = list(pos)
        for i, a in enumerate("XYZ"):
            if a in words:
                pos[i] = words[a]
        for i, a in enumerate("ABC"):
            if a in words:
                abc[i] = words[a]
        if g in (0, 1, 38):
            moves.append(({0: "R", 1: "F", 38: "P"}[g], *pos, *(abc if ROTARY[0] else [])))
        else:
            c = [start[0] + words.get("I", 0.0), start[1] + words.get("J", 0.0), start[2] + words.get("K", 0.0)]
            normal = {"XY": 2, "XZ": 1, "YZ": 0}[plane]
            c[normal] = start[normal]
            moves.append(("A", int(g == 3), plane, *pos, *c))
    return moves, None


def fmt(m):
    if m[0] == "S":
        return "S %d" % m[1]
    if m[0] == "A":
        return "A%d %s %.4f %.4f %.4f %.4f %.4f %.4f" % m[1:]
    return m[0] + "".join(" %.4f" % v for v in m[1:])


def agrees(x, y, tol=TOL):
    """Whether rs274 move x and novanc move y are the same move (kind, direction, numbers; an
    arc centre's coordinate along the plane's normal means nothing and is not compared)."""
    if x[0] != y[0] or (x[0] == "A" and (x[1] != y[1] or x[2] != y[2])):
        return False
    nums_x = [v for v in x if isinstance(v, float)]
    nums_y = [v for v in y if isinstance(v, float)]
    if x[0] == "A":
        skip = 3 + {"XY": 2, "XZ": 1, "YZ": 0}[x[2]]
        del nums_x[skip], nums_y[skip]
    return all(abs(p - q) <= tol + (0.0006 if x[0] == "A" else 0.0) for p, q in zip(nums_x, nums_y))


def tol_of(i):
    """The allowance for rs274 move i: wider where rs274 printed inches, wider still for the
    whole turns of a multi-turn arc rebuilt from rs274's printed centre."""
    if i < len(inch) and inch[i] == "turn":
        return TOL + 0.01
    return TOL + (0.00127 if i < len(inch) and inch[i] else 0.0)


def end_of(m):
    """Where a novanc move ends."""
    return list(m[3:6] if m[0] == "A" else m[1:4])


def spline_runs(a, i, b, j):
    """The ways the splines a[i:i+c] (c consecutive NURBS_FEED) can match novanc's moves from
    b[j]: (c, [(n, skip)...], error). A run is novanc's feed moves b[j:j+n], at least one per
    spline, ending where the next novanc move agrees with rs274's next move a[i+c]; skip is 1
    when that next move is one novanc did not make (no length: it ends where the run ends)."""
    c = 0
    while i + c < len(a) and a[i + c][0] == "S":
        c += 1
    m = 0
    while j + m < len(b) and b[j + m][0] in ("F", "A"):
        m += 1
    if m < c:
        return c, [], f"move {j + 1}: rs274 has {c} spline(s) here, novanc {m} feed moves"
    if i + c == len(a):
        return c, [(m, 0)], None
    nxt = a[i + c]
    tol = TOL + (0.00127 if inch[i + c] else 0.0)
    runs = [(n, 0) for n in range(c, m + 1) if j + n < len(b) and agrees(nxt, b[j + n], tol)]
    if nxt[0] != "A" and all(abs(nxt[1 + k] - end_of(b[j + m - 1])[k]) <= tol for k in range(3)):
        runs.append((m, 1))
    if not runs:
        return c, [], f"move {j + 1}: no run of novanc's feed moves after rs274's {c} spline(s) is followed by rs274's next move {fmt(nxt)}"
    return c, runs, None


def on_circle(start, arc):
    """Whether an rs274 arc starts on its own circle at `start` (the end of a spline run)."""
    normal = {"XY": 2, "XZ": 1, "YZ": 0}[arc[2]]
    u, v = [k for k in range(3) if k != normal]
    end, centre = arc[3:6], arc[6:9]
    r0 = math.hypot(start[u] - centre[u], start[v] - centre[v])
    r1 = math.hypot(end[u] - centre[u], end[v] - centre[v])
    return abs(r0 - r1) <= 0.03


def one_pulse(prev, y):
    """Whether novanc move `y` is a straight move of at most one pulse from `prev`: where
    rs274 drops a move shorter than half a pulse, novanc may still round its ends a pulse
    apart and make it."""
    return y[0] in "RF" and prev is not None and all(abs(y[1 + k] - prev[k]) <= 0.0015 for k in range(3))


def resync(a, b, i, j, span=60, step=0.01):
    """Where rs274 printed inches (a 0.0001 in grid) over a run of tiny straight moves, the two
    lists keep different subsets of them. Finds the next pair of equal end points within
    `span` moves of each, every move skipped being a straight move of the same kind shorter
    than `step` mm, and returns their indices after it (or None)."""
    if not (i < len(inch) and inch[i]):
        return None
    kind = a[i][0]
    if kind not in "RF" or b[j][0] != kind:
        return None

    def short(lst, n):
        if n == 0 or lst[n][0] != kind or lst[n - 1][0] not in "RF":
            return False
        return all(abs(lst[n][1 + q] - lst[n - 1][1 + q]) <= step for q in range(3))

    for di in range(span):
        ii = i + di
        if ii >= len(a) or (di and not short(a, ii)):
            break
        for dj in range(span):
            jj = j + dj
            if jj >= len(b) or (dj and not short(b, jj)):
                break
            if a[ii][0] == b[jj][0] and all(abs(a[ii][1 + q] - b[jj][1 + q]) <= TOL + 0.00127 for q in range(3)):
                return ii + 1, jj + 1
    return None


def compare(a, b):
    """None if rs274's moves a agree with novanc's moves b, else a description of the first
    difference. A run of splines in a matches a run of novanc's feed moves (spline_runs; where
    several runs could, the one with which the rest agrees). novanc's one departure in canned
    cycles (docs/gcode.md "Canned cycles"): where rs274 rises diagonally to the clear level while
    crossing to the next hole, novanc rises straight first, then crosses."""
    failed = {}

    def walk(i, j):
        while i < len(a):
            x = a[i]
            if x[0] == "S":
                if (i, j) in failed:
                    return failed[(i, j)]
                c, runs, err = spline_runs(a, i, b, j)
                for n, skip in runs:
                    nxt = a[i + c + skip] if i + c + skip < len(a) else None
                    if nxt is not None and nxt[0] == "A" and not on_circle(end_of(b[j + n - 1]), nxt):
                        err = err or f"move {j + n + 1}: the spline ends at {end_of(b[j + n - 1])}, off the circle of rs274's next arc {fmt(nxt)}"
                        continue
                    e = walk(i + c + skip, j + n)
                    if e is None:
                        return None
                    err = err or e
                failed[(i, j)] = err
                return err
            if j >= len(b):
                break
            if (x[0] == "R" and j + 1 < len(b) and b[j][0] == "R" and b[j + 1][0] == "R" and j > 0
                    and b[j - 1][0] != "A"):
                p, q, up = b[j - 1][1:4], x[1:4], b[j][1:4]
                moved = [k for k in range(3) if abs(up[k] - p[k]) > TOL]
                if (len(moved) == 1 and abs(up[moved[0]] - q[moved[0]]) <= TOL and q[moved[0]] > p[moved[0]]
                        and all(abs(b[j + 1][1 + k] - q[k]) <= TOL for k in range(3))):
                    i, j = i + 1, j + 2
                    continue
            if not agrees(x, b[j], tol_of(i)):
                prev_b = end_of(b[j - 1]) if j > 0 else None
                prev_a = (end_of(a[i - 1]) if a[i - 1][0] != "S" else None) if i > 0 else None
                # Both may have a sub-pulse move here: skip the one after which the lists
                # agree again (novanc's first), else novanc's, else rs274's.
                skip_b = one_pulse(prev_b, b[j])
                skip_a = one_pulse(prev_a, x)
                if skip_b and skip_a and j + 1 < len(b) and not agrees(x, b[j + 1], tol_of(i)):
                    if i + 1 < len(a) and agrees(a[i + 1], b[j], tol_of(i + 1)):
                        skip_b = False
                if skip_b:
                    j += 1
                    continue
                if skip_a:
                    i += 1
                    continue
                k = resync(a, b, i, j)
                if k:
                    i, j = k
                    continue
                return f"move {j + 1}: rs274 {fmt(x)}, novanc {fmt(b[j])}"
            i, j = i + 1, j + 1
        while j < len(b) and j > 0 and one_pulse(end_of(b[j - 1]), b[j]):
            j += 1
        if i < len(a) or j < len(b):
            return f"rs274 has {len(a)} moves, novanc {len(b)} (they part after novanc's move {j})"
        return None

    return walk(0, 0)


# Runs of straight moves shorter than this (mm) are compared as paths (compare_as_paths).
RUN_STEP = 0.02
# How far a point of one run may lie from the other run's path (mm): a pulse and rs274's
# 4-decimal inch rounding (1.27 um), with room.
RUN_TOL = 0.003


def runs_of(lst):
    """The moves of lst with every run of straight moves of one kind, each shorter than
    RUN_STEP, folded into one item ("T", kind, points): the point before the run, then
    each move's end."""
    out = []
    prev = None
    k = 0
    while k < len(lst):
        m = lst[k]
        run = [prev] if prev is not None else []
        n = k
        while (n < len(lst) and lst[n][0] in "RF" and lst[n][0] == m[0] and prev is not None
               and max(abs(lst[n][1 + q] - run[-1][q]) for q in range(3)) < RUN_STEP):
            run.append(list(lst[n][1:4]))
            n += 1
        if n > k:
            out.append(("T", m[0], run))
            prev = run[-1]
            k = n
        else:
            out.append(m)
            prev = end_of(m) if m[0] != "S" else None
            k += 1
    return out


def seg_dist(p, a, b):
    """The distance from point p to the segment a-b."""
    d = [b[q] - a[q] for q in range(3)]
    dd = sum(v * v for v in d)
    t = 0.0 if dd == 0 else max(0.0, min(1.0, sum((p[q] - a[q]) * d[q] for q in range(3)) / dd))
    return math.sqrt(sum((p[q] - a[q] - t * d[q]) ** 2 for q in range(3)))


def path_gap(pts, other):
    """The farthest any point of pts lies from the path `other` (both in order: each point is
    looked for near where the last one was found)."""
    worst = 0.0
    w = 0
    for p in pts:
        lo, hi = max(0, w - 50), min(len(other) - 1, w + 400)
        if len(other) == 1:
            best, at = math.dist(p, other[0]), 0
        else:
            best, at = min((seg_dist(p, other[q], other[q + 1]), q) for q in range(lo, max(lo + 1, hi)))
        worst = max(worst, best)
        w = at
    return worst


def compare_as_paths(a, b):
    """None if rs274's moves a and novanc's b agree once every run of short straight moves is
    compared as a path (same ends, each point within RUN_TOL of the other's path), else why.
    For programs whose moves are near the pulse (rs274's listing cannot pair them move by
    move: it drops moves under half a pulse, prints inches to 2.54 um, and novanc rounds each
    end to a pulse). Not for splines."""
    if any(m[0] == "S" for m in a):
        return "splines"
    ra, rb = runs_of(a), runs_of(b)
    tol = TOL + (0.00127 if any(inch) else 0.0)

    def points(items):
        out = []
        for m in items:
            out.extend(m[2][1:] if m[0] == "T" else [end_of(m)])
        return out

    def anchor(i, j, span=60):
        # The nearest pair of straight moves or arcs that agree after (i, j): where the two
        # lists meet again after runs that the 0.02 mm limit cut in different places.
        for total in range(1, 2 * span):
            for di in range(max(0, total - span), min(total, span) + 1):
                ii, jj = i + di, j + total - di
                if ii < len(ra) and jj < len(rb) and ra[ii][0] != "T" and agrees(ra[ii], rb[jj], tol):
                    return ii, jj
        return None

    i = j = 0
    start = None
    while i < len(ra) and j < len(rb):
        x, y = ra[i], rb[j]
        if x[0] != "T" and y[0] != "T" and agrees(x, y, tol):
            start = end_of(x)
            i, j = i + 1, j + 1
            continue
        if (x[0] == "T" and y[0] == "T" and x[1] == y[1] and start is not None
                and all(abs(x[2][-1][q] - y[2][-1][q]) <= tol for q in range(3))
                and max(path_gap(x[2], y[2]), path_gap(y[2], x[2])) <= RUN_TOL):
            start = x[2][-1]
            i, j = i + 1, j + 1
            continue
        k = anchor(i, j)
        if k is None and start is not None:
            break  # the rest, as a path (below)
        if k is None or start is None:
            return f"item {i + 1}: rs274 {fmt(x) if x[0] != 'T' else 'a run'}, novanc {fmt(y) if y[0] != 'T' else 'a run'}"
        pa = [start] + points(ra[i:k[0] + 1])
        pb = [start] + points(rb[j:k[1] + 1])
        gap = max(path_gap(pa, pb), path_gap(pb, pa))
        if gap > RUN_TOL:
            return f"item {i + 1}: {len(pa) - 1} and {len(pb) - 1} moves, {gap:.4f} mm apart"
        start = end_of(ra[k[0]])
        i, j = k[0] + 1, k[1] + 1
    if i < len(ra) or j < len(rb):
        pa = [start] + points(ra[i:])
        pb = [start] + points(rb[j:])
        if start is None or math.dist(pa[-1], pb[-1]) > tol or max(path_gap(pa, pb), path_gap(pb, pa)) > RUN_TOL:
            return f"{len(ra)} moves and runs in rs274, {len(rb)} in novanc, apart at the end"
    return None


def main(argv):
    novanc = os.path.join(ROOT, "target/release/novanc")
    if os.environ.get("CARGO_TARGET_DIR"):
        novanc = os.path.join(os.environ["CARGO_TARGET_DIR"], "release/novanc")
    golden = None
    progs = []
    it = iter(argv)
    for a in it:
        if a == "--novanc":
            novanc = next(it)
        elif a == "--golden":
            golden = next(it)
        elif a == "--machine":
            MACHINE[0] = next(it)
            LATHE[0] = read_lathe(MACHINE[0])
        elif a == "--rotary":
            ROTARY[0] = True
        else:
            progs.append(a)
    with tempfile.NamedTemporaryFile("w", suffix=".tbl", delete=False) as f:
        f.write(tool_table())
        tbl = f.name
    bad = 0
    total_moves = 0
    refused = 0
    for prog in progs:
        current_plane[0] = "XZ" if LATHE[0] else "XY"
        last_prog[0] = [0.0, 0.0, 0.0]
        inch.clear()
        ref, ref_err = rs274_moves(prog, tbl)
        got, got_err = novanc_moves(prog, novanc)
        name = os.path.basename(prog)
        if ref_err:
            if got_err:
                refused += 1
                print(f"ok   {name}: both refuse (rs274: {ref_err}; novanc: {got_err})")
            else:
                bad += 1
                print(f"FAIL {name}: rs274 refuses ({ref_err}), novanc accepts")
        elif got_err:
            print(f"note {name}: novanc refuses ({got_err}), rs274 accepts {len(ref)} moves")
        else:
            d = compare(ref, got)
            paths = d and compare_as_paths(ref, got) is None
            if d and not paths:
                bad += 1
                print(f"FAIL {name}: {d}")
            elif paths:
                total_moves += len(ref)
                print(f"ok   {name}: {len(ref)} moves agree as a path (move by move: {d}; runs of "
                      f"straight moves under {RUN_STEP} mm compared as paths, within {RUN_TOL} mm)")
            else:
                total_moves += len(ref)
                splines = sum(1 for m in ref if m[0] == "S")
                also = f" ({splines} of them splines)" if splines else ""
                print(f"ok   {name}: {len(ref)} moves agree{also}")
        if golden and not (got_err and not ref_err) and not (ref_err is None and compare(ref, got)):
            base = os.path.join(golden, os.path.splitext(name)[0])
            if not os.path.exists(base + ".ngc") or not os.path.samefile(prog, base + ".ngc"):
                # (Opened for writing, the program itself would be emptied first.)
                with open(prog) as src, open(base + ".ngc", "w") as dst:
                    dst.write(src.read())
            with open(base + ".expect", "w") as out:
                if ref_err:
                    out.write("ERROR " + ref_err + "\n")
                else:
                    out.write("# rs274 moves in machine mm: kind, end X Y Z (arcs: A0 cw / A1 ccw, plane,\n")
                    out.write("# end, centre), then the tolerance in mm (wider where rs274 printed inches)\n")
                    out.write("# (S n: a spline of n control points, a run of novanc feed moves)\n")
                    for i, m in enumerate(ref):
                        tol = TOL + (0.0006 if m[0] == "A" else 0.0) + (0.00127 if inch[i] else 0.0)
                        out.write(f"{fmt(m)} {tol:.5f}\n")
    os.unlink(tbl)
    print(f"{len(progs)} programs: {len(progs) - bad} agree ({refused} refused by both), {bad} differ; {total_moves} moves compared")
    return 1 if bad else 0


if __name__ == "__main__":
    sys.exit(main(sys.argv[1:]))
