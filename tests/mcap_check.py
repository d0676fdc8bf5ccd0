#!/usr/bin/env python3
"""Check a novanc MCAP recording (docs/recording.md) with Python's `mcap` reader.

usage: mcap_check.py FILE [--expect-topics TOPIC ...] [--expect-complete] [--unfinished]

Checks:
  * the whole file streams with CRC validation (data section CRC and every chunk CRC), and the
    indexed reader (summary, chunk indexes) reads every message with chunk CRC validation;
  * every channel's schema encoding is `jsonschema` and its message encoding is `json`, and every
    channel's topic is one of docs/recording.md's;
  * every message parses as a JSON object with its topic's required fields, of the right types;
  * log times never decrease within a topic (within each channel's messages of a topic, in a
    recording of several channels, whose messages carry `channel`: docs/recording.md "Lathe
    recordings");
  * both readers see the same messages, and the summary statistics agree with them;
  * with --expect-topics, each named topic has at least one message;
  * with --expect-complete, the closing `novanc.recording` metadata says complete;
  * with --unfinished, the file may lack its summary section (a process that ended while it was
    recording: docs/recording.md "Interrupted runs"): it must still end with a footer, both
    readers must read it (`make_reader` then streams it), and its `novanc.recording` metadata
    must say complete false.

Prints the message count of each topic and the pulse count per axis (and, in a recording of
several channels, each channel's pulses per axis with their directions summed: its counters'
travel). Exit status 0 if every
check passes, 1 with a message on stderr otherwise, 2 if the `mcap` module is missing.
"""

import json
import sys

try:
    from mcap.reader import make_reader
    from mcap.stream_reader import StreamReader
    from mcap.records import Footer, Message, Metadata
except ImportError as e:  # pragma: no cover - environment problem, not a file problem
    print(f"mcap_check: the Python `mcap` module is missing ({e}); pip install mcap", file=sys.stderr)
    sys.exit(2)

INT = "int"
NUM = "num"
STR = "str"
BOOL = "bool"

# topic -> {field: type}
REQUIRED = {
    "/nc/block": {"seq": INT, "stmt": INT, "text": STR},
    "/nc/position": {"x": NUM, "y": NUM, "z": NUM, "pulses": "pulses3"},
    "/nc/pulses": {"axis": "axis", "dir": "dir", "t_ns": "times"},
    "/nc/state": {
        "run": INT,
        "op_mode": STR,
        "data_mode": STR,
        "feed_override": INT,
        "tool": INT,
        "spindle": INT,
    },
    "/panel/display": {"lines": "strings"},
    "/panel/event": {"event": STR},
    "/nc/probe": {
        "seq": INT,
        "stmt": INT,
        "x": NUM,
        "y": NUM,
        "z": NUM,
        "pulses": "pulses3",
        "tripped": BOOL,
        "at_start": BOOL,
    },
    "/nc/io": {
        "seq": INT,
        "stmt": INT,
        "kind": STR,
        "index": INT,
        "value": NUM,
        "synced": BOOL,
    },
    "/lathe/event": {"channel": INT, "event": STR, "text": STR},
    # Foxglove's schemas (issue 25); tests/foxglove_check.py validates them in full.
    "/foxglove/log": {
        "timestamp": "time",
        "level": INT,
        "message": STR,
        "name": STR,
        "file": STR,
        "line": INT,
    },
    "/foxglove/scene": {"deletions": "list", "entities": "list"},
    "/foxglove/tool": {
        "timestamp": "time",
        "parent_frame_id": STR,
        "child_frame_id": STR,
        "translation": "object",
        "rotation": "object",
    },
}


class CheckError(Exception):
    pass


def is_int(v):
    return isinstance(v, int) and not isinstance(v, bool)


