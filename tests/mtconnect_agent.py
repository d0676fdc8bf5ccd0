#!/usr/bin/env python3
"""A stand-in MTConnect agent for novanc's SHDR adapter (docs/mtconnect.md).

usage: mtconnect_agent.py PORT DEVICES_XML RECORDING.mcap
       mtconnect_agent.py --citizen PORT DEVICES_XML

An adapter-level test, not agent conformance: it reads the adapter as the reference agent
(cppagent) would, with that agent's SHDR tokenizer rules, and checks what novanc sent against
the shipped device file, the MTConnect 2.0 enumerations and the same run's recording. It is run
by tests/mtconnect.rs on a `novanc script` run of Table B (single block, then AUTO with a feed
hold, to M30, then E-STOP and RESET, then T02's length revised on OFS). Loopback only; every wait is bounded.

Checks:
  * two agents connect (they may be slow to be accepted: retried for 30 s); the first sends
    `* PING` and must get `* PONG <ms>`;
  * both get every line until novanc closes (60 s at most), the same data lines after their
    dumps (a change is sent to every agent);
  * the first lines (the dump) carry every DataItem of the device file;
  * every key is a DataItem id of the device file; every value is of its DataItem's kind: an
    enumerated event one of the MTConnect 2.0 values, a sample a number, a count an integer, a
    condition five fields with an MTConnect level, a message two fields, a table `K={k=v ...}`
    entries; UNAVAILABLE is allowed for every item;
  * timestamps are UTC ISO 8601 with milliseconds and never go backwards;
  * Execution goes READY -> ACTIVE -> INTERRUPTED (between single blocks) ... FEED_HOLD while
    held, ACTIVE again, PROGRAM_COMPLETED at M30, STOPPED at E-STOP;
  * every block's line reaches the agent, in order: the `line` values are the recording's
    `/nc/block` statement lines, none merged away (most of them live only inside one `wait`);
    so `line` goes backwards only where the program loops;
  * `partcount` rises by one, when Execution becomes PROGRAM_COMPLETED;
  * E-STOP raises a FAULT on `system`, RESET makes it NORMAL;
  * the last Xmach/Ymach/Zmach equal the last `/nc/position` of the recording, and
    Xact/Yact/Zact are that position in G54 (zero on a fresh state) less the length of the tool
    in the spindle;
  * T02's length revised on OFS after the run is sent in a new `tooloffsets` table.

With --citizen it reads `novanc script --machine citizen` (START, 3 s of machine time,
E-STOP, RESET) against the Citizen's device file (docs/mtconnect/Devices-citizen.xml): the
same connection, dump, key, value and timestamp checks, then:
  * the three channels are three paths: `p1_`, `p2_`, `p3_` items in the dump, each path
    READY, then ACTIVE after START;
  * a channel waiting at a sync point is WAIT: `p2_exec` WAIT while `p1_exec` is ACTIVE;
  * `estop` ARMED, TRIGGERED at E-STOP (every path STOPPED), ARMED after RESET (every path
    READY: the cycle is abandoned); `system` FAULT then NORMAL;
  * each path's `partcount` an integer that never falls; its work and machine positions equal
    (a lathe channel has no work offsets).

Exit status 0 if every check passes, 1 with the failures on stderr, 2 if `mcap` is missing
(Table B only).
"""

import re
import socket
import sys
import threading
import time
import xml.etree.ElementTree as ET

import json

# The MTConnect 2.0 controlled vocabularies of the enumerated events novanc sends, as
# MTConnectStreams_2.0.xsd (the reference agent's schemas/) lists them: ExecutionValueType,
# ControllerModeValueType, EmergencyStopValueType, AvailabilityValueType; and the condition
# levels, its Condition elements Normal, Warning, Fault, Unavailable.
ENUMS = {
    "EXECUTION": {"READY", "ACTIVE", "INTERRUPTED", "FEED_HOLD", "STOPPED", "OPTIONAL_STOP",
                  "PROGRAM_STOPPED", "PROGRAM_COMPLETED", "WAIT"},
    "CONTROLLER_MODE": {"AUTOMATIC", "MANUAL", "MANUAL_DATA_INPUT", "SEMI_AUTOMATIC", "EDIT",
                        "FEED_HOLD"},
    "EMERGENCY_STOP": {"ARMED", "TRIGGERED"},
    "AVAILABILITY": {"AVAILABLE", "UNAVAILABLE"},
}
LEVELS = {"NORMAL", "WARNING", "FAULT", "UNAVAILABLE"}
INTEGER_TYPES = {"LINE_NUMBER", "PART_COUNT", "TOOL_NUMBER"}
NUMBER_TYPES = {"PATH_FEEDRATE_OVERRIDE", "ROTARY_VELOCITY_OVERRIDE"}
TS = re.compile(r"^\d{4}-\d\d-\d\dT\d\d:\d\d:\d\d\.\d{3}Z$")
TABLE = re.compile(r"^(\S+=\{(\S+=\S+( \S+=\S+)*)?\}( |$))*$")

