#!/usr/bin/env python3
"""Check the Foxglove topics of a novanc recording against Foxglove's published schemas.

usage: foxglove_check.py FILE --package DIR

DIR is where `npm install --prefix DIR @foxglove/schemas@VERSION` put the package (.ci/run does
it); its JSON Schemas (`@foxglove/schemas/jsonschema`) are read with node. Checks:
  * every channel whose schema is named `foxglove.*` has schema encoding `jsonschema`, message
    encoding `json`, and as schema data exactly the package's schema of that name;
  * every message on those channels validates against the package's schema (Python's
    `jsonschema`), and its timestamps (the message's, each entity's and deletion's) are its
    log time in Foxglove's {sec, nsec};
  * the scene's line points, strip after strip, are /nc/position points (metres = mm / 1000) in
    their order, from the first move to the last position, every position left out lies within
    a pulse of the segment drawn past it, and the last strip of each block ends where
    /nc/position says the block ended;
  * every /foxglove/tool transform is the /nc/position of its log time, and every position at
    rest (speed 0) has one.

Prints one line `foxglove SCHEMA N` per schema (messages validated) and `path points N`, then
`OK`. Exit status 0 if every check passes, 1 with a message on stderr otherwise, 2 if a module
or the package is missing.
"""

import json
import os
import subprocess
import sys

try:
    import jsonschema
    from mcap.reader import make_reader
except ImportError as e:  # pragma: no cover - environment problem
    print(f"foxglove_check: a Python module is missing ({e}); pip install mcap jsonschema", file=sys.stderr)
    sys.exit(2)


def package_schemas(prefix):
    js = (
        "const s = require(process.argv[1] + '/node_modules/@foxglove/schemas/jsonschema');"
        "process.stdout.write(JSON.stringify(s));"
    )
    try:
        out = subprocess.run(["node", "-e", js, os.path.abspath(prefix)], check=True, capture_output=True, text=True)
    except (OSError, subprocess.CalledProcessError) as e:
        print(f"foxglove_check: cannot read @foxglove/schemas in {prefix}: {e}", file=sys.stderr)
        sys.exit(2)
    return {"foxglove." + k: v for k, v in json.loads(out.stdout).items()}


def fail(msg):
    print(f"foxglove_check: {msg}", file=sys.stderr)
    sys.exit(1)


def stamp(t):
    return t["sec"] * 1_000_000_000 + t["nsec"]


def main():
    args = sys.argv[1:]
    if len(args) != 3 or args[1] != "--package":
        print(__doc__, file=sys.stderr)
        sys.exit(1)
    path, prefix = args[0], args[2]
    published = package_schemas(prefix)
    with open(path, "rb") as f:
        reader = make_reader(f, validate_crcs=True)
        summary = reader.get_summary()
        validators = {}
        for ch in summary.channels.values():
            schema = summary.schemas[ch.schema_id]
            if not schema.name.startswith("foxglove."):
                continue
            if schema.encoding != "jsonschema" or ch.message_encoding != "json":
                fail(f"{ch.topic}: encodings {schema.encoding!r}/{ch.message_encoding!r}")
            if schema.name not in published:
                fail(f"{ch.topic}: {schema.name} is not a published Foxglove schema")
            if json.loads(schema.data) != published[schema.name]:
                fail(f"{ch.topic}: the schema data of {schema.name} is not the package's")
            cls = jsonschema.validators.validator_for(published[schema.name])
            cls.check_schema(published[schema.name])
            validators[ch.topic] = (schema.name, cls(published[schema.name], format_checker=cls.FORMAT_CHECKER))
        counts = {}
        # The pulse (the tolerance of the path check): novanc.settings, 0.001 mm in a file
        # without it.
        settings = [m.metadata for m in reader.iter_metadata() if m.name == "novanc.settings"]
        pulse_mm = float(settings[0].get("pulse_mm", "0.001")) if settings else 0.001
        # Per channel (None: a single machine; N: a kernel's channel N, its messages carrying
        # "channel": N).
        positions = {}  # (log time, (x, y, z) mm, speed)
        block_starts = {}  # (log time, seq)
        strips = {}  # (log time, entity id, [(x, y, z) m])
        tools = {}  # (log time, (x, y, z) m)
        placed = {}  # channel frame -> its translation in `machine`
        for _, ch, m in reader.iter_messages(log_time_order=False):
            obj = json.loads(m.data)
            if ch.topic in validators:
                name, v = validators[ch.topic]
                errors = sorted(v.iter_errors(obj), key=lambda e: list(e.path))
                if errors:
                    fail(f"{ch.topic} message at {m.log_time}: {errors[0].message} at {list(errors[0].path)}")
                counts[name] = counts.get(name, 0) + 1
                times = []
                if "timestamp" in obj:
                    times.append(obj["timestamp"])
                for e in obj.get("entities", []) + obj.get("deletions", []):
                    times.append(e["timestamp"])
                for t in times:
                    if stamp(t) != m.log_time:
                        fail(f"{ch.topic}: timestamp {t} is not the log time {m.log_time}")
            c = obj.get("channel") if isinstance(obj, dict) else None
            if ch.topic == "/nc/position":
                positions.setdefault(c, []).append((m.log_time, (obj["x"], obj["y"], obj["z"]), obj.get("speed", 0)))
            elif ch.topic == "/nc/block":
                block_starts.setdefault(c, []).append((m.log_time, obj["seq"]))
            elif ch.topic == "/foxglove/scene":
                prefix = "" if c is None else f"channel{c}/"
                frame = "machine" if c is None else f"channel{c}"
                for e in obj["entities"]:
                    if not e["id"].startswith(prefix):
                        fail(f"scene entity {e['id']} of channel {c} is not named {prefix}...")
                    for line in e["lines"]:
                        if e["frame_id"] != frame:
                            fail(f"scene entity {e['id']} of channel {c} is in frame {e['frame_id']}, not {frame}")
                        strips.setdefault(c, []).append((m.log_time, e["id"], [(p["x"], p["y"], p["z"]) for p in line["points"]]))
            elif ch.topic == "/foxglove/tool":
                tr = obj["translation"]
                xyz = (tr["x"], tr["y"], tr["z"])
                if c is not None and obj["child_frame_id"] == f"channel{c}":
                    # A channel's frame placed in `machine`, once.
                    if obj["parent_frame_id"] != "machine" or obj["child_frame_id"] in placed:
                        fail(f"channel frame {obj['child_frame_id']} placed twice or not in machine")
                    placed[obj["child_frame_id"]] = xyz
                    continue
                want = ("machine", "tool") if c is None else (f"channel{c}", f"channel{c}/tool")
                if (obj["parent_frame_id"], obj["child_frame_id"]) != want:
                    fail(f"tool transform {obj['parent_frame_id']} -> {obj['child_frame_id']} of channel {c}, not {want}")
                tools.setdefault(c, []).append((m.log_time, xyz))

    for c in sorted(set(positions) | set(strips) | set(tools), key=lambda c: -1 if c is None else c):
        if c is not None and f"channel{c}" not in placed and (strips.get(c) or tools.get(c)):
            fail(f"channel {c} is drawn but its frame channel{c} is never placed")
        check_path(c, positions.get(c, []), block_starts.get(c, []), strips.get(c, []), tools.get(c, []), pulse_mm)
    if len(set(placed.values())) != len(placed):
        fail(f"two channels placed at the same spot: {placed}")
    for name in sorted(counts):
        print(f"foxglove {name} {counts[name]}")
    print(f"channels drawn {len(placed)}")
    print("OK")