def check_field(topic, name, kind, v, where):
    ok = {
        INT: lambda: is_int(v),
        NUM: lambda: (is_int(v) or isinstance(v, float)),
        STR: lambda: isinstance(v, str),
        BOOL: lambda: isinstance(v, bool),
        # One more counter for each rotary axis A, B, C a machine has (docs/recording.md).
        "pulses3": lambda: isinstance(v, list) and 3 <= len(v) <= 6 and all(is_int(p) for p in v),
        "axis": lambda: v in ("X", "Y", "Z", "A", "B", "C"),
        "dir": lambda: is_int(v) and v in (1, -1),
        "times": lambda: isinstance(v, list) and all(is_int(t) and t >= 0 for t in v),
        "strings": lambda: isinstance(v, list) and all(isinstance(s, str) for s in v),
        "time": lambda: isinstance(v, dict) and is_int(v.get("sec")) and is_int(v.get("nsec")),
        "list": lambda: isinstance(v, list),
        "object": lambda: isinstance(v, dict),
    }[kind]()
    if not ok:
        raise CheckError(f"{where}: {topic} field {name!r} has a bad value {v!r:.80}")


def check_message(topic, msg, where):
    try:
        obj = json.loads(msg.data.decode("utf-8"))
    except (UnicodeDecodeError, json.JSONDecodeError) as e:
        raise CheckError(f"{where}: {topic} message is not JSON: {e}")
    if not isinstance(obj, dict):
        raise CheckError(f"{where}: {topic} message is not a JSON object")
    for name, kind in REQUIRED[topic].items():
        if name not in obj:
            raise CheckError(f"{where}: {topic} message lacks {name!r}")
        check_field(topic, name, kind, obj[name], where)
    return obj


def check_channel(channel, schema):
    if channel.topic not in REQUIRED:
        raise CheckError(f"channel {channel.id} has an unknown topic {channel.topic!r}")
    if channel.message_encoding != "json":
        raise CheckError(f"{channel.topic}: message encoding {channel.message_encoding!r}, not 'json'")
    if schema is None:
        raise CheckError(f"{channel.topic}: no schema")
    if schema.encoding != "jsonschema":
        raise CheckError(f"{channel.topic}: schema encoding {schema.encoding!r}, not 'jsonschema'")
    try:
        doc = json.loads(schema.data.decode("utf-8"))
    except (UnicodeDecodeError, json.JSONDecodeError) as e:
        raise CheckError(f"{channel.topic}: schema is not JSON: {e}")
    missing = set(REQUIRED[channel.topic]) - set(doc.get("required", []))
    if missing:
        raise CheckError(f"{channel.topic}: schema does not require {sorted(missing)}")


def stream_pass(path):
    """Every record in file order, with data-section and chunk CRCs validated."""
    messages = []  # (channel id, log_time, data)
    metadata = {}
    footer = False
    with open(path, "rb") as f:
        for record in StreamReader(f, validate_crcs=True).records:
            if isinstance(record, Message):
                messages.append((record.channel_id, record.log_time, record.data))
            elif isinstance(record, Metadata):
                metadata[record.name] = dict(record.metadata)
            elif isinstance(record, Footer):
                footer = True
    if not footer:
        raise CheckError("no footer: the file ends in the middle of a record")
    return messages, metadata