failures = []


def fail(msg):
    failures.append(msg)


def tokenize(line):
    """cppagent's ShdrTokenizer: fields split on `|`; a field starting with `"` runs to a `"`
    followed by `|` or the end, a backslash taking the next character as it is."""
    out, i, n = [], 0, len(line)
    while True:
        while i < n and line[i].isspace():
            i += 1
        if i < n and line[i] == '"':
            j, tok, closed = i + 1, [], False
            while j < n:
                c = line[j]
                if c == "\\" and j + 1 < n:
                    tok.append(line[j + 1])
                    j += 2
                    continue
                if c == "|":
                    break
                if c == '"':
                    k = j + 1
                    while k < n and line[k].isspace():
                        k += 1
                    if k == n or line[k] == "|":
                        closed = True
                        j = k
                        break
                tok.append(c)
                j += 1
            if not closed:
                fail(f"an unterminated quoted field: {line!r}")
            out.append("".join(tok))
            i = j
        else:
            j = line.find("|", i)
            j = n if j < 0 else j
            out.append(line[i:j].strip())
            i = j
        if i >= n:
            break
        i += 1  # the `|`
        if i == n:
            out.append("")
            break
    return out


def device_items(path):
    ns = {"m": "urn:mtconnect.org:MTConnectDevices:2.0"}
    root = ET.parse(path).getroot()
    items = {}
    for d in root.iter("{%s}DataItem" % ns["m"]):
        items[d.get("id")] = d.attrib
    return items


def connect(port):
    end = time.time() + 30
    while True:
        try:
            s = socket.create_connection(("127.0.0.1", port), timeout=5)
            s.settimeout(60)
            return s
        except OSError:
            if time.time() > end:
                raise
            time.sleep(0.02)


def read_all(s, out):
    buf = b""
    end = time.time() + 60
    while time.time() < end:
        try:
            chunk = s.recv(65536)
        except OSError:
            break
        if not chunk:
            break
        buf += chunk
    out.extend(buf.decode("utf-8", "replace").splitlines())


def parse(lines, items):
    """(timestamp, key, fields) of every value, in order; checks kinds and timestamps."""
    values, last_ts = [], ""
    for line in lines:
        if line.startswith("*"):
            continue
        f = tokenize(line)
        ts = f[0]
        if not TS.match(ts):
            fail(f"timestamp {ts!r} is not UTC ISO 8601 with milliseconds: {line!r}")
        if ts < last_ts:
            fail(f"timestamp {ts} before {last_ts}: {line!r}")
        last_ts = max(ts, last_ts)
        i = 1
        while i < len(f):
            key = f[i]
            d = items.get(key)
            if d is None:
                fail(f"key {key!r} is not a DataItem id of Devices.xml: {line!r}")
                break
            arity = 5 if d.get("category") == "CONDITION" else 2 if d.get("type") == "MESSAGE" else 1
            fields = f[i + 1:i + 1 + arity]
            if len(fields) != arity:
                fail(f"{key}: {arity} fields expected: {line!r}")
            check_value(key, d, fields, line)
            values.append((ts, key, fields))
            i += 1 + arity
    return values


def check_value(key, d, fields, line):
    v = fields[0] if fields else ""
    if v == "UNAVAILABLE":
        return
    t = d.get("type")
    if d.get("category") == "CONDITION":
        if v not in LEVELS:
            fail(f"{key}: condition level {v!r} is not MTConnect's: {line!r}")
    elif d.get("representation") == "TABLE":
        if not TABLE.match(v):
            fail(f"{key}: not a table {v!r}")
    elif t in ENUMS:
        if v not in ENUMS[t]:
            fail(f"{key}: {v!r} is not a {t} value: {line!r}")
    elif t in INTEGER_TYPES:
        if not re.fullmatch(r"-?\d+", v):
            fail(f"{key}: {v!r} is not an integer")
    elif d.get("category") == "SAMPLE" or t in NUMBER_TYPES:
        try:
            float(v)
        except ValueError:
            fail(f"{key}: {v!r} is not a number")