def mm(p):
    return tuple(round(c * 1000, 6) for c in p)


def check_path(c, positions, block_starts, strips, tools, pulse_mm):
    """One channel's scene against its /nc/position and /nc/block (c None: a single machine)."""
    name = "" if c is None else f"channel {c}: "

    def fail_on(msg):
        fail(name + msg)

    # The path: consecutive distinct positions; the strips joined (each starts where the one
    # before ended) pick points of it in order, and pass within a pulse of every other.
    path_mm = []
    for _, p, _ in positions:
        if not path_mm or path_mm[-1] != p:
            path_mm.append(p)
    drawn = []
    for i, (_, ident, pts) in enumerate(strips):
        pts = [mm(p) for p in pts]
        if len(pts) < 2:
            fail_on(f"strip {ident} has {len(pts)} points")
        if drawn and pts[0] != drawn[-1]:
            fail_on(f"strip {ident} starts at {pts[0]}, not where the one before ended ({drawn[-1]})")
        drawn.extend(pts[1:] if drawn else pts)
    tol = pulse_mm * 1.0 + 1e-9

    def off(a, b, q):
        ab = [b[i] - a[i] for i in range(3)]
        aq = [q[i] - a[i] for i in range(3)]
        l2 = sum(c * c for c in ab)
        t = 0.0 if l2 == 0 else max(0.0, min(1.0, sum(aq[i] * ab[i] for i in range(3)) / l2))
        return sum((aq[i] - t * ab[i]) ** 2 for i in range(3)) ** 0.5

    if drawn:
        try:
            k = path_mm.index(drawn[0])
        except ValueError:
            fail_on(f"the scene starts at {drawn[0]}, not a /nc/position point")
        for a, b in zip(drawn, drawn[1:]):
            j = k + 1
            while j < len(path_mm) and path_mm[j] != b:
                if off(a, b, path_mm[j]) > tol:
                    fail_on(f"/nc/position {path_mm[j]} is {off(a, b, path_mm[j]):.6f} mm from the scene's segment {a} -> {b}")
                j += 1
            if j == len(path_mm):
                fail_on(f"scene point {b} is not the next /nc/position point after {a}")
            k = j
        if k != len(path_mm) - 1:
            fail_on(f"the scene ends at {drawn[-1]}, /nc/position at {path_mm[-1]}")
    # Block ends: the last position before each block starts is the end of the last strip
    # written for the block before (strip ids N<seq> and N<seq>.<k>).
    last_of = {}
    for _, ident, pts in strips:
        last_of[ident.split(".")[0]] = mm(pts[-1])
    ends = 0
    for (t, seq), (_, prev_seq) in zip(block_starts[1:], block_starts[:-1]):
        before = [p for (tp, p, _) in positions if tp <= t]
        key = ("" if c is None else f"channel{c}/") + f"N{prev_seq}"
        if before and key in last_of:
            if last_of[key] != before[-1]:
                fail_on(f"block N{prev_seq} ends at {before[-1]} on /nc/position, its strip at {last_of[key]}")
            ends += 1
    at = {}
    for tp, p, _ in positions:
        at.setdefault(tp, []).append(p)
    moved = {tt for tt, _ in tools}
    for tt, tp in tools:
        if mm(tp) not in at.get(tt, []):
            fail_on(f"tool transform at {tt} {mm(tp)} is not a /nc/position of that time {at.get(tt)}")
    for tp, p, speed in positions:
        if speed == 0 and tp not in moved:
            fail_on(f"/nc/position at rest at {tp} {p} has no tool transform")
    print(f"{name}path points {len(drawn)} of {len(path_mm)}")
    print(f"{name}tool transforms {len(tools)} for {len(positions)} positions")
    print(f"{name}block ends {ends}")


if __name__ == "__main__":
    main()
