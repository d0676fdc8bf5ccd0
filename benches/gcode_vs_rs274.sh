#!/usr/bin/env bash
# The whole `novanc translate PROG.ngc` process against LinuxCNC 2.9's `rs274 -g` on the same
# programs (docs/gcode.md "Speed"), side by side: best of 3 runs each, output to /dev/null,
# and the ratio (target: novanc at least 10x faster). First a large generated program of
# lines, arcs and cycles; then, one by one and in total, the real programs named on the
# command line (CAM output: they are not in the repository, whose license is not theirs;
# docs/gcode.md "Speed" says where those measured come from).
#
# Run from the repository: bash benches/gcode_vs_rs274.sh [PROGRAM.ngc ...]
# Needs rs274 (Debian package linuxcnc-uspace); without it, it says so and exits 0.
set -euo pipefail
cd "$(dirname "$0")/.."
if ! command -v rs274 >/dev/null 2>&1; then
    echo "gcode_vs_rs274: rs274 is not installed (apt-get install linuxcnc-uspace); skipped"
    exit 0
fi
target="${CARGO_TARGET_DIR:-target}"
cargo build --release --quiet --bin novanc
work="$(mktemp -d)"
trap 'rm -rf "$work"' EXIT
cp "$target/release/novanc" "$work/novanc"
cargo bench --quiet --bench gcode -- --write "$work/big.ngc" >/dev/null
python3 -c "
import sys; sys.path.insert(0, 'tools'); import compare_rs274 as c
open('$work/tools.tbl', 'w').write(c.tool_table())"
lines=$(wc -l < "$work/big.ngc")
bytes=$(wc -c < "$work/big.ngc")
# Best of 3 runs of each, wall clock and CPU time (user + system of the process: the machine
# may be shared with other work, which stretches wall clock but not CPU time).
python3 - "$work" "$lines" "$bytes" "$@" <<'PY'
import os, resource, statistics, subprocess, sys, time
work, lines, size = sys.argv[1], int(sys.argv[2]), int(sys.argv[3])
real = [os.path.abspath(p) for p in sys.argv[4:]]
env = dict(os.environ, HOME=work)
def run(cmd):
    best_wall, best_cpu = 1e9, 1e9
    for _ in range(3):
        r0 = resource.getrusage(resource.RUSAGE_CHILDREN)
        t0 = time.perf_counter()
        with open(os.devnull, "w") as null:
            subprocess.run(cmd, stdout=null, stderr=null, check=False, env=env, cwd=work)
        wall = time.perf_counter() - t0
        r1 = resource.getrusage(resource.RUSAGE_CHILDREN)
        cpu = (r1.ru_utime - r0.ru_utime) + (r1.ru_stime - r0.ru_stime)
        best_wall, best_cpu = min(best_wall, wall), min(best_cpu, cpu)
    return best_wall, best_cpu
nw, nc = run([f"{work}/novanc", "translate", f"{work}/big.ngc"])
rw, rc = run(["rs274", "-t", f"{work}/tools.tbl", "-g", f"{work}/big.ngc"])
print(f"program: {lines} lines, {size / 1e6:.1f} MB, load average {os.getloadavg()[0]:.1f}")
print(f"novanc translate: {nw * 1e3:.0f} ms wall, {nc * 1e3:.0f} ms CPU ({lines / nw / 1e6:.2f} M program lines/s wall)")
print(f"rs274 -g:         {rw * 1e3:.0f} ms wall, {rc * 1e3:.0f} ms CPU ({lines / rw / 1e6:.2f} M program lines/s wall)")
print(f"ratio: novanc is {rw / nw:.1f}x faster by wall clock, {rc / nc:.1f}x by CPU time (target >= 10x)")
if real:
    print(f"real programs ({len(real)}), CPU time, best of 3:")
    tn = tr = 0.0
    ratios = []
    for p in real:
        _, n = run([f"{work}/novanc", "translate", p])
        _, r = run(["rs274", "-t", f"{work}/tools.tbl", "-g", p])
        tn, tr = tn + n, tr + r
        ratios.append(r / n)
        print(f"  {os.path.basename(p)[:48]:48} {os.path.getsize(p) / 1e3:7.0f} kB  novanc {n * 1e3:7.1f} ms  rs274 {r * 1e3:7.1f} ms  {r / n:5.1f}x")
    print(f"real programs: novanc {tn:.2f} s, rs274 {tr:.2f} s CPU: {tr / tn:.1f}x in total; per program median {statistics.median(ratios):.1f}x, {min(ratios):.1f}x to {max(ratios):.1f}x (target >= 10x)")
PY