def series(values, key):
    return [(ts, f[0]) for ts, k, f in values if k == key]


def recording(path):
    try:
        from mcap.reader import make_reader
    except ImportError as e:  # pragma: no cover - environment problem
        print(f"mtconnect_agent: the Python `mcap` module is missing ({e})", file=sys.stderr)
        sys.exit(2)
    stmts, last_pos = [], None
    with open(path, "rb") as fh:
        for _schema, channel, message in make_reader(fh).iter_messages(topics=["/nc/block", "/nc/position"]):
            m = json.loads(message.data)
            if channel.topic == "/nc/block":
                if not stmts or stmts[-1] != m["stmt"]:
                    stmts.append(m["stmt"])
            else:
                last_pos = (m["x"], m["y"], m["z"])
    return stmts, last_pos


def main():
    citizen = sys.argv[1] == "--citizen"
    args = sys.argv[2:] if citizen else sys.argv[1:]
    port, devices = int(args[0]), args[1]
    items = device_items(devices)
    a, b = connect(port), connect(port)
    a.sendall(b"* PING\n")
    la, lb = [], []
    ta = threading.Thread(target=read_all, args=(a, la))
    tb = threading.Thread(target=read_all, args=(b, lb))
    ta.start(), tb.start()
    ta.join(70), tb.join(70)
    if not la or not lb:
        print("mtconnect_agent: nothing read", file=sys.stderr)
        return 1
    if not any(re.fullmatch(r"\* PONG \d+", l) for l in la):
        fail("no `* PONG <ms>` answered the PING")
    va, vb = parse(la, items), parse(lb, items)
    dump_keys = set()
    for ts, k, _ in va:
        if ts != va[0][0]:
            break
        dump_keys.add(k)
    missing = set(items) - dump_keys
    if missing:
        fail(f"the dump lacks {sorted(missing)}")
    # Both agents get every change: the same values after the later one's dump.
    tail = lambda v: [x for x in v if x[0] > max(va[0][0], vb[0][0])]
    if tail(va) != tail(vb):
        fail("the two agents got different changes")
    if citizen:
        return check_citizen(la, va)
    return check_table_b(la, va, args[2])


def check_citizen(la, va):
    """The Citizen's three channels as three paths (see the module's doc)."""
    paths = ("p1_", "p2_", "p3_")
    dump = {k for ts, k, _ in va if ts == va[0][0]}
    for p in paths:
        if p + "exec" not in dump:
            fail(f"path {p} is not in the dump")
        ex = [v for _, v in series(va, p + "exec")]
        if not ex or ex[0] != "READY" or "ACTIVE" not in ex:
            fail(f"{p}exec {ex}: READY, then ACTIVE after START expected")
        if ex and ex[-1] != "READY":
            fail(f"{p}exec ends {ex[-1]}, not READY after RESET")
        pc = [v for _, v in series(va, p + "partcount")]
        if any(not re.fullmatch(r"\d+", v) for v in pc) or pc != sorted(pc, key=int):
            fail(f"{p}partcount {pc}: integers that never fall expected")
        for a in "XZ":
            act, mach = series(va, p + a + "act"), series(va, p + a + "mach")
            if act != mach:
                fail(f"{p}{a}act and {p}{a}mach differ (no work offsets on a lathe channel)")
    # WAIT on CH2 while CH1 runs: the values in the order sent, the latest of each.
    now, waited = {}, False
    for _, k, f in va:
        now[k] = f[0]
        if k == "p2_exec" and f[0] == "WAIT" and now.get("p1_exec") == "ACTIVE":
            waited = True
    if not waited:
        fail("p2_exec was never WAIT while p1_exec was ACTIVE")
    estop = [v for _, v in series(va, "estop")]
    if estop != ["ARMED", "TRIGGERED", "ARMED"]:
        fail(f"estop {estop}, not ARMED, TRIGGERED, ARMED")
    at = [ts for ts, v in series(va, "estop") if v == "TRIGGERED"]
    for p in paths:
        if at and (at[0], "STOPPED") not in series(va, p + "exec"):
            fail(f"{p}exec is not STOPPED at E-STOP ({at[0]})")
    system = [v for _, v in series(va, "system")]
    if system != ["NORMAL", "FAULT", "NORMAL"]:
        fail(f"system condition {system}: NORMAL, FAULT at E-STOP, NORMAL after RESET expected")
    print(f"mtconnect_agent: citizen: {len(la)} lines, {len(va)} values; exec per path "
          + "; ".join(f"{p}{[v for _, v in series(va, p + 'exec')]}" for p in paths))
    for f in failures:
        print(f"mtconnect_agent: {f}", file=sys.stderr)
    return 1 if failures else 0


