#!/usr/bin/env python3
"""Compare novanc's G-code reading with LinuxCNC 2.9's rs274 on programs (docs/gcode.md
"Agreement with LinuxCNC"). Development only: needs rs274 (Debian package linuxcnc-uspace)
and a built novanc; the test suite never runs this.

For each program: rs274 -g prints canonical calls in program coordinates; this script adds the
work offset, the tool length offset and the units to get machine millimetres, drops moves shorter
than half a pulse (0.0005 mm), and compares every move's kind and end point and every arc's centre and direction with
the blocks `novanc translate` prints, in the same order, to 0.001 mm. Where rs274 refuses a
program, novanc must refuse it.

usage: compare_rs274.py [--novanc BIN] [--golden DIR] PROG.ngc...
  --golden DIR   also write DIR/NAME.ngc and DIR/NAME.expect (the rs274 moves in machine mm,
                 or 'ERROR message') for tests/gcode_golden.rs
Exit 0 if every program agrees.
"""
import os
import re
import subprocess
import sys
import tempfile

ROOT = os.path.dirname(os.path.dirname(os.path.abspath(__file__)))
TOL = 0.001 + 1e-6


def tool_table():
    """The sample magazine as an rs274 tool table (rs274 reads it in inches)."""
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


def rs274_moves(prog, tbl):
    """(moves, error): moves as tuples ('R'|'F', x, y, z) or ('A', ccw, plane, x, y, z, cx, cy, cz)."""
    p = subprocess.run(["rs274", "-t", tbl, "-g", prog], capture_output=True, text=True, timeout=600)
    factor = 1.0
    g5x = [0.0, 0.0, 0.0]
    tlo = 0.0
    moves = []
    last = [0.0, 0.0, 0.0]
    for line in (p.stdout + p.stderr).splitlines():
        m = re.match(r"\s*\d+ N\S* +(\w+)\((.*)\)\s*$", line)
        if not m:
            if line.strip() in ("executing", ""):
                continue
            return moves, line.strip()
        name, args = m.group(1), m.group(2)
        vals = [float(v) for v in re.findall(r"-?\d+\.\d+|-?\d+", args)] if name not in ("COMMENT", "MESSAGE") else []
        if name == "USE_LENGTH_UNITS":
            factor = 25.4 if "INCHES" in args else 1.0
        elif name == "SET_G5X_OFFSET":
            g5x = [v * factor for v in vals[1:4]]
        elif name == "SET_G92_OFFSET":
            if any(abs(v) > 0 for v in vals[:3]):
                return moves, "G92 offsets in use"
        elif name == "USE_TOOL_LENGTH_OFFSET":
            # Printed in the program's units.
            tlo = vals[2] * factor
        elif name in ("STRAIGHT_TRAVERSE", "STRAIGHT_FEED"):
            e = [vals[0] * factor + g5x[0], vals[1] * factor + g5x[1], vals[2] * factor + g5x[2] + tlo]
            # Shorter than half a pulse (rs274's inch rounding): novanc cannot move it.
            if max(abs(e[i] - last[i]) for i in range(3)) >= 0.0005:
                moves.append(("R" if name == "STRAIGHT_TRAVERSE" else "F", *e))
                inch.append(factor != 1.0)
            last = e
        elif name == "ARC_FEED":
            fe, se, fa, sa, rot, ae = vals[:6]
            plane = current_plane[0]
            if plane == "XY":
                e, c = [fe, se, ae], [fa, sa, None]
            elif plane == "XZ":
                e, c = [se, ae, fe], [sa, None, fa]
            else:
                e, c = [ae, fe, se], [None, fa, sa]
            off = [g5x[0], g5x[1], g5x[2] + tlo]
            e = [e[i] * factor + off[i] for i in range(3)]
            c = [None if c[i] is None else c[i] * factor + off[i] for i in range(3)]
            normal = {"XY": 2, "XZ": 1, "YZ": 0}[plane]
            c[normal] = last[normal]
            if abs(rot) != 1:
                return moves, "multi-turn arc (P) is not in the subset"
            moves.append(("A", int(rot > 0), plane, *e, *c))
            inch.append(factor != 1.0)
            last = e
        elif name == "SELECT_PLANE":
            current_plane[0] = {"CANON_PLANE_XY": "XY", "CANON_PLANE_XZ": "XZ", "CANON_PLANE_YZ": "YZ"}[args.strip()]
    return moves, None


