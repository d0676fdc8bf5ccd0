#!/usr/bin/env python3
"""Draws an ASCII timing chart of a lathe recording (docs/lathe.md "Timing chart"):
one row per channel, one character per STEP seconds of machine time:
  '=' running (machining or moving)   '.' waiting at a queue point
  'S' the bar feeder supplies a work  'T' a transfer the channel delivers   'U' to the unloader
  'F' faulted   ' ' idle or done
usage: tools/lathe_chart.py REC.mcap [END_S] [STEP_S]"""
import json, sys
from mcap.reader import make_reader

path = sys.argv[1]
end = float(sys.argv[2]) if len(sys.argv) > 2 else 40.0
step = float(sys.argv[3]) if len(sys.argv) > 3 else 0.5
n = int(end / step)
states = {}   # channel -> list of (t, state)
marks = {}    # channel -> {col: char}
with open(path, 'rb') as f:
    for _, ch, m in make_reader(f).iter_messages():
        t = m.log_time / 1e9
        if t > end:
            break
        d = json.loads(m.data)
        c = d.get('channel')
        if ch.topic == '/nc/state':
            states.setdefault(c, []).append((t, d['data_mode']))
        elif ch.topic == '/lathe/event' and d['event'] in ('supply', 'transfer'):
            mark = 'S' if d['event'] == 'supply' else ('U' if d.get('value') == 0 else 'T')
            row = marks.setdefault(c, {})
            col = min(int(t / step), n - 1)
            if mark != 'S' or col not in row:
                row[col] = mark
sym = {'RUN': '=', 'WAIT': '.', 'FAULT': 'F', 'ALARM': 'A', 'HOLD': 'h', 'STOP': 's'}
head = ''.join(('|' if (i * step) % 5 == 0 else ' ') for i in range(n))
print('time s  ' + ''.join(f'{int(i * step):<10d}' if (i * step) % 5 == 0 and i % 10 == 0 else '' for i in range(n)))
print('        ' + head)
for c in sorted(states):
    row = []
    for i in range(n):
        t = (i + 0.5) * step
        s = ' '
        for (ts, st) in states[c]:
            if ts <= t:
                s = sym.get(st, ' ')
        row.append(s)
    for col, mk in marks.get(c, {}).items():
        row[col] = mk
    print(f'CH{c}     ' + ''.join(row))