def check(path, expect_topics, expect_complete, unfinished=False):
    streamed, metadata = stream_pass(path)

    counts = {}
    last_log = {}
    pulses = {"X": 0, "Y": 0, "Z": 0, "A": 0, "B": 0, "C": 0}
    # channel -> axis -> pulses with their directions (the counters' travel)
    travel = {}
    indexed = []
    with open(path, "rb") as f:
        reader = make_reader(f, validate_crcs=True)
        summary = reader.get_summary()
        if summary is None and not unfinished:
            raise CheckError("no summary section (the recording was not finished)")
        if summary is not None:
            for channel in summary.channels.values():
                check_channel(channel, summary.schemas.get(channel.schema_id))
        for n, (schema, channel, msg) in enumerate(reader.iter_messages(log_time_order=False)):
            where = f"message {n} (seq {msg.sequence}, log time {msg.log_time})"
            check_channel(channel, schema)
            obj = check_message(channel.topic, msg, where)
            topic = channel.topic
            ch = obj.get("channel")
            if ch is not None and not is_int(ch):
                raise CheckError(f"{where}: {topic} field 'channel' has a bad value {ch!r:.80}")
            # Pulse batches of different axes may be written slightly out of time order
            # (MCAP allows it); every other topic is written in time order, per channel.
            key = (topic, ch)
            if topic != "/nc/pulses" and msg.log_time < last_log.get(key, 0):
                raise CheckError(f"{where}: {topic} log time goes back from {last_log[key]}")
            last_log[key] = msg.log_time
            counts[topic] = counts.get(topic, 0) + 1
            if topic == "/nc/pulses":
                pulses[obj["axis"]] += len(obj["t_ns"])
                if ch is not None:
                    axes = travel.setdefault(ch, {})
                    axes[obj["axis"]] = axes.get(obj["axis"], 0) + obj["dir"] * len(obj["t_ns"])
                if obj["t_ns"] != sorted(obj["t_ns"]):
                    raise CheckError(f"{where}: pulse times not ascending")
                if obj["t_ns"] and msg.log_time != obj["t_ns"][0]:
                    raise CheckError(f"{where}: log time is not the first pulse's time")
            indexed.append((msg.channel_id, msg.log_time, msg.data))

    if sorted(indexed) != sorted(streamed):
        raise CheckError(
            f"the indexed reader saw {len(indexed)} messages, the streaming reader {len(streamed)}"
        )
    stats = summary.statistics if summary is not None else None
    if stats is not None:
        if stats.message_count != len(indexed):
            raise CheckError(f"statistics say {stats.message_count} messages, found {len(indexed)}")
        for cid, n in stats.channel_message_counts.items():
            topic = summary.channels[cid].topic
            if counts.get(topic, 0) != n:
                raise CheckError(f"statistics say {n} messages on {topic}, found {counts.get(topic, 0)}")
    for topic in expect_topics:
        if counts.get(topic, 0) == 0:
            raise CheckError(f"no message on {topic}")
    recording = metadata.get("novanc.recording")
    if expect_complete and (recording is None or recording.get("complete") != "true"):
        raise CheckError(f"the recording is not marked complete: {recording}")
    if summary is None and (recording is None or recording.get("complete") != "false"):
        raise CheckError(f"an unfinished recording not marked incomplete: {recording}")

    for topic in REQUIRED:
        print(f"{topic:16} {counts.get(topic, 0):10} messages")
    a = "".join(f"  {r} {pulses[r]}" for r in "ABC" if pulses[r])
    print(f"pulses           X {pulses['X']}  Y {pulses['Y']}  Z {pulses['Z']}{a}")
    for ch in sorted(travel):
        t = "  ".join(f"{ax} {travel[ch][ax]:+d}" for ax in sorted(travel[ch]))
        print(f"channel {ch} travel {t}")
    if recording is not None:
        print(f"novanc.recording {recording}")
    finished = "" if summary is not None else " (unfinished: no summary section)"
    print(f"OK {path}: {len(indexed)} messages, CRCs valid{finished}")


def main(argv):
    args = argv[1:]
    if not args or args[0].startswith("-"):
        print(__doc__.strip().splitlines()[2], file=sys.stderr)
        return 1
    path = args[0]
    expect_topics = []
    expect_complete = False
    unfinished = False
    mode = None
    for a in args[1:]:
        if a == "--expect-topics":
            mode = "topics"
        elif a == "--expect-complete":
            expect_complete = True
            mode = None
        elif a == "--unfinished":
            unfinished = True
            mode = None
        elif mode == "topics" and not a.startswith("--"):
            expect_topics.append(a)
        else:
            print(f"mcap_check: unknown argument {a!r}", file=sys.stderr)
            return 1
    try:
        check(path, expect_topics, expect_complete, unfinished)
    except CheckError as e:
        print(f"mcap_check: {path}: {e}", file=sys.stderr)
        return 1
    except Exception as e:  # a reader error: bad CRC, truncated file, bad record
        print(f"mcap_check: {path}: {type(e).__name__}: {e}", file=sys.stderr)
        return 1
    return 0


if __name__ == "__main__":
    sys.exit(main(sys.argv))