def check_table_b(la, va, mcap_path):
    """Table B on the mill (see the module's doc)."""
    ex = [v for _, v in series(va, "exec")]
    order = ["READY", "ACTIVE", "INTERRUPTED", "ACTIVE", "FEED_HOLD", "ACTIVE", "PROGRAM_COMPLETED", "STOPPED"]
    i = 0
    for v in ex:
        if i < len(order) and v == order[i]:
            i += 1
    if i < len(order):
        fail(f"Execution {ex} lacks {order[i:]} in the order {order}")
    if ex and ex[0] != "READY":
        fail(f"Execution starts {ex[0]}, not READY")

    stmts, last_pos = recording(mcap_path)
    lines = [int(v) for _, v in series(va, "line") if v != "UNAVAILABLE"]
    if lines != stmts:
        fail(f"`line` sent {lines}, the recording's blocks ran {stmts}")
    loops = sum(1 for x, y in zip(stmts, stmts[1:]) if y < x)
    back = sum(1 for x, y in zip(lines, lines[1:]) if y < x)
    if back > loops:
        fail(f"`line` went backwards {back} times, the program looped {loops} times")

    pc = series(va, "partcount")
    if [v for _, v in pc] != ["0", "1"]:
        fail(f"partcount {pc}, not 0 then 1")
    done = [ts for ts, v in series(va, "exec") if v == "PROGRAM_COMPLETED"]
    if len(pc) == 2 and done and pc[1][0] != done[0]:
        fail(f"partcount rose at {pc[1][0]}, the program completed at {done[0]}")

    system = [v for _, v in series(va, "system")]
    if "FAULT" not in system or system[-1] != "NORMAL":
        fail(f"system condition {system}: FAULT at E-STOP, NORMAL after RESET expected")

    got = tuple(float(series(va, k)[-1][1]) for k in ("Xmach", "Ymach", "Zmach"))
    if last_pos is None or any(abs(g - p) > 0.0005 for g, p in zip(got, last_pos)):
        fail(f"last Xmach/Ymach/Zmach {got}, the recording ends at {last_pos}")

    # OFS revised T02's set length to 155 after the run: the table is sent again with it.
    tables = [v for _, v in series(va, "tooloffsets")]
    t2 = lambda t: re.search(r"T2=\{LENGTH=(\S+) RADIUS=\S+ LENGTH_WEAR=(\S+)", t)
    if len(tables) < 2 or not t2(tables[-1]) or t2(tables[-1]).group(1) != "155.000" \
            or t2(tables[0]).group(1) == "155.000":
        fail(f"tooloffsets {tables}: T2's length revised to 155 expected")
    # The work position: G54 is zero on a fresh state, so X and Y are the machine's, and Z is
    # the machine's less the length of the tool in the spindle (the tool file's, with no run
    # loaded, as POS shows it).
    tool = series(va, "tool")[-1][1]
    m = re.search(r"\bT%s=\{LENGTH=(\S+) RADIUS=\S+ LENGTH_WEAR=(\S+)" % tool, tables[-1]) if tables else None
    work = tuple(float(series(va, k)[-1][1]) for k in ("Xact", "Yact", "Zact"))
    if not m:
        fail(f"the tool in the spindle T{tool} is not in the table {tables[-1:]}")
    else:
        length = float(m.group(1)) + float(m.group(2))
        want = (got[0], got[1], round(got[2] - length, 3))
        if any(abs(w - g) > 0.0005 for w, g in zip(work, want)):
            fail(f"last Xact/Yact/Zact {work}, expected {want} (tool T{tool} length {length})")

    print(f"mtconnect_agent: {len(la)} lines, {len(va)} values, {len(lines)} lines of blocks, "
          f"Execution {len(ex)} changes; ends at machine {got}, work {work}, tool T{tool}")
    for f in failures:
        print(f"mtconnect_agent: {f}", file=sys.stderr)
    return 1 if failures else 0


if __name__ == "__main__":
    sys.exit(main())