current_plane = ["XY"]
# Per rs274 move: whether it was printed in inches (4 decimals = 0.00127 mm).
inch = []


def novanc_moves(prog, novanc):
    p = subprocess.run([novanc, "translate", prog], capture_output=True, text=True, timeout=600)
    if p.returncode != 0:
        return [], p.stderr.strip() or "refused"
    moves = []
    pos = [0.0, 0.0, 0.0]
    g = None
    plane = "XY"
    for line in p.stdout.splitlines():
        words = dict()
        gs = []
        for w in line.split():
            if w[0] == "G":
                gs.append(int(w[1:]))
            else:
                words[w[0]] = float(w[1:]) if w[1:] else 0.0
        for x in gs:
            if x in (17, 18, 19):
                plane = {17: "XY", 18: "XZ", 19: "YZ"}[x]
            elif x in (0, 1, 2, 3):
                g = x
            elif x == 4:
                pass
        if 4 in gs or not any(k in words for k in "XYZ"):
            continue
        start = list(pos)
        for i, a in enumerate("XYZ"):
            if a in words:
                pos[i] = words[a]
        if g in (0, 1):
            moves.append(("R" if g == 0 else "F", *pos))
        else:
            c = [start[0] + words.get("I", 0.0), start[1] + words.get("J", 0.0), start[2] + words.get("K", 0.0)]
            normal = {"XY": 2, "XZ": 1, "YZ": 0}[plane]
            c[normal] = start[normal]
            moves.append(("A", int(g == 3), plane, *pos, *c))
    return moves, None


def fmt(m):
    if m[0] == "A":
        return "A%d %s %.4f %.4f %.4f %.4f %.4f %.4f" % m[1:]
    return "%s %.4f %.4f %.4f" % m


def compare(a, b):
    """None if the move lists agree, else a description of the first difference."""
    for i, (x, y) in enumerate(zip(a, b)):
        if x[0] != y[0] or (x[0] == "A" and (x[1] != y[1] or x[2] != y[2])):
            return f"move {i + 1}: rs274 {fmt(x)}, novanc {fmt(y)}"
        nums_x = [v for v in x if isinstance(v, float)]
        nums_y = [v for v in y if isinstance(v, float)]
        tol = TOL + 0.0006 if x[0] == "A" else TOL
        if i < len(inch) and inch[i]:
            tol += 0.00127
        if any(abs(p - q) > tol for p, q in zip(nums_x, nums_y)):
            return f"move {i + 1}: rs274 {fmt(x)}, novanc {fmt(y)}"
    if len(a) != len(b):
        return f"rs274 has {len(a)} moves, novanc {len(b)}"
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
        else:
            progs.append(a)
    with tempfile.NamedTemporaryFile("w", suffix=".tbl", delete=False) as f:
        f.write(tool_table())
        tbl = f.name
    bad = 0
    total_moves = 0
    refused = 0
    for prog in progs:
        current_plane[0] = "XY"
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
            if d:
                bad += 1
                print(f"FAIL {name}: {d}")
            else:
                total_moves += len(ref)
                print(f"ok   {name}: {len(ref)} moves agree")
        if golden and not (got_err and not ref_err) and not (ref_err is None and compare(ref, got)):
            base = os.path.join(golden, os.path.splitext(name)[0])
            with open(prog) as src, open(base + ".ngc", "w") as dst:
                dst.write(src.read())
            with open(base + ".expect", "w") as out:
                if ref_err:
                    out.write("ERROR " + ref_err + "\n")
                else:
                    out.write("# rs274 moves in machine mm: kind, end X Y Z (arcs: A0 cw / A1 ccw, plane,\n")
                    out.write("# end, centre), then the tolerance in mm (wider where rs274 printed inches)\n")
                    for i, m in enumerate(ref):
                        tol = TOL + (0.0006 if m[0] == "A" else 0.0) + (0.00127 if inch[i] else 0.0)
                        out.write(f"{fmt(m)} {tol:.5f}\n")
    os.unlink(tbl)
    print(f"{len(progs)} programs: {len(progs) - bad} agree ({refused} refused by both), {bad} differ; {total_moves} moves compared")
    return 1 if bad else 0


if __name__ == "__main__":
    sys.exit(main(sys.argv[1:]))
